"""The attractors at one w from random starts: who they are, the share of starts each takes, how
mixed their basins are, and the file that keeps it.

Why a module: the command ``impactosc attractors`` and the workflow's continuation along w (one
survey per w, :mod:`.attractor_continuation`) do the same thing at each w: draw starts (x0, v0)
uniformly in a rectangle at phase 0, settle them (:func:`.recurrence.discover` on
:class:`.stroboscopic.StroboscopicMap`), count (:func:`.basins.basin_fractions`: fraction and
binomial standard error) and measure the basins' mixing on boxes of the rectangle
(:mod:`.basin_mixing`).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import h5py
import numpy as np

from impactosc.dynamics.basin_mixing import BasinEntropy, basin_entropy, sample_boxes
from impactosc.dynamics.basins import basin_fractions
from impactosc.dynamics.recurrence import STOPPED, UNRESOLVED, FoundAttractor, RecurrenceSettings, discover
from impactosc.dynamics.stroboscopic import StroboscopicMap, oscillator_settings
from impactosc.io.files import atomic_write, check_writable, stamp_h5
from impactosc.model.parameters import ModelParams

__all__ = [
    "Survey",
    "random_starts",
    "survey",
    "survey_names",
    "survey_rows",
    "write_survey_group",
    "settings_attrs",
    "read_survey_group",
    "save_survey",
    "load_survey",
    "X_RANGE",
    "V_RANGE",
]

#: the rectangle of starts (m, m/s): the basin grid's (config basins.x0, basins.v0); an attractor may
#: reach beyond it (the chaotic set at w = 40.3 reaches x = -12 mm), the starts need not cover it
X_RANGE = (-8e-3, 4e-3)
V_RANGE = (-0.3, 0.3)


@dataclass
class Survey:
    """One w's attractors and what each start reached (labels as :mod:`.recurrence`'s)."""

    omega: float
    starts: np.ndarray  # (n, 2) x0 (m), v0 (m/s)
    labels: np.ndarray
    iterations: np.ndarray
    attractors: list  # FoundAttractor
    entropy: BasinEntropy | None
    cpu_time: float
    x_range: tuple = X_RANGE
    v_range: tuple = V_RANGE


def random_starts(n: int, x_range=X_RANGE, v_range=V_RANGE, seed: int = 0) -> np.ndarray:
    """n states (x0, v0) uniform in the rectangle (the same n for the same seed at every w)."""
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or n < 1:
        raise ValueError(f"the number of starts must be an integer >= 1, got {n!r}")
    for name, (lo, hi) in (("x range", x_range), ("v range", v_range)):
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"the {name} must be finite with start < stop, got [{lo}, {hi}]")
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(*x_range, n), rng.uniform(*v_range, n)])


def survey(
    omega: float,
    starts,
    params: ModelParams | None = None,
    settings: RecurrenceSettings | None = None,
    *,
    boxes: int = 10,
    seeds=None,
    known=None,
    progress=None,
    x_range=X_RANGE,
    v_range=V_RANGE,
) -> Survey:
    """Settle `starts` at w and count them; basin entropy over boxes x boxes of the rectangle.

    `seeds`: more states run first and not counted (e.g. points of the attractors at the
    neighbouring w, so that an attractor with a basin too small for the sample is still found);
    `known`: attractors given to the discovery to catch starts early."""
    system = StroboscopicMap(omega, params)
    settings = settings or oscillator_settings()
    started = time.process_time()
    attractors, reached = list(known or []), set()
    if seeds is not None and len(seeds):
        ds = discover(system, seeds, settings, known=attractors)
        attractors, reached = ds.attractors, set(ds.labels[ds.labels > 0].tolist())
    d = discover(system, starts, settings, progress=progress, known=attractors)
    reached |= set(d.labels[d.labels > 0].tolist())
    # a known attractor (from elsewhere) that neither a seed nor a start reaches here is not one here
    keep = [k for k in range(len(d.attractors)) if k + 1 in reached]
    relabel = {old + 1: new + 1 for new, old in enumerate(keep)}
    labels = np.array([relabel[int(c)] if c > 0 else c for c in d.labels], dtype=np.int64)
    starts = np.asarray(starts, dtype=float)
    box_ids = sample_boxes(starts[:, :2], (x_range[0], v_range[0]), (x_range[1], v_range[1]), boxes)
    # too few starts for any box to hold two: no entropy (None), the fractions still stand
    entropy = basin_entropy(labels, box_ids) if np.bincount(box_ids).max() >= 2 else None
    return Survey(
        float(omega), starts[:, :2], labels, d.iterations, [d.attractors[k] for k in keep], entropy,
        time.process_time() - started, tuple(x_range), tuple(v_range),
    )  # fmt: skip


def survey_names(attractors) -> dict:
    """Label -> name for the fractions: 'A<k>: <period, impacts or kind>', unresolved, stopped."""
    names = {k + 1: f"A{k + 1}: {a.name}" for k, a in enumerate(attractors)}
    names[UNRESOLVED] = "unresolved"
    names[STOPPED] = "stopped by the core"
    return names


def survey_rows(s: Survey) -> list[dict]:
    """One row per attractor (then unresolved, stopped): fraction +- se, period, impacts, exponent."""
    rows = basin_fractions(s.labels, survey_names(s.attractors))
    for r in rows:
        a = s.attractors[r["class"] - 1] if r["class"] > 0 else None
        r.update(
            kind=a.kind if a else "",
            period=a.period if a else "",
            impacts=a.impacts if a else "",
            exponent=a.exponent if a else "",
            x=float(a.points[-1, 0]) if a else "",
            v=float(a.points[-1, 1]) if a else "",
            median_iterations=float(np.median(s.iterations[s.labels == r["class"]])) if r["cells"] else "",
        )
    return rows


# ------------------------------------------------------------------------------ files

UNITS = {"starts": "m, m/s", "labels": "1", "iterations": "forcing periods", "points": "m, m/s", "owner": "1"}


def save_survey(path, s: Survey, *, sources=None, **attrs) -> None:
    """Write a survey to HDF5 atomically: the starts, labels and iterations; every attractor's
    points (`points`, with `owner` its index) and its period, impacts, exponent; the entropy."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        write_survey_group(f, s)
        for k, v in attrs.items():
            f.attrs[k] = v
        stamp_h5(f, sources=sources, units=UNITS)


