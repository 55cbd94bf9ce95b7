"""Attractors and their basins followed along w, and what they say about the two sweeps' hysteresis.

Why: Fig 2 (w increasing) and Fig 3b (w decreasing) show different attractors at some w; a sweep
shows the one it came from, so where they differ, two attractors should coexist. Here each w is
surveyed from the same random starts (:mod:`.attractor_survey`); an attractor found at one w seeds
the next w (a forward pass over the grid) and the one before (a backward pass of seeds alone), so an
attractor whose basin is too small for the sample is still followed, as a sweep follows it.

Attractors of neighbouring w are matched by the distance of their Poincare sets (Hausdorff, in
units of SCALE: 1 mm, 0.1 m/s), greedily from the closest pair, up to 0.5 or 8 per rad/s of the
step, whichever is larger: never by
their period or impacts, which jump at a grazing where the points do not. A set left unmatched
at the next w dies there, or merges into an attractor there that holds its points within that
distance; one
without a match at the w before is born.

A sweep's attractor at a w is the set of its recorded Poincare points; it is the survey's
attractor k when its points lie within 1 um and 0.1 mm/s of an orbit's (all of them; a settled
orbit repeats to 1e-13 m) or 0.1 mm and 10 mm/s of a non-periodic set's (95 % of them: the set is
a sample of `record` points). Where they lie on none, the sweep's record is a transient, and its
end state is settled further to say where it was heading.
"""

from __future__ import annotations

from dataclasses import dataclass

import h5py
import numpy as np

from impactosc.dynamics.attractor_survey import UNITS, read_survey_group, survey, write_survey_group
from impactosc.dynamics.diagram import classify_sweep, differing_windows
from impactosc.dynamics.recurrence import discover
from impactosc.dynamics.shooting import SCALE
from impactosc.dynamics.stroboscopic import StroboscopicMap, oscillator_settings
from impactosc.dynamics.sweep import OK
from impactosc.io.files import atomic_write, check_writable, stamp_h5

__all__ = [
    "differing_omegas",
    "continuation_omegas",
    "study_omegas",
    "survey_along",
    "set_distance",
    "Tracks",
    "track",
    "sweep_attractor",
    "hysteresis_rows",
    "save_surveys",
    "load_surveys",
]

#: largest distance (units of SCALE) of two attractors at neighbouring w that are one attractor:
#: MAX_DISTANCE, or MAX_DRIFT per rad/s between them if more. The period-1 orbit's point moves by
#: 4 mm per rad/s between 25 and 27 rad/s (1 mm per grid step of 0.25); two samples of 1000 points
#: of one chaotic set lie up to about 0.3 apart however close the w
MAX_DISTANCE = 0.5
MAX_DRIFT = 8.0
#: a sweep's point lies on a periodic attractor within (1 um, 0.1 mm/s) / SCALE, on a non-periodic
#: one within (0.1 mm, 10 mm/s) / SCALE (its recorded set leaves gaps of that size)
ON_PERIODIC = 1e-3
ON_CLOUD = 0.1


def differing_omegas(increasing, decreasing, reading: dict) -> list[tuple]:
    """(w_up, key_up, w_down, key_down) at every w_up of the increasing sweep where it reads another
    attractor than the decreasing sweep at its nearest w_down (:func:`.diagram.differing_windows`,
    one w enough); keys as :meth:`.diagram.BranchTable.key`. The two grids differ (0.025 and 0.02
    rad/s), so each sweep is compared with the survey at its own w."""
    tol = {k: reading[k] for k in ("x_tol", "v_tol", "isi_tol") if k in reading}
    a, b = classify_sweep(increasing, **tol), classify_sweep(decreasing, **tol)
    out = []
    for lo, hi in differing_windows(a, b, 1):
        for i in np.flatnonzero((a.omega >= lo) & (a.omega <= hi)):
            j = int(np.abs(b.omega - a.omega[i]).argmin())
            out.append((float(a.omega[i]), a.key(int(i)), float(b.omega[j]), b.key(j)))
    return out


def continuation_omegas(start: float, stop: float, step: float, extra=()) -> np.ndarray:
    """The regular grid start..stop by step, with the w of `extra` (e.g. where the sweeps differ)."""
    if not (0 < start < stop and step > 0):
        raise ValueError(f"the w grid needs 0 < start < stop and step > 0, got {start}, {stop}, {step}")
    grid = np.round(np.arange(start, stop + 0.5 * step, step), 9)
    return np.unique(np.concatenate([grid, np.round(np.asarray(extra, dtype=float), 9)]))


def study_omegas(increasing, decreasing, reading: dict, grid: dict) -> tuple[np.ndarray, list]:
    """(the w values of a continuation, the sweeps' differing w): the regular grid {start, stop,
    step} with both sweeps' w of every disagreement added (:func:`differing_omegas`)."""
    differing = differing_omegas(increasing, decreasing, reading)
    extra = [d[0] for d in differing] + [d[2] for d in differing]
    return continuation_omegas(grid["start"], grid["stop"], grid["step"], extra), differing


