"""Basins of attraction: which attractor each initial state (x0, v0) at phase 0 settles on.

Why: at w = 23.05 rad/s the period-1 orbit of the branch followed down from higher w coexists
with the period-3 orbit (4 impacts) past the grazing that the run from rest lands on, so "the"
attractor depends on the start. A basin map says how much of the plane each one attracts.

How: the reference attractors are shot (Newton on P^N(y) = y) and kept with all N Poincare
points. A cell runs in blocks of `block` periods (each core run continues from the last one's
end state at phase 0) and stops once `confirm` Poincare points in a row lie, in the attractor's
own order, in the box |dx| < x_tol, |dv| < v_tol around its points (early exit). A cell that
reaches none within `max_periods` is UNRESOLVED (with the period of its tail: another attractor
is reported, not forced into a class); one the core stopped is FAILED. The box must lie inside
the basin: period 1 passes the obstacle 6.4 um away, so a kick of that size can make it touch and
jump to period 3. Measured on ellipses of radius r in x and 20 r /s in v around each point: every
state returned for r <= 5 um, 8 of 32 left period 1 at 10 um (period 3: none up to 30 um). Hence
1 um and 20 um/s, 5 times inside; there the orbits contract (|mu| = 0.40 per period, 0.35 per 3
periods), so 6 periods in order (two cycles of period 3) is no transient passing by. Rows of the
grid are split into jobs as the 2-D map (:mod:`..sweeps.maps`). The binomial standard error of a
fraction does not cover the grid's resolution of basin boundaries (compare a finer grid).
"""

from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass, field

import h5py
import numpy as np

from impactosc.core.simulation import DEFAULT_ATOL, DEFAULT_RTOL, StallError, end_state, simulate, start_of
from impactosc.dynamics.branch_segments import orbit_sample, seed_from_rest
from impactosc.dynamics.shooting import shoot
from impactosc.io.files import atomic_write, check_writable, stamp_h5
from impactosc.model.parameters import ModelParams

__all__ = [
    "UNRESOLVED",
    "FAILED",
    "MAX_TAIL_PERIOD",
    "Attractor",
    "BasinSettings",
    "BasinGrid",
    "Cell",
    "BasinMap",
    "reference_attractors",
    "classify_state",
    "chunk_rows",
    "classify_rows",
    "class_names",
    "basin_fractions",
    "save_basins",
    "load_basins",
    "merge_basins",
]

#: class of a cell that reached no known attractor within max_periods (another attractor, or
#: a transient longer than the cap); class k >= 1 is the k-th reference attractor
UNRESOLVED = 0
#: class of a cell whose run the core stopped (StallError: step budget or step-size underflow)
FAILED = -1
#: the tail of an unresolved cell is checked for periods 1..MAX_TAIL_PERIOD (forcing periods)
MAX_TAIL_PERIOD = 12


@dataclass(frozen=True)
class Attractor:
    """A stable periodic orbit at phase 0: its N Poincare points P^k(y), k = 1..N, in the
    order the map visits them (the last is the shot fixed point y)."""

    name: str
    n_periods: int  # N
    impacts: int  # per orbit (N forcing periods)
    x: np.ndarray  # m, (N,)
    v: np.ndarray  # m/s, (N,)
    multipliers: np.ndarray  # complex, of P^N, by decreasing modulus

    def __post_init__(self):
        if np.shape(self.x) != (self.n_periods,) or np.shape(self.v) != (self.n_periods,):
            raise ValueError(f"attractor {self.name}: needs {self.n_periods} Poincare points x and v")

    def index_of(self, x: float, v: float, x_tol: float, v_tol: float) -> int:
        """Index k of the Poincare point whose box |dx| < x_tol, |dv| < v_tol holds (x, v); -1 if none."""
        inside = np.flatnonzero((np.abs(self.x - x) < x_tol) & (np.abs(self.v - v) < v_tol))
        return int(inside[0]) if inside.size else -1


