"""Names a user types: the closest valid name to a misspelt one, so that the workflow config, model files and
command-line overrides answer a typo the same way ("unknown key (did you mean 'kI'?)"), the
one reading of NAME=VALUE items, and the one way a value a user gave is echoed in a message."""

from __future__ import annotations

import difflib
import reprlib

#: Longest echo of a value in a message (characters). Why a limit: a value can be far larger than
#: the text that wrote it (a YAML alias nested in an alias repeats its value, nine aliases of nine
#: aliases six deep are half a million values), and a message echoing it whole is megabytes on
#: one line.
SHOWN_LIMIT = 80

# repr with a few items per level and a few levels: its work is bounded whatever the value's size
_REPR = reprlib.Repr()
_REPR.maxlevel = 4
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = _REPR.maxset = _REPR.maxfrozenset = 6
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = SHOWN_LIMIT


def shown(value, limit: int = SHOWN_LIMIT) -> str:
    """repr(`value`) as a message echoes it: whole when short (``'stiff'``, ``1e-200``), else cut to
    at most `limit` characters ending in ' ...', without building the whole repr of a large value."""
    try:
        text = _REPR.repr(value)
    except Exception:  # an int too long for str(), or an object whose repr fails
        text = f"<{type(value).__name__}>"
    if len(text) <= limit:
        return text
    head = text[: max(limit - 4, 1)]
    comma = head.rfind(", ")  # cut after an item, not inside one
    return (head[: comma + 1] if comma > limit // 2 else head) + " ..."


def closest_name(key: str, names, absent=()) -> str | None:
    """Closest of `names` to `key`, case folded; `absent` ones (names not given) first, as a
    typo usually hides a name that was not given. None when nothing is close."""
    for pool in (list(absent), list(names)):
        folded = {n.lower(): n for n in pool}
        # cutoff 0.5, not difflib's 0.6: a one-letter slip in a two-letter key ('kl' for 'kI') scores 0.5
        match = difflib.get_close_matches(str(key).lower(), list(folded), n=1, cutoff=0.5)
        if match:
            return folded[match[0]]
    return None


def split_assignment(item) -> tuple[str, str | None]:
    """(name, value text) of one ``NAME=VALUE`` item, both stripped; the value is None where the
    item has no ``=`` (a bare NAME, which some options allow and others refuse with their own
    message). The one reading of NAME=VALUE for every option and override that takes it."""
    name, eq, text = (part.strip() for part in str(item).partition("="))
    return name, (text if eq else None)
