"""Attractors of a map found without hints: every start iterated until its sequence recurs.

Why: :mod:`.basins` classifies states against orbits shot beforehand, so an attractor nobody shot
stays unnamed. Here the attractors come out of the iteration itself, as in Attractors.jl's
AttractorsViaRecurrences (cells of a grid, a finite-state machine per start), on two scales,
because this map has periodic orbits micrometres from a discontinuity (grazing) and chaotic sets
millimetres wide:

- a **periodic tail**: the last `confirm` points each repeat the point p iterations before to
  `tight` (settled orbits repeat to ~1e-13 m; a start still converging does not), p <= max_period,
  and do not repeat with a divisor of p to `reading` (near a period doubling a start converging to
  the period-1 orbit passes the test with p = 2 first);
- a **recurrent cloud**: `recur` consecutive points in coarse `cell`s this start visited before;
  3 max_period more points are periodic if they repeat to `reading` (the tolerance the sweeps'
  reading uses, so both name an attractor alike), else `record` points in all describe it,
  periodic if their last 3 max_period repeat (a slowly converging start's first ones do not),
  else non-periodic. A periodic reading settles the start only once its tail repeats to `tight`
  as well; until then the start goes on.

A known attractor catches a later start early: `confirm` consecutive points in the boxes
(`box`) of a periodic attractor's points, in its order (the box must lie inside the basin, as in
:mod:`.basins`: one point in a box is not enough near a discontinuity), or `confirm_cloud`
consecutive points in the cells of a non-periodic one (or their neighbours) that visit at least
`cloud_cells` distinct cells, or half the set's cells if it has fewer than twice that (a start
converging to a periodic orbit inside the cloud visits few).
A newly settled set that matches a known attractor is that attractor: two orbits whose periods
divide one another and whose points lie within half a cell of the other's (a start still
converging slowly, read at twice the period, is the orbit; at w = 23.05 the period-1 point lies
72 um and 3 mm/s from the period-3 orbit's nearest point, the other two 1 mm away), or two non-periodic sets with half the new one's cells on the known cells. Matching uses the points,
never the impacts: at a grazing the impacts per period change while the points move continuously.

The map is any object with ``iterate(state, n) -> (points (n, d), end state)`` (raising
:class:`Stopped` when it cannot go on) and ``describe(point, period) -> (impacts per period,
largest Lyapunov exponent)``; :mod:`.stroboscopic` gives the oscillator's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from impactosc.dynamics.basins import FAILED as STOPPED
from impactosc.dynamics.basins import UNRESOLVED
from impactosc.statistics.periods import detect_period

__all__ = [
    "STOPPED",
    "UNRESOLVED",
    "Stopped",
    "RecurrenceSettings",
    "FoundAttractor",
    "Discovery",
    "discover",
]

# labels as the basin maps': attractor k is k + 1, UNRESOLVED (0) settled on nothing within
# max_iterations, STOPPED (-1) could not be iterated (the core stopped)
#: a non-periodic attractor's largest exponent above this (per iteration) calls it chaotic: a finite
#: run's estimate on a periodic orbit is negative, near a bifurcation within about 1e-2 of zero
CHAOTIC_EXPONENT = 0.01


class Stopped(RuntimeError):
    """The map could not iterate this state (for the oscillator: the core stalled)."""


def _vector(name, value, d=None):
    a = np.atleast_1d(np.asarray(value, dtype=float))
    if a.ndim != 1 or (d is not None and a.size != d) or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ValueError(f"{name} must be {d or 'one or more'} finite numbers > 0, got {value!r}")
    return a


@dataclass(frozen=True)
class RecurrenceSettings:
    """Scales per state component (box, tight, reading, cell) and counts (in iterations)."""

    box: tuple  # half-widths around a periodic point that catch a start (inside its basin)
    tight: tuple  # a periodic tail repeats to this
    reading: tuple  # a recorded set is periodic if it repeats to this
    cell: tuple  # coarse cells of the recurrence of non-periodic sets
    max_period: int = 33
    confirm: int = 6
    confirm_cloud: int = 50
    cloud_cells: int = 16
    recur: int = 100
    record: int = 1000
    max_iterations: int = 2000
    block: int = 10

    def __post_init__(self):
        d = len(np.atleast_1d(self.box))
        for name in ("box", "tight", "reading", "cell"):
            object.__setattr__(self, name, tuple(_vector(name, getattr(self, name), d)))
        for name in (
            "max_period",
            "confirm",
            "confirm_cloud",
            "cloud_cells",
            "recur",
            "record",
            "max_iterations",
            "block",
        ):
            value = getattr(self, name)
            if not isinstance(value, (int, np.integer)) or isinstance(value, bool) or value < 1:
                raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
        if self.record < 3 * self.max_period:
            raise ValueError(f"record ({self.record}) must be >= 3 max_period ({3 * self.max_period}) to read a period")
        if self.max_iterations < self.confirm + self.max_period:
            raise ValueError(f"max_iterations ({self.max_iterations}) must be >= confirm + max_period")

    @property
    def dim(self) -> int:
        return len(self.box)


@dataclass
class FoundAttractor:
    """One attractor: period (0: non-periodic), its points (p of them in the map's order, or the
    recorded set), impacts per period (per iteration if non-periodic), largest Lyapunov exponent
    per iteration, and the coarse cells of a non-periodic one."""

    period: int
    points: np.ndarray  # (p or record, d)
    impacts: float
    exponent: float
    cells: set = field(default_factory=set, repr=False)
    _near: tuple = field(default=(0, frozenset()), repr=False)

    def near_cells(self) -> set:
        """The cells with their neighbours (cached until the cells grow)."""
        if self._near[0] != len(self.cells):
            self._near = (len(self.cells), _neighbours(self.cells))
        return self._near[1]

    @property
    def kind(self) -> str:
        if self.period:
            return "periodic"
        return "chaotic" if self.exponent > CHAOTIC_EXPONENT else "non-periodic"

    @property
    def name(self) -> str:
        if self.period:
            imp = f", {self.impacts:g} impact{'s' if self.impacts != 1 else ''}" if math.isfinite(self.impacts) else ""
            return f"period {self.period}{imp}"
        return self.kind


@dataclass
class Discovery:
    """What a set of starts settled on: the attractors, a label per start (k + 1, UNRESOLVED,
    STOPPED), the iterations each took and each start's last point."""

    attractors: list
    labels: np.ndarray
    iterations: np.ndarray
    last: np.ndarray  # (n, d)