def _positive(name, value, integer=False):
    if integer:
        if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    elif not isinstance(value, (int, float, np.integer, np.floating)) or not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")


@dataclass(frozen=True)
class BasinSettings:
    """How a cell is classified: forcing w, the box around each attractor point, the periods
    in a row it must stay there, the cap, the block length per core run, model, tolerances."""

    omega: float  # rad/s
    x_tol: float = 1e-6  # m
    v_tol: float = 2e-5  # m/s
    confirm: int = 6  # consecutive Poincare points in the boxes, in the attractor's order
    max_periods: int = 400
    block: int = 10  # forcing periods per core run
    params: ModelParams = field(default_factory=ModelParams)
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL

    def __post_init__(self):
        for name in ("omega", "x_tol", "v_tol", "rtol", "atol"):
            _positive(name, getattr(self, name))
        for name in ("confirm", "max_periods", "block"):
            _positive(name, getattr(self, name), integer=True)
        if self.confirm > self.max_periods:
            raise ValueError(f"confirm ({self.confirm}) must not exceed max_periods ({self.max_periods})")

    @classmethod
    def from_config(cls, basins: dict, model: dict, solver: dict) -> BasinSettings:
        """Settings from the workflow config sections basins, model and solver."""
        keys = ("x_tol", "v_tol", "confirm", "max_periods", "block")
        return cls(
            omega=float(basins["omega"]),
            params=ModelParams(**model),
            rtol=float(solver["rtol"]),
            atol=float(solver["atol"]),
            **{k: basins[k] for k in keys if k in basins},
        )

    def to_attrs(self) -> dict:
        """Flat attributes for the HDF5 file (which settings produced the classes)."""
        out = {
            k: getattr(self, k) for k in ("omega", "x_tol", "v_tol", "confirm", "max_periods", "block", "rtol", "atol")
        }
        out.update({f"param_{k}": v for k, v in self.params.to_dict().items()})
        return out


@dataclass(frozen=True)
class BasinGrid:
    """Initial states at phase 0: x0 (m) along a row, v0 (m/s) one row each (both increasing)."""

    x0: np.ndarray
    v0: np.ndarray

    def __post_init__(self):
        for name in ("x0", "v0"):
            a = np.asarray(getattr(self, name), dtype=float)
            if a.ndim != 1 or a.size == 0:
                raise ValueError(f"the grid's {name} must be a non-empty 1-D array, got shape {a.shape}")
            if not np.all(np.isfinite(a)):
                raise ValueError(f"the grid's {name} must be finite")
            if np.any(np.diff(a) <= 0):
                raise ValueError(f"the grid's {name} must be strictly increasing")
            object.__setattr__(self, name, a)

    @classmethod
    def linspace(cls, x_range, v_range, n_x: int, n_v: int) -> BasinGrid:
        """n_x x0 values from x_range[0] to x_range[1] (m), n_v v0 values over v_range (m/s)."""
        axes = []
        for name, rng, n in (("x0", x_range, n_x), ("v0", v_range, n_v)):
            _positive(f"n of {name}", n, integer=True)
            lo, hi = (float(r) for r in rng)
            if not (math.isfinite(lo) and math.isfinite(hi)) or not lo < hi:
                raise ValueError(f"{name} range must be finite with start < stop, got [{lo}, {hi}]")
            axes.append(np.linspace(lo, hi, n))
        return cls(*axes)

    @property
    def shape(self) -> tuple[int, int]:
        return self.v0.size, self.x0.size


@dataclass(frozen=True)
class Cell:
    """Result of one initial state: class (k >= 1: attractor k; UNRESOLVED; FAILED), forcing
    periods run until it was known, end state (m, m/s), and for an unresolved cell the period of
    its tail (forcing periods; 0: none up to MAX_TAIL_PERIOD)."""

    cls: int
    periods: int
    x_end: float
    v_end: float
    tail_period: int = 0


