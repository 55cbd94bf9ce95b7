"""What the explorer's page shows, read from its fields, and written as a study's config.

Why a module of its own: everything a user types passes through here, and every bad value (text
in a number field, w <= 0, a range the wrong way round, a parameter the model refuses) becomes a
:class:`InputError` with a message the page shows, before anything is scheduled or redrawn. The
same view, written as a config snippet, rebuilds the picture as a figure of the workflow.

A record path typed in the page passes here too (:class:`RecordAccess`): the page reads records
only from the directories and files named when the explorer started, and its messages name the
file and what is wrong with it, never a piece of what it holds.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import shlex
import stat
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from impactosc.dynamics.sweep import SweepSettings
from impactosc.io.files import atomic_write
from impactosc.model.contact_laws import DEFAULT_LAW, LAWS
from impactosc.model.model_file import NAMES
from impactosc.model.parameters import LAW_PARAMETERS, PARAMETERS, ModelParams

__all__ = [
    "InputError",
    "View",
    "parse_number",
    "parse_omega",
    "parse_range",
    "with_parameter",
    "config_snippet",
    "write_config",
    "snakemake_command",
    "RecordAccess",
    "record_error",
]

#: The diagram's quantities: Poincare x (the workflow's Fig 2) or the intervals S_j (Fig 3b).
QUANTITIES = ("x", "isi")
DIRECTIONS = ("increasing", "decreasing")
#: The figure target of each quantity (bifurcation.fig02 / fig03b name the sweep they draw).
TARGETS = {"x": "fig02", "isi": "fig03b"}
#: Parameters with a slider of their own; every other one has a field.
SLIDERS = ("xI", "m0e")
#: Record files the page loads: their suffixes, and the largest (bytes)
RECORD_SUFFIXES = (".csv", ".h5", ".hdf5", ".tdms")
RECORD_MAX_BYTES = 256 * 2**20


class InputError(ValueError):
    """A value typed in the page that the explorer refuses; its message is shown in the page."""


@dataclass(frozen=True)
class View:
    """The picture the page asks for: the diagram's window and grid, its quantity and direction,
    the model, the per-w lengths of the continuation, and the w whose attractor is shown.

    The per-w lengths are the explorer's own (short, for speed); the config snippet writes them
    so that the figure the workflow draws is the picture on the screen."""

    w_lo: float = 20.0
    w_hi: float = 45.0
    n_columns: int = 200
    quantity: str = "x"
    direction: str = "increasing"
    params: ModelParams = field(default_factory=ModelParams)
    n_transient: int = 100
    n_record: int = 50
    n_initial: int = 600
    omega: float = 40.86
    model_file: str | None = None
    file_params: ModelParams | None = None  # the model file's values, the page's defaults

    def omegas(self) -> np.ndarray:
        """The diagram's grid in sweep order (a decreasing sweep starts at w_hi)."""
        w = np.linspace(self.w_lo, self.w_hi, self.n_columns)
        return w if self.direction == "increasing" else w[::-1].copy()

    def settings(self) -> SweepSettings:
        return SweepSettings(
            n_transient=self.n_transient, n_record=self.n_record, n_initial=self.n_initial, params=self.params
        )

    def replace(self, **changes) -> View:
        return dataclasses.replace(self, **changes)