def _cells(points, cell) -> list:
    return [tuple(c) for c in np.floor(np.asarray(points) / np.asarray(cell)).astype(np.int64)]


def _neighbours(cells: set) -> set:
    """The cells and the 3^d - 1 around each (a later start on the same set falls beside the
    recorded cells as often as in them)."""
    if not cells:
        return set()
    d = len(next(iter(cells)))
    shifts = np.array(np.meshgrid(*[[-1, 0, 1]] * d)).reshape(d, -1).T
    return {tuple(np.add(c, s)) for c in cells for s in shifts}


class _Catcher:
    """The known attractors' catching state along one start (streaks of consecutive hits)."""

    def __init__(self, attractors, s: RecurrenceSettings):
        self.att, self.s = attractors, s
        self.box = np.asarray(s.box)
        self.near = [a.near_cells() if not a.period else None for a in attractors]
        self.streak = [0] * len(attractors)
        self.last = [-1] * len(attractors)
        self.seen = [set() for _ in attractors]
        self.need = [min(s.cloud_cells, math.ceil(len(a.cells) / 2)) for a in attractors]

    def __call__(self, y) -> int:
        """Index of the attractor that caught the start at point y, or -1."""
        c = None
        for i, a in enumerate(self.att):
            if a.period:
                inside = np.flatnonzero(np.all(np.abs(a.points - y) < self.box, axis=1))
                k = int(inside[0]) if inside.size else -1
                if k < 0:
                    self.streak[i] = 0
                elif self.streak[i] and k == (self.last[i] + 1) % a.period:
                    self.streak[i] += 1
                else:
                    self.streak[i] = 1
                self.last[i] = k
                if self.streak[i] >= self.s.confirm:
                    return i
            else:
                c = c or _cells([y], self.s.cell)[0]
                if c in self.near[i]:
                    self.streak[i] += 1
                    self.seen[i].add(c)
                else:
                    self.streak[i], self.seen[i] = 0, set()
                if self.streak[i] >= self.s.confirm_cloud and len(self.seen[i]) >= self.need[i]:
                    return i
        return -1