def _lowest_period(sample: dict) -> int:
    """Smallest k dividing N with P^k(y) = y (to 1e-9 m, 1e-7 m/s): a period-N guess may
    converge to an orbit of lower period, e.g. a period-1 orbit, which is a fixed point of P^3 too."""
    px, pv = np.array(sample["poincare_x"]), np.array(sample["poincare_v"])
    n = px.size
    for k in range(1, n):
        if (
            n % k == 0
            and np.all(np.abs(px[k - 1 :: k] - px[-1]) < 1e-9)
            and np.all(np.abs(pv[k - 1 :: k] - pv[-1]) < 1e-7)
        ):
            return k
    return n


def reference_attractors(omega: float, seeds: dict, params: ModelParams | None = None) -> list[Attractor]:
    """The stable periodic orbits to classify against, shot at `omega`.

    seeds: name -> {"n_periods": N, "guess": [x, v] or None}; None settles from rest first
    (:func:`..periodic_orbits.segments.seed_from_rest`). Raises ValueError for no seeds, an
    unstable orbit (not an attractor), a guess that converges to an orbit of lower period, or two
    seeds that give the same orbit."""
    if not seeds:
        raise ValueError("no reference attractors given")
    out: list[Attractor] = []
    for name, seed in seeds.items():
        n = seed.get("n_periods")
        _positive(f"n_periods of attractor {name}", n, integer=True)
        guess = seed.get("guess")
        orbit = seed_from_rest(omega, n, params) if guess is None else shoot(guess, omega, n, params)
        if not orbit.stable:
            raise ValueError(
                f"attractor {name} at w = {omega}: the orbit is unstable (|mu| = {np.abs(orbit.multipliers)})"
            )
        sample = orbit_sample(orbit, params)
        k = _lowest_period(sample)
        if k != n:
            raise ValueError(f"attractor {name}: the period-{n} guess converged to a period-{k} orbit")
        att = Attractor(
            str(name), n, sample["impacts"], np.array(sample["poincare_x"]), np.array(sample["poincare_v"]),
            orbit.multipliers,
        )  # fmt: skip
        for other in out:
            if any(other.index_of(x, v, 1e-9, 1e-7) >= 0 for x, v in zip(att.x, att.v)):
                raise ValueError(f"attractors {other.name} and {name} are the same orbit")
        out.append(att)
    return out


def _check_boxes(attractors: list[Attractor], s: BasinSettings) -> None:
    """The boxes of different points must not overlap, or a point could belong to two."""
    pts = [(a.name, x, v) for a in attractors for x, v in zip(a.x, a.v)]
    for i, (n1, x1, v1) in enumerate(pts):
        for n2, x2, v2 in pts[i + 1 :]:
            if abs(x1 - x2) < 2 * s.x_tol and abs(v1 - v2) < 2 * s.v_tol:
                raise ValueError(
                    f"the tolerance boxes of {n1} and {n2} overlap at x = {x1:.6e} m: lower x_tol ({s.x_tol}) or v_tol ({s.v_tol})"
                )


def _tail_period(history, x_tol: float, v_tol: float) -> int:
    """Smallest N <= MAX_TAIL_PERIOD with each of the last N Poincare points within the box
    (x_tol, v_tol) of the point N periods before it; 0 if none."""
    h = np.asarray(history)
    for n in range(1, MAX_TAIL_PERIOD + 1):
        if h.shape[0] < 2 * n:
            break
        d = np.abs(h[-n:] - h[-2 * n : -n])
        if np.all(d[:, 0] < x_tol) and np.all(d[:, 1] < v_tol):
            return n
    return 0


