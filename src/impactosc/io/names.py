"""Names a user types: the closest valid name to a misspelt one, so that the workflow config, model files and
command-line overrides answer a typo the same way ("unknown key (did you mean 'kI'?)"), and the
one reading of NAME=VALUE items."""

from __future__ import annotations

import difflib


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