def settings_attrs(settings: RecurrenceSettings) -> dict:
    """The discovery's settings as flat file attributes (recurrence_<name>)."""
    return {f"recurrence_{k}": v for k, v in asdict(settings).items()}


def write_survey_group(g, s: Survey) -> None:
    """A survey's datasets and attributes into an open HDF5 group (one per w in a continuation)."""
    g.create_dataset("starts", data=s.starts)
    g.create_dataset("labels", data=s.labels)
    g.create_dataset("iterations", data=s.iterations)
    pts = [a.points for a in s.attractors]
    g.create_dataset("points", data=np.concatenate(pts) if pts else np.zeros((0, 2)))
    g.create_dataset("owner", data=np.repeat(np.arange(len(pts)), [p.shape[0] for p in pts]))
    g.attrs.update(
        omega=s.omega, cpu_time=s.cpu_time, x_range=s.x_range, v_range=s.v_range,
        periods=[a.period for a in s.attractors], impacts=[a.impacts for a in s.attractors],
        exponents=[a.exponent for a in s.attractors],
    )  # fmt: skip
    if s.entropy is not None:
        g.attrs.update({f"entropy_{k}": v for k, v in s.entropy.to_dict().items()})


def read_survey_group(g) -> Survey:
    """The survey of :func:`write_survey_group` (attractor cells are not kept: rebuilt on demand)."""
    pts, owner = g["points"][()], g["owner"][()]
    attractors = [
        FoundAttractor(int(p), pts[owner == k], float(q), float(e))
        for k, (p, q, e) in enumerate(zip(g.attrs["periods"], g.attrs["impacts"], g.attrs["exponents"]))
    ]
    keys = ("entropy", "boundary_entropy", "boundary_fraction", "boxes", "boundary_boxes", "skipped")
    entropy = BasinEntropy(**{k: g.attrs[f"entropy_{k}"].item() for k in keys}) if "entropy_boxes" in g.attrs else None
    return Survey(
        float(g.attrs["omega"]), g["starts"][()], g["labels"][()], g["iterations"][()], attractors, entropy,
        float(g.attrs["cpu_time"]), tuple(g.attrs["x_range"]), tuple(g.attrs["v_range"]),
    )  # fmt: skip


def load_survey(path) -> Survey:
    """The survey of a file :func:`save_survey` wrote."""
    with h5py.File(path, "r") as f:
        return read_survey_group(f)