def classify_state(x0: float, v0: float, attractors: list[Attractor], settings: BasinSettings) -> Cell:
    """Run (x0, v0) at phase 0 in blocks of settings.block periods until `confirm` consecutive
    Poincare points sit on one attractor's points in its order (early exit), at most
    max_periods; see the module docstring."""
    s = settings
    if not attractors:
        raise ValueError("no reference attractors to classify against")
    for name, value in (("x0", x0), ("v0", v0)):
        if not isinstance(value, (int, float, np.integer, np.floating)) or not math.isfinite(value):
            raise ValueError(f"{name} must be a finite number, got {value!r}")
    period = 2 * math.pi / s.omega
    x, v = float(x0), float(v0)
    state = np.array([x, v])  # and a restitution contact's onset velocity once a block ends inside one
    done = 0
    streak, last = 0, (-1, -1)
    history = deque(maxlen=2 * MAX_TAIL_PERIOD)
    while done < s.max_periods:
        n = min(s.block, s.max_periods - done)
        try:
            run = simulate(
                s.omega,
                0.0,
                n * period,
                **start_of(state),
                params=s.params,
                rtol=s.rtol,
                atol=s.atol,
                record=("poincare",),
            )
        except StallError as e:
            return Cell(FAILED, done, float(e.state["x"]), float(e.state["v"]))
        px, pv = run.events["poincare"]["x"], run.events["poincare"]["v"]
        if px.size != n:
            raise RuntimeError(f"the core gave {px.size} Poincare points for a run of {n} forcing periods")
        for xj, vj in zip(px, pv):
            done += 1
            history.append((xj, vj))
            hit = next(
                ((i, k) for i, a in enumerate(attractors) if (k := a.index_of(xj, vj, s.x_tol, s.v_tol)) >= 0),
                (-1, -1),
            )
            if hit[0] < 0:
                streak = 0
            elif streak and hit[0] == last[0] and hit[1] == (last[1] + 1) % attractors[hit[0]].n_periods:
                streak += 1
            else:
                streak = 1
            last = hit
            if streak >= s.confirm:
                return Cell(hit[0] + 1, done, float(xj), float(vj))
        state = end_state(run)
        x, v = float(state[0]), float(state[1])
    return Cell(UNRESOLVED, done, x, v, _tail_period(history, s.x_tol, s.v_tol))


def chunk_rows(n_rows: int, chunks: int, part: int) -> np.ndarray:
    """Row indices of job `part` of `chunks` (contiguous, sizes differing by at most one)."""
    _positive("n_rows", n_rows, integer=True)
    _positive("chunks", chunks, integer=True)
    if chunks > n_rows:
        raise ValueError(f"{chunks} chunks for {n_rows} grid rows: some jobs would have no rows")
    if not isinstance(part, (int, np.integer)) or not 0 <= part < chunks:
        raise ValueError(f"part must be an integer in [0, {chunks}), got {part!r}")
    return np.array_split(np.arange(n_rows), chunks)[part]


@dataclass
class BasinMap:
    """Classes of grid rows (all rows, or one job's chunk): arrays (len(rows), n_x)."""

    x0: np.ndarray  # m, (n_x,)
    v0: np.ndarray  # m/s, (n_rows,) the v0 of these rows
    rows: np.ndarray  # row indices in the full grid
    classes: np.ndarray  # int
    periods: np.ndarray  # int, forcing periods run
    x_end: np.ndarray
    v_end: np.ndarray
    tail_period: np.ndarray  # int
    attractors: list[Attractor]
    settings: dict  # BasinSettings.to_attrs()
    cpu_time: float = 0.0  # s, CPU time of the classification (sum over jobs)