def _tail_period(history: list, tight: np.ndarray, s: RecurrenceSettings) -> int:
    """Smallest p <= max_period with each of the last `confirm` points within `tight` of the point
    p before it; 0 if none."""
    n = len(history)
    if n < s.confirm + 1:
        return 0
    h = np.asarray(history[-(s.confirm + s.max_period) :])
    m = h.shape[0]
    for p in range(1, min(s.max_period, m - s.confirm) + 1):
        if np.all(np.abs(h[m - s.confirm :] - h[m - s.confirm - p : m - p]) <= tight):
            return p
    return 0


def _coarser(points: list, s: RecurrenceSettings) -> bool:
    """Whether p points of a tail repeat with a divisor of p to `reading`: a start still converging
    to an orbit whose multiplier is near -1 repeats sooner with twice its period (the error shrinks
    by 1 - mu^2 over two periods, by 1 - mu over one), and is not settled yet."""
    h, p = np.asarray(points), len(points)
    return any(p % k == 0 and np.all(np.abs(h[k:] - h[:-k]) <= s.reading) for k in range(1, p))


def _same(a: FoundAttractor, b: FoundAttractor, s: RecurrenceSettings) -> bool:
    """Whether b, just settled, is the known a (see the module docstring)."""
    if a.period and b.period:
        if max(a.period, b.period) % min(a.period, b.period):
            return False
        tol = np.asarray(s.cell) / 2  # a slowly converging start read at twice the period lies this close
        near = lambda p, q: all(np.any(np.all(np.abs(q - y) <= tol, axis=1)) for y in p)
        return near(a.points, b.points) and near(b.points, a.points)
    if not a.period and not b.period:
        return len(b.cells & a.near_cells()) >= 0.5 * len(b.cells)
    return False


def _settled(system, state, s: RecurrenceSettings):
    """What a start whose points recur in coarse cells sits on: 3 max_period more points, periodic
    if they repeat to `reading`, else `record` points in all, periodic or not by their last
    3 max_period. A periodic reading counts only once the tail repeats to `tight` too: near a
    period doubling a start converging to the period-1 orbit reads as period 2 at the reading's
    tolerance long before it has settled. Returns (attractor or None: not settled yet, the points,
    the end state)."""
    n = 3 * s.max_period
    pts, state = system.iterate(state, n)
    pts = np.asarray(pts, dtype=float)
    p = detect_period(pts, s.reading, max_period=s.max_period)
    if not p and s.record > n:
        more, state = system.iterate(state, s.record - n)
        pts = np.concatenate([pts, np.asarray(more, dtype=float)])
        p = detect_period(pts[-n:], s.reading, max_period=s.max_period)
    if p:
        tail = list(pts[-(s.confirm + s.max_period) :])
        q = _tail_period(tail, np.asarray(s.tight), s)
        settled = q and not _coarser(tail[-q:], s)
        return (_periodic(system, tail[-q:]) if settled else None), pts, state
    impacts, exponent = system.describe(pts[-1], 0)
    return FoundAttractor(0, pts, impacts, exponent, set(_cells(pts, s.cell))), pts, state