def parse_number(text, name: str, *, positive: bool = False) -> float:
    """A finite number from a field's text, or InputError naming the field."""
    try:
        value = float(str(text).strip())
    except ValueError:
        raise InputError(f"{name}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise InputError(f"{name}: {text!r} is not finite")
    if positive and value <= 0:
        raise InputError(f"{name} must be > 0, got {value:g}")
    return value


def parse_omega(text) -> float:
    """The w of the attractor panel (rad/s, > 0)."""
    return parse_number(text, "w", positive=True)


def parse_range(lo_text, hi_text) -> tuple[float, float]:
    """The diagram's window (rad/s): both > 0 and lo < hi (the sweep direction is its own choice)."""
    lo = parse_number(lo_text, "w from", positive=True)
    hi = parse_number(hi_text, "w to", positive=True)
    if not lo < hi:
        raise InputError(f"the w range must run from low to high, got {lo:g} .. {hi:g}")
    return lo, hi


def parse_columns(text, limit: int = 2000) -> int:
    """The number of diagram columns (2 .. limit)."""
    value = parse_number(text, "columns")
    if value != int(value) or not 2 <= value <= limit:
        raise InputError(f"columns must be a whole number in 2..{limit}, got {text!r}")
    return int(value)


def _replaced(params: ModelParams, **changes) -> ModelParams:
    """The model with `changes`; its own checks (a mass > 0, ...) become InputError. A value
    outside the tested ranges is allowed (the page says so: :func:`parameter_warning`)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return dataclasses.replace(params, **changes)
    except ValueError as exc:
        raise InputError(str(exc)) from None


def shown_parameters(law: str) -> tuple[str, ...]:
    """The fields the page shows for a law (its component's): model BC's family as the law reads
    it (b, n2, n3 only for a law that reads them as given), then the law's own numbers."""
    return LAWS[law].fields


def with_parameter(params: ModelParams, name: str, text) -> ModelParams:
    """The model with one parameter set from a field's text (one the model's law reads)."""
    if name not in {p[0] for p in PARAMETERS} | {p[0] for p in LAW_PARAMETERS}:
        raise InputError(f"unknown model parameter {name!r}")
    if name not in shown_parameters(params.law):
        raise InputError(f"the {params.law} law has no parameter {name}")
    return _replaced(params, **{name: parse_number(text, name)})


def with_law(params: ModelParams, law: str, base: ModelParams | None = None) -> ModelParams:
    """The model with another contact law: a law of its own elastic exponent sets it (Kelvin-Voigt
    is linear, n1 = 1, kI then in N/m); leaving such a law restores the exponent of `base` (the
    model file's, or model BC's)."""
    if law not in LAWS:
        raise InputError(f"unknown contact law {law!r}; choose from {', '.join(LAWS)}")
    new, old = LAWS[law], LAWS[params.law]
    n1 = new.n1 if new.n1 is not None else (base or ModelParams()).n1 if old.n1 is not None else params.n1
    return _replaced(params, law=law, n1=n1)


def parameter_warning(params: ModelParams) -> str:
    """The model's warning when a parameter lies outside the tested ranges, else ''."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ModelParams(**params.to_dict())
    return "; ".join(str(w.message) for w in caught)


def config_snippet(view: View, study: str = "explore") -> str:
    """The view as a config file for the workflow: the model (every parameter that differs from
    the model file's or model BC's), the per-w lengths, the sweep of the window in its direction
    with the view's step, and the figure that draws the diagram's quantity from that sweep.

    Written by yaml.safe_dump, so that what the workflow reads back is what was written: a float
    as a YAML float (1.0e-05, not the string 1e-05 that YAML 1.1 makes of repr), a path quoted
    when it holds a comma, '#', ': ' or a brace."""
    step = (view.w_hi - view.w_lo) / (view.n_columns - 1)
    start, stop = (view.w_lo, view.w_hi) if view.direction == "increasing" else (view.w_hi, view.w_lo)
    head = ["# The explorer's view as a study of its own (impactosc explore)"]
    if view.model_file and view.params == view.file_params:
        model = {"file": str(view.model_file)}
    else:
        # the workflow refuses a model file beside keys that differ from it: every value, written out
        if view.model_file:
            head.append("# every parameter written out: the model file's were changed in the explorer")
        base, law = ModelParams(), LAWS[view.params.law]
        model = {
            k: float(getattr(view.params, k))
            for k in NAMES
            if (view.model_file or getattr(view.params, k) != getattr(base, k)) and k in law.family
        }
        if law.name != DEFAULT_LAW:  # the config names a law as the model files do: model.contact
            model["contact"] = {"law": law.name, **{k: float(getattr(view.params, k)) for k in law.own}}
    # the workflow splits a sweep into chunks seeded by a coarse pass over every stride-th w
    # (impactosc.dynamics.sweep_chunks): a short grid needs a short stride and few chunks
    stride = 10 if view.n_columns >= 40 else max(1, view.n_columns // 4)
    chunks = min(4, (view.n_columns - 1) // stride + 1)
    config = {
        "study": study,
        "model": model,
        "bifurcation": {
            "chunks": chunks,
            "stride": stride,
            "per_w": {"n_transient": view.n_transient, "n_record": view.n_record, "n_initial": view.n_initial},
            "sweeps": {view.direction: {"start": float(start), "stop": float(stop), "step": float(step)}},
            TARGETS[view.quantity]: {"sweep": view.direction},
        },
    }
    body = yaml.safe_dump(config, sort_keys=False, default_flow_style=False, allow_unicode=True)
    return "\n".join(head) + "\n" + body


def write_config(path, text: str) -> Path:
    """Write the config `text` to `path` atomically (a reader never sees half a file), never
    through a symbolic link: one at `path` is refused, as a link may point anywhere."""
    path = Path(path)
    if path.is_symlink():
        raise InputError(f"{path.name}: a symbolic link; the config is not written through it")
    with atomic_write(path) as tmp:
        Path(tmp).write_text(text)
    return path


def snakemake_command(view: View, config_path: str) -> str:
    """The command that draws the view's diagram as a figure of the study the snippet names."""
    return (
        f".venv/bin/snakemake -j2 {TARGETS[view.quantity]} --configfile config/config.yaml "
        f"{shlex.quote(str(config_path))}"
    )


def _inside(path: str, directory: str) -> bool:
    return os.path.commonpath([path, directory]) == directory


@dataclass(frozen=True)
class RecordAccess:
    """The record files the page may read: those inside `dirs` and the `files` named at start,
    judged by the path they resolve to (symbolic links followed), regular files with a record's
    suffix, at most `max_bytes` long. A relative path typed in the page is looked up in `dirs`."""

    dirs: tuple[str, ...] = (".",)
    files: tuple[str, ...] = ()
    max_bytes: int = RECORD_MAX_BYTES

    def __post_init__(self):
        object.__setattr__(self, "dirs", tuple(os.path.realpath(d) for d in self.dirs))
        object.__setattr__(self, "files", tuple(os.path.realpath(f) for f in self.files))

    def resolve(self, text: str) -> str:
        """The real path of the record `text` names, or InputError saying why it is refused
        (naming the file as typed, never its contents)."""
        typed = str(text).strip()
        if not typed:
            raise InputError("record file: give a path")
        name = os.path.basename(typed) or typed
        typed = os.path.expanduser(typed)
        candidates = [typed] if os.path.isabs(typed) else [os.path.join(d, typed) for d in self.dirs]
        real = next((os.path.realpath(c) for c in candidates if os.path.exists(c)), os.path.realpath(candidates[0]))
        if real not in self.files and not any(_inside(real, d) for d in self.dirs):
            where = ", ".join(self.dirs)
            raise InputError(
                f"record {name}: outside the directories records are read from ({where}); "
                "start the explorer with --data-dir DIR or --record FILE"
            )
        try:
            info = os.stat(real)
        except OSError:
            raise InputError(f"record {name}: no such file") from None
        if not stat.S_ISREG(info.st_mode):
            raise InputError(f"record {name}: not a regular file")
        if Path(real).suffix.lower() not in RECORD_SUFFIXES:
            raise InputError(f"record {name}: not a record file (use {', '.join(RECORD_SUFFIXES)})")
        if info.st_size > self.max_bytes:
            raise InputError(
                f"record {name}: {info.st_size / 2**20:.1f} MiB, more than the {self.max_bytes / 2**20:g} MiB "
                "the explorer loads"
            )
        return real


#: Quoted or bracketed text in a reader's message: possibly a piece of the file (a line, a header)
_QUOTED = re.compile(r"'[^'\n]*'|\"[^\"\n]*\"|\[[^\]\n]*\]|\{[^}\n]*\}|\([^)\n]*\)")


def record_error(name: str, real: str, message: str, limit: int = 300) -> str:
    """A record reader's error for the page, naming the file `name` and what is wrong (line,
    field count, ...) but none of its contents: the path becomes `name`, and whatever the reader
    quoted or bracketed (a line, a header, a value) is cut out."""
    first = str(message).strip().splitlines()[0] if str(message).strip() else "could not be read"
    text = _QUOTED.sub("(...)", first.replace(real, name))
    if len(text) > limit:
        text = text[:limit] + " ..."
    return f"record {name}: {text}"