def classify_rows(grid: BasinGrid, rows, attractors: list[Attractor], settings: BasinSettings) -> BasinMap:
    """Classify every cell of the given grid rows (one job's work)."""
    rows = np.asarray(rows, dtype=int)
    if rows.ndim != 1 or rows.size == 0:
        raise ValueError("no grid rows to classify")
    if rows.min() < 0 or rows.max() >= grid.v0.size:
        raise ValueError(f"rows must lie in [0, {grid.v0.size}), got {rows.min()}..{rows.max()}")
    _check_boxes(attractors, settings)
    shape = (rows.size, grid.x0.size)
    out = {k: np.zeros(shape, dtype=int) for k in ("classes", "periods", "tail_period")}
    out.update({k: np.zeros(shape) for k in ("x_end", "v_end")})
    started = time.process_time()
    for i, r in enumerate(rows):
        for j, x0 in enumerate(grid.x0):
            c = classify_state(float(x0), float(grid.v0[r]), attractors, settings)
            out["classes"][i, j], out["periods"][i, j], out["tail_period"][i, j] = c.cls, c.periods, c.tail_period
            out["x_end"][i, j], out["v_end"][i, j] = c.x_end, c.v_end
    return BasinMap(
        grid.x0.copy(), grid.v0[rows].copy(), rows, **out, attractors=list(attractors),
        settings=settings.to_attrs(), cpu_time=time.process_time() - started,
    )  # fmt: skip


def class_names(attractors: list[Attractor]) -> dict[int, str]:
    """Class code -> name: the attractors (1..K), then unresolved and failed."""
    names = {i + 1: a.name for i, a in enumerate(attractors)}
    names[UNRESOLVED] = "unresolved"
    names[FAILED] = "failed"
    return names


def basin_fractions(classes, names: dict[int, str], tail_period=None) -> list[dict]:
    """Rows (class, name, cells, fraction, se) for every class in `names`, then one per tail
    period found among the unresolved cells ("unresolved, period N tail").

    se = sqrt(p (1 - p) / n): the binomial standard error of a fraction of n cells. It is the
    sampling error of a random set of n states; it does not cover how well the grid resolves the
    basin boundaries (fine structure between grid points), which only a finer grid shows."""
    c = np.asarray(classes)
    if c.size == 0:
        raise ValueError("empty class grid: no cells to count")
    unknown = sorted(set(np.unique(c).tolist()) - set(names))
    if unknown:
        raise ValueError(f"class grid has codes {unknown} not in {sorted(names)}")
    n = c.size

    def row(code, name, count):
        p = count / n
        return {"class": code, "name": name, "cells": int(count), "fraction": p, "se": math.sqrt(p * (1 - p) / n)}

    order = sorted(k for k in names if k > 0) + sorted((k for k in names if k <= 0), reverse=True)
    out = [row(code, names[code], np.count_nonzero(c == code)) for code in order]
    if tail_period is not None:
        t = np.asarray(tail_period)
        if t.shape != c.shape:
            raise ValueError(f"tail_period has shape {t.shape}, the class grid {c.shape}")
        for period in sorted(set(t[(c == UNRESOLVED) & (t > 0)].tolist())):
            count = np.count_nonzero((c == UNRESOLVED) & (t == period))
            out.append(row(UNRESOLVED, f"unresolved, period-{period} tail", count))
    return out


# ------------------------------------------------------------------------------ files

_ARRAYS = ("x0", "v0", "rows", "classes", "periods", "x_end", "v_end", "tail_period")
UNITS = {
    "x0": "m",
    "v0": "m/s",
    "rows": "1",
    "classes": "1",
    "periods": "1",
    "tail_period": "1",
    "attractor_x": "m",
    "attractor_v": "m/s",
    "attractor_of_point": "1",
    "multipliers_re": "1",
    "multipliers_im": "1",
}