def _seeds(s) -> np.ndarray:
    """One state per attractor of a survey: its last point."""
    return np.array([a.points[-1] for a in s.attractors]).reshape(-1, 2)


def survey_along(omegas, starts, params=None, settings=None, *, boxes: int = 10, progress=None) -> list:
    """One survey per w (in increasing order) from `starts`, seeded forward and backward (module docstring)."""
    omegas = np.asarray(omegas, dtype=float)
    if omegas.ndim != 1 or omegas.size == 0 or np.any(np.diff(omegas) <= 0):
        raise ValueError("the w values must be a non-empty increasing 1-D array")
    out = []
    for i, w in enumerate(omegas):
        out.append(survey(w, starts, params, settings, boxes=boxes, seeds=_seeds(out[-1]) if out else None))
        if progress is not None:
            progress(i + 1, omegas.size, out[-1])
    settings = settings or oscillator_settings()
    for i in range(omegas.size - 2, -1, -1):  # seeds alone from the w above: an attractor the w below missed
        s, seeds = out[i], _seeds(out[i + 1])
        if not len(seeds):  # nothing settled at the w above (at a bifurcation every start may be unresolved)
            continue
        d = discover(StroboscopicMap(s.omega, params), seeds, settings, known=list(s.attractors))
        s.attractors.extend(d.attractors[len(s.attractors) :])
    return out


def set_distance(a: np.ndarray, b: np.ndarray, directed: bool = False, quantile: float = 1.0) -> float:
    """Hausdorff distance of two point sets (n, 2) in units of SCALE; `directed`: the largest
    distance from a point of a to the set b (or that quantile of the distances)."""
    d = np.sqrt((((a[:, None, :] - b[None, :, :]) / SCALE) ** 2).sum(axis=2))
    forward = float(np.quantile(d.min(axis=1), quantile))
    return forward if directed else max(forward, float(d.min(axis=0).max()))


@dataclass
class Tracks:
    """A track id for every attractor of every survey, and the events between neighbouring w."""

    ids: list  # per survey: list of ids, one per attractor
    events: list  # dicts: omega, event (born | died | merged), track, into


def track(surveys, max_distance: float = MAX_DISTANCE, max_drift: float = MAX_DRIFT) -> Tracks:
    """Match attractors of neighbouring w (module docstring) and name births, deaths and mergers;
    two are one within max(max_distance, max_drift |dw|)."""
    ids, events, next_id = [], [], 0
    for i, s in enumerate(surveys):
        if i == 0:
            ids.append(list(range(len(s.attractors))))
            next_id = len(s.attractors)
            continue
        prev, prev_ids = surveys[i - 1], ids[-1]
        limit = max(max_distance, max_drift * abs(s.omega - prev.omega))
        d = np.array([[set_distance(a.points, b.points) for b in s.attractors] for a in prev.attractors])
        d = d.reshape(len(prev.attractors), len(s.attractors))
        mine = [None] * len(s.attractors)
        used = set()
        for flat in np.argsort(d, axis=None):
            p, q = np.unravel_index(flat, d.shape)
            if d[p, q] > limit:
                break
            if p in used or mine[q] is not None:
                continue
            mine[q], used = prev_ids[p], used | {p}
        for q, m in enumerate(mine):
            if m is None:
                mine[q], next_id = next_id, next_id + 1
                events.append({"omega": s.omega, "event": "born", "track": mine[q], "into": ""})
        for p in set(range(len(prev.attractors))) - used:
            # merged: it lies within the limit of (inside) an attractor at this w: the distance from
            # its points to that set, not back (a set that merges into a larger one is part of it)
            into = [set_distance(prev.attractors[p].points, b.points, directed=True) for b in s.attractors]
            near = int(np.argmin(into)) if into else -1
            merged = near >= 0 and into[near] <= limit
            events.append(
                {"omega": s.omega, "event": "merged" if merged else "died", "track": prev_ids[p],
                 "into": mine[near] if merged else ""}
            )  # fmt: skip
        ids.append(mine)
    return Tracks(ids, events)


def sweep_attractor(points, attractors) -> int:
    """Index of the attractor holding a sweep's Poincare points (module docstring), -1 if none:
    every point on an orbit, 95 % of them on a non-periodic set (a sample of 1000 points leaves
    thin parts of a chaotic set bare)."""
    best, where = np.inf, -1
    for k, a in enumerate(attractors):
        d = set_distance(np.asarray(points), a.points, directed=True, quantile=1.0 if a.period else 0.95)
        if d <= (ON_PERIODIC if a.period else ON_CLOUD) and d < best:
            best, where = d, k
    return where