def _periodic(system, points) -> FoundAttractor:
    points = np.asarray(points, dtype=float)
    impacts, exponent = system.describe(points[-1], points.shape[0])
    return FoundAttractor(points.shape[0], points, impacts, exponent)


def _settle_one(system, start, known: list, s: RecurrenceSettings):
    """Iterate one start until a known attractor catches it or it settles on a new one.
    Returns (label, iterations, last point, new attractor or None)."""
    catch = _Catcher(known, s)
    tight = np.asarray(s.tight)
    history, visited, recurrences = [], set(), 0
    state = np.asarray(start, dtype=float)
    last = state[: s.dim]
    done = 0
    while done < s.max_iterations:
        n = min(s.block, s.max_iterations - done)
        try:
            pts, state = system.iterate(state, n)
        except Stopped:
            return STOPPED, done, last, None
        for y in np.asarray(pts, dtype=float):
            done += 1
            last = y
            k = catch(y)
            if k >= 0:
                return k + 1, done, y, None
            history.append(y)
            p = _tail_period(history, tight, s)
            if p and not _coarser(history[-p:], s):
                return None, done, y, _periodic(system, history[-p:])
            c = _cells([y], s.cell)[0]
            recurrences = recurrences + 1 if c in visited else 0
            visited.add(c)
            if recurrences >= s.recur:
                try:
                    found, record, state = _settled(system, state, s)
                except Stopped:
                    return STOPPED, done, y, None
                done, last = done + record.shape[0], record[-1]
                if found is not None:
                    return None, done, last, found
                history.extend(record)  # periodic to the reading, not yet settled: go on from there
                recurrences = 0
                break
    return UNRESOLVED, done, last, None


def discover(system, starts, settings: RecurrenceSettings, progress=None, known=None) -> Discovery:
    """Settle every start (rows of `starts`: the map's states) and name what it settles on.

    `known`: attractors found before (e.g. at a neighbouring parameter), tried first and kept in
    the result's list whether or not a start reaches them. `progress(done, total, n_attractors)`
    is called after each start. The starts left unresolved are run once more at the end, with every
    attractor known (their iterations count both runs)."""
    s = settings
    starts = np.asarray(starts, dtype=float)
    if starts.ndim != 2 or starts.shape[0] == 0 or starts.shape[1] < s.dim:
        raise ValueError(f"starts must be an (n, >= {s.dim}) array of states with n >= 1, got shape {starts.shape}")
    if not np.all(np.isfinite(starts[:, : s.dim])):
        raise ValueError("starts must be finite")
    attractors = list(known or [])
    n = starts.shape[0]
    labels = np.zeros(n, dtype=np.int64)
    iterations = np.zeros(n, dtype=np.int64)
    last = np.zeros((n, s.dim))
    for i, y0 in enumerate(starts):
        labels[i], iterations[i], last[i] = _label(system, y0, attractors, s)
        if progress is not None:
            progress(i + 1, n, len(attractors))
    # a start run before the attractor it heads for was known had only the slow recurrence to
    # settle by: once more with every attractor known (its result then does not depend on the order)
    for i in np.flatnonzero(labels == UNRESOLVED):
        labels[i], used, last[i] = _label(system, starts[i], attractors, s)
        iterations[i] += used
    return Discovery(attractors, labels, iterations, last)


def _label(system, start, attractors: list, s: RecurrenceSettings):
    """(label, iterations, last point) of one start; a new attractor is appended to `attractors`."""
    label, used, y, found = _settle_one(system, start, attractors, s)
    if found is not None:
        same = next((j for j, a in enumerate(attractors) if _same(a, found, s)), None)
        if same is None:
            attractors.append(found)
            label = len(attractors)
        else:
            label = same + 1
            attractors[same].cells |= found.cells
    return label, used, np.asarray(y)[: s.dim]