def save_basins(path, m: BasinMap, *, sources=None, **attrs) -> None:
    """Write a basin map (or one job's rows) to HDF5 atomically, with units and provenance.
    Datasets: the arrays of BasinMap, the attractors' Poincare points (attractor_x/_v, with
    attractor_of_point) and multipliers; attributes: the settings, cpu_time, attractor names,
    periods and impacts, and `attrs`."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        for k in _ARRAYS:
            f.create_dataset(k, data=getattr(m, k))
        f.create_dataset("attractor_x", data=np.concatenate([a.x for a in m.attractors]))
        f.create_dataset("attractor_v", data=np.concatenate([a.v for a in m.attractors]))
        f.create_dataset(
            "attractor_of_point", data=np.repeat(np.arange(len(m.attractors)), [a.n_periods for a in m.attractors])
        )
        f.create_dataset("multipliers_re", data=np.array([a.multipliers.real for a in m.attractors]))
        f.create_dataset("multipliers_im", data=np.array([a.multipliers.imag for a in m.attractors]))
        f.attrs["attractor_names"] = np.array([a.name for a in m.attractors], dtype=h5py.string_dtype())
        f.attrs["attractor_periods"] = [a.n_periods for a in m.attractors]
        f.attrs["attractor_impacts"] = [a.impacts for a in m.attractors]
        f.attrs["cpu_time"] = m.cpu_time
        for k, v in {**m.settings, **attrs}.items():
            f.attrs[k] = v
        stamp_h5(f, sources=sources, units=UNITS)


def load_basins(path) -> tuple[BasinMap, dict]:
    """Read a file of :func:`save_basins`: the map and the extra root attributes it was given."""
    with h5py.File(path, "r") as f:
        arrays = {k: f[k][()] for k in _ARRAYS}
        ax, av, owner = f["attractor_x"][()], f["attractor_v"][()], f["attractor_of_point"][()]
        mu = f["multipliers_re"][()] + 1j * f["multipliers_im"][()]
        names = [s.decode() if isinstance(s, bytes) else str(s) for s in f.attrs["attractor_names"]]
        attractors = [
            Attractor(name, int(n), int(imp), ax[owner == i], av[owner == i], mu[i])
            for i, (name, n, imp) in enumerate(zip(names, f.attrs["attractor_periods"], f.attrs["attractor_impacts"]))
        ]
        keys = ("omega", "x_tol", "v_tol", "confirm", "max_periods", "block", "rtol", "atol")
        settings = {k: _plain(f.attrs[k]) for k in f.attrs if k in keys or k.startswith("param_")}
        reserved = {*settings, "attractor_names", "attractor_periods", "attractor_impacts", "cpu_time"}
        extra = {k: f.attrs[k] for k in f.attrs if k not in reserved}
        return BasinMap(**arrays, attractors=attractors, settings=settings, cpu_time=float(f.attrs["cpu_time"])), extra


def _plain(value):
    """An HDF5 attribute as a plain Python value (a number, or the law's name)."""
    return value.item() if hasattr(value, "item") else value


def merge_basins(parts: list[BasinMap]) -> BasinMap:
    """Stack row chunks (in row order) into one map; they must share x0, attractors and settings
    and their rows must be 0, 1, ..., n - 1 without gaps."""
    if not parts:
        raise ValueError("no basin chunks to merge")
    first = parts[0]
    for p in parts[1:]:
        if not np.array_equal(p.x0, first.x0) or p.settings != first.settings:
            raise ValueError("basin chunks differ in their x0 grid or settings")
        if [a.name for a in p.attractors] != [a.name for a in first.attractors] or not all(
            np.array_equal(a.x, b.x) and np.array_equal(a.v, b.v) for a, b in zip(p.attractors, first.attractors)
        ):
            raise ValueError("basin chunks differ in their reference attractors")
    rows = np.concatenate([p.rows for p in parts])
    if not np.array_equal(rows, np.arange(rows.size)):
        raise ValueError(f"basin chunks cover rows {rows.tolist()}, not 0..{rows.size - 1} in order")
    stacked = {k: np.concatenate([getattr(p, k) for p in parts]) for k in _ARRAYS if k != "x0"}
    return BasinMap(
        first.x0.copy(), **stacked, attractors=list(first.attractors), settings=dict(first.settings),
        cpu_time=float(sum(p.cpu_time for p in parts)),
    )  # fmt: skip