#: why two sweeps read different attractors at a w (the `why` of a hysteresis row)
COEXIST = "coexisting attractors"
CHANGES = "the attractor changes between the two sweeps' w"
READ_TWICE = "one attractor, read two ways"
TRANSIENT = "a sweep's record is a transient"


def hysteresis_rows(surveys, tracks: Tracks, increasing, decreasing, differing, params=None, settings=None):
    """One row per w where the sweeps differ (:func:`differing_omegas`): the attractors found there
    (track, name, fraction of starts), each sweep's attractor among them (the increasing sweep's
    at its w, the decreasing one's at its nearest w), and why they differ:

    - COEXIST: both found, distinct, both present at one of the two w (hysteresis);
    - CHANGES: each on the attractor of its own w, but no w has both, or one attractor followed
      along w that changes its period between the two w (the grids are up to 0.01 rad/s apart);
    - READ_TWICE: both on the same attractor at the same w, or on the same track with the same
      period (a reading at the sweeps' tolerance of a record near a period doubling);
    - TRANSIENT: a sweep's points lie on no attractor found; its end state is then settled
      further, and the row says where it lands and after how many periods.

    `explained` is True for COEXIST only."""
    by_w = {round(s.omega, 9): (s, ids) for s, ids in zip(surveys, tracks.ids)}
    rows = []
    for w_up, key_up, w_down, key_down in differing:
        (s_up, ids_up), (s_down, ids_down) = by_w[round(w_up, 9)], by_w[round(w_down, 9)]
        sides = [
            _sweep_side(result, w, sv, ids, params, settings)
            for result, w, sv, ids in ((increasing, w_up, s_up, ids_up), (decreasing, w_down, s_down, ids_down))
        ]
        (t_up, text_up, settled_up), (t_down, text_down, settled_down) = sides
        if not (settled_up and settled_down):
            why = TRANSIENT
        elif t_up != t_down and ({t_up, t_down} <= set(ids_up) or {t_up, t_down} <= set(ids_down)):
            why = COEXIST
        elif t_up == t_down and (w_up == w_down or text_up == text_down):
            why = READ_TWICE
        else:
            why = CHANGES
        n = s_up.labels.size
        rows.append(
            {
                "omega": w_up,
                "omega_decreasing": w_down,
                "increasing_reads": _key_text(key_up),
                "decreasing_reads": _key_text(key_down),
                "attractors": len(s_up.attractors),
                "found": "; ".join(
                    f"T{t} {a.name} {100 * np.count_nonzero(s_up.labels == k + 1) / n:.1f} %"
                    for k, (a, t) in enumerate(zip(s_up.attractors, ids_up))
                ),
                "increasing": text_up,
                "decreasing": text_down,
                "why": why,
                "explained": why == COEXIST,
            }
        )
    return rows


def _sweep_side(result, omega, s, ids, params, settings):
    """(track, text, on an attractor) of a sweep at w: the attractor holding its recorded points,
    or, for a transient record, where its end state settles (:func:`.recurrence.discover` with
    the survey's attractors known)."""
    i = int(np.abs(result.omega - omega).argmin())
    if result.status[i] != OK:
        return None, "abandoned", False
    k = sweep_attractor(np.column_stack([result.poincare_x[i], result.poincare_v[i]]), s.attractors)
    if k >= 0:
        return ids[k], f"T{ids[k]} {s.attractors[k].name}", True
    end = np.array([[result.x_end[i], result.v_end[i]]])
    d = discover(StroboscopicMap(s.omega, params), end, settings or oscillator_settings(), known=list(s.attractors))
    label, periods = int(d.labels[0]), int(d.iterations[0])
    if 0 < label <= len(s.attractors):
        where = f"T{ids[label - 1]} {s.attractors[label - 1].name}"
    elif label > 0:
        where = f"a new attractor ({d.attractors[label - 1].name})"
    else:
        where = "nothing"
    return None, f"transient: settles on {where} after {periods} more periods", False


def _key_text(key) -> str:
    return f"period {key[1]}, {key[2]} impacts" if key[0] == "periodic" else key[0]


# ------------------------------------------------------------------------------ files


def save_surveys(path, surveys, *, sources=None, **attrs) -> None:
    """All surveys of a continuation (or one chunk of it) in one HDF5 file, a group per w."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        for i, s in enumerate(surveys):
            write_survey_group(f.create_group(f"w{i:04d}"), s)
        f.attrs["omegas"] = [s.omega for s in surveys]
        for k, v in attrs.items():
            f.attrs[k] = v
        stamp_h5(f, sources=sources, units=UNITS)


def load_surveys(path) -> list:
    """The surveys of a file :func:`save_surveys` wrote, in w order."""
    with h5py.File(path, "r") as f:
        return [read_survey_group(f[k]) for k in sorted(k for k in f if k.startswith("w"))]
