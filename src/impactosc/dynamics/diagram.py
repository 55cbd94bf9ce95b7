"""Reading a bifurcation diagram: periods, impacts per period, and the transitions between them.

Why: a diagram drawn as a cloud of points shows period doublings, chaos and grazing to the
eye only; this module turns the sweep data into numbers that a table can hold and a test
can check. Along a sweep (:class:`impactosc.dynamics.sweep.SweepResult`) every w gets

- the period p of its Poincare sequence in forcing periods (:func:`impactosc.statistics.periods.detect_period`, 0 when
  the sequence does not repeat within the record: chaotic, quasi-periodic or unsettled),
- the impacts q per orbit period (:func:`impactosc.statistics.periods.impacts_per_orbit`) and so the impact rate q/p,
- the number of distinct inter-impact intervals (the branches of the ISI diagram).

Runs of equal (p, q) form segments; between consecutive segments of at least
``min_points`` w values :func:`transitions` names what changed: a period doubling
(p -> 2p with the same impact rate), an impact-adding jump (the impact rate q/p changes),
the edge of a non-periodic window, or another period change. An impact-adding jump whose
lower-rate side carries a near miss whose gap closes linearly on the jump is a grazing
bifurcation (:func:`find_grazings`; the gap line is
:func:`impactosc.dynamics.grazing.extrapolate_gap_zero`, shared with the grazing figure).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import asdict, dataclass, field
from fractions import Fraction

import numpy as np

from impactosc.dynamics.grazing import extrapolate_gap_zero
from impactosc.dynamics.sweep import OK
from impactosc.statistics import distinct_levels
from impactosc.statistics.periods import FAILED, NONPERIODIC, detect_period, impacts_per_orbit

__all__ = [
    "BranchTable",
    "classify_sweep",
    "Segment",
    "segments",
    "Transition",
    "transitions",
    "Grazing",
    "find_grazings",
    "differing_windows",
    "SweepReading",
    "read_sweep",
]


@dataclass
class BranchTable:
    """The reading of one sweep, per w in sweep order.

    period: forcing periods (NONPERIODIC = 0, FAILED = -1); impacts: per orbit period
    (-1 unless periodic); rate: impacts per forcing period over the whole record (NaN if
    failed); n_isi_levels: distinct ISIs (0 with fewer than 2 impacts); min_gap: smallest
    near-miss gap (m, NaN if none).
    """

    omega: np.ndarray
    period: np.ndarray
    impacts: np.ndarray
    rate: np.ndarray
    n_isi_levels: np.ndarray
    min_gap: np.ndarray

    def __len__(self) -> int:
        return int(self.omega.size)

    @property
    def direction(self) -> str:
        return "increasing" if self.omega.size < 2 or self.omega[1] > self.omega[0] else "decreasing"

    @property
    def step(self) -> float:
        """Grid spacing (rad/s)."""
        return float(np.median(np.abs(np.diff(self.omega)))) if self.omega.size > 1 else math.nan

    def key(self, i: int) -> tuple:
        """What a segment has in common: ('periodic', p, q), ('nonperiodic',) or ('failed',)."""
        p = int(self.period[i])
        if p == FAILED:
            return ("failed",)
        if p == NONPERIODIC:
            return ("nonperiodic",)
        return ("periodic", p, int(self.impacts[i]))

    def rows(self) -> list[dict]:
        """One dict per w, for a CSV."""
        return [
            {
                "omega": f"{self.omega[i]:.6f}",
                "period": int(self.period[i]),
                "impacts": int(self.impacts[i]),
                "impacts_per_forcing_period": f"{self.rate[i]:.6f}",
                "n_isi_levels": int(self.n_isi_levels[i]),
                "min_gap_m": f"{self.min_gap[i]:.6e}",
            }
            for i in range(len(self))
        ]


def classify_sweep(
    result, x_tol: float = 1e-6, v_tol: float = 1e-4, isi_tol: float = 1e-4, max_period: int | None = None
) -> BranchTable:
    """Period, impacts per period and ISI levels of every w of a sweep.

    x_tol (m) and v_tol (m/s) are the Poincare repetition tolerances (defaults 1 um and
    0.1 mm/s: far above the ~1e-13 m to which settled orbits repeat, far below the
    spacing of distinct branch points); isi_tol (s) groups equal ISIs.
    """
    n = len(result)
    n_rec = result.poincare_x.shape[1]
    period = np.full(n, FAILED, dtype=np.int64)
    impacts = np.full(n, -1, dtype=np.int64)
    rate = np.full(n, np.nan)
    levels = np.zeros(n, dtype=np.int64)
    for i in range(n):
        if result.status[i] != OK:
            continue
        pts = np.column_stack([result.poincare_x[i], result.poincare_v[i]])
        period[i] = detect_period(pts, (x_tol, v_tol), max_period=max_period)
        t = result.impacts(i)
        rate[i] = t.size / n_rec
        if period[i] > 0:
            impacts[i] = impacts_per_orbit(t, 2 * math.pi / result.omega[i], n_rec, int(period[i]))
        if t.size > 2:
            levels[i] = distinct_levels(np.diff(t), rel_tol=0.0, abs_tol=isi_tol).n_levels
    return BranchTable(
        omega=result.omega.copy(),
        period=period,
        impacts=impacts,
        rate=rate,
        n_isi_levels=levels,
        min_gap=result.min_gap.copy(),
    )


@dataclass(frozen=True)
class Segment:
    """A run of consecutive w with the same key; indices [start, stop) into the table."""

    start: int
    stop: int
    omega_first: float
    omega_last: float
    key: tuple

    @property
    def n_points(self) -> int:
        return self.stop - self.start

    @property
    def kind(self) -> str:
        return self.key[0]

    @property
    def period(self) -> int:
        return self.key[1] if self.kind == "periodic" else (NONPERIODIC if self.kind == "nonperiodic" else FAILED)

    @property
    def impacts(self) -> int:
        return self.key[2] if self.kind == "periodic" else -1

    @property
    def rate(self) -> Fraction | None:
        """Impacts per forcing period q/p, exact (None unless periodic)."""
        return Fraction(self.impacts, self.period) if self.kind == "periodic" else None

    def label(self) -> str:
        if self.kind == "periodic":
            return f"period {self.period}, {self.impacts} impact{'s' if self.impacts != 1 else ''}"
        return self.kind

    def to_dict(self) -> dict:
        return {
            "omega_first": round(self.omega_first, 6),
            "omega_last": round(self.omega_last, 6),
            "n_points": self.n_points,
            "kind": self.kind,
            "period": self.period,
            "impacts": self.impacts,
            "impacts_per_forcing_period": str(self.rate) if self.rate is not None else "",
        }


def segments(table: BranchTable) -> list[Segment]:
    """Maximal runs of equal key, in sweep order."""
    out = []
    start = 0
    for i in range(1, len(table) + 1):
        if i == len(table) or table.key(i) != table.key(start):
            out.append(Segment(start, i, float(table.omega[start]), float(table.omega[i - 1]), table.key(start)))
            start = i
    return out


@dataclass(frozen=True)
class Transition:
    """A change between two settled segments, met in sweep order.

    omega_before / omega_after: last w of the segment before and first w of the one after
    (the bifurcation lies between them, up to any unsettled w values in between);
    kind: 'period doubling', 'impact adding', 'non-periodic boundary' or 'period change';
    detail: e.g. 'period 2 -> 1' or 'impacts per forcing period 1 -> 4/3'.
    """

    kind: str
    omega_before: float
    omega_after: float
    before: str
    after: str
    detail: str
    grazing: dict = field(default_factory=dict)

    @property
    def omega(self) -> float:
        """Midpoint estimate of the transition w (rad/s)."""
        return 0.5 * (self.omega_before + self.omega_after)

    @property
    def width(self) -> float:
        return abs(self.omega_after - self.omega_before)

    def to_dict(self) -> dict:
        d = {k: v for k, v in asdict(self).items() if k != "grazing"}
        d.update(omega=round(self.omega, 6), width=round(self.width, 6))
        g = self.grazing
        d["grazing_omega_zero"] = f"{g['omega_zero']:.4f}" if g else ""
        return d


def _classify(a: Segment, b: Segment) -> tuple[str, str]:
    if a.kind == "periodic" and b.kind == "periodic":
        if a.rate != b.rate:
            return "impact adding", f"impacts per forcing period {a.rate} -> {b.rate}"
        hi, lo = max(a.period, b.period), min(a.period, b.period)
        if hi == 2 * lo:
            return "period doubling", f"period {a.period} -> {b.period}"
        return "period change", f"period {a.period} -> {b.period}"
    return "non-periodic boundary", f"{a.label()} -> {b.label()}"


def transitions(table: BranchTable, min_points: int = 2) -> list[Transition]:
    """Transitions between consecutive segments of at least `min_points` w (sweep order).

    Shorter segments (a w or two that has not settled near a bifurcation, abandoned w
    values) are skipped, so the bracket of a transition spans them.
    """
    if not isinstance(min_points, (int, np.integer)) or min_points < 1:
        raise ValueError(f"min_points must be an integer >= 1, got {min_points!r}")
    settled = [s for s in segments(table) if s.n_points >= min_points and s.kind != "failed"]
    out = []
    for a, b in itertools.pairwise(settled):
        if a.key == b.key:  # the same state on both sides of an unsettled stretch
            continue
        kind, detail = _classify(a, b)
        out.append(Transition(kind, a.omega_last, b.omega_first, a.label(), b.label(), detail))
    return out


@dataclass(frozen=True)
class Grazing:
    """An impact-adding transition explained by a near miss closing on the obstacle.

    transition: the impact-adding Transition; omega_zero: where the straight line through
    the last `n_fit` near-miss gaps of the lower-rate side reaches zero (rad/s); slope (m
    per rad/s) and rms (m) of that line; gap_last (m): the smallest gap seen on the grid.
    """

    transition: Transition
    omega_zero: float
    slope: float
    rms: float
    gap_last: float

    @property
    def bracket(self) -> tuple[float, float]:
        w = sorted((self.transition.omega_before, self.transition.omega_after))
        return w[0], w[1]


def find_grazings(table: BranchTable, min_points: int = 2, n_fit: int = 5) -> list[Grazing]:
    """Impact-adding transitions whose lower-rate side ends on a closing near miss.

    Criterion: the last `n_fit` w of the lower-rate segment next to the transition all
    have a near miss, and the straight line through their gaps reaches zero within one
    grid step of the transition bracket (a near miss turning into a contact).
    """
    segs = [s for s in segments(table) if s.n_points >= min_points and s.kind != "failed"]
    found = []
    for tr in transitions(table, min_points):
        if tr.kind != "impact adding":
            continue
        a = next(s for s in segs if s.omega_last == tr.omega_before)
        b = next(s for s in segs if s.omega_first == tr.omega_after)
        low, at_end = (a, True) if a.rate < b.rate else (b, False)
        idx = np.arange(low.start, low.stop)
        idx = idx[-n_fit:] if at_end else idx[:n_fit][::-1]  # ordered towards the transition
        if idx.size < n_fit:
            continue
        gaps = table.min_gap[idx]
        if not np.all(np.isfinite(gaps) & (gaps > 0)):
            continue
        fit = extrapolate_gap_zero(table.omega[idx], gaps, n_fit)
        lo, hi = sorted((tr.omega_before, tr.omega_after))
        step = table.step
        if lo - step <= fit.omega_zero <= hi + step:
            g = {"omega_zero": fit.omega_zero, "slope": fit.slope, "rms": fit.rms, "gap_last": float(gaps[-1])}
            tr_g = Transition(tr.kind, tr.omega_before, tr.omega_after, tr.before, tr.after, tr.detail, g)
            found.append(Grazing(tr_g, fit.omega_zero, fit.slope, fit.rms, float(gaps[-1])))
    return found


def differing_windows(a: BranchTable, b: BranchTable, min_points: int = 2) -> list[tuple[float, float]]:
    """w intervals where two sweeps over the same range settle on different attractors.

    Why: a one-way diagram hides coexisting attractors; where the increasing and the
    decreasing sweep disagree (different period or impacts per period, or periodic against
    non-periodic) there is hysteresis. Each w of `a` inside the common range is compared
    with the nearest w of `b`; runs of at least `min_points` disagreeing w of `a` are
    returned as (w_lo, w_hi). Failed w are ignored.
    """
    if not isinstance(min_points, (int, np.integer)) or min_points < 1:
        raise ValueError(f"min_points must be an integer >= 1, got {min_points!r}")
    lo = max(a.omega.min(), b.omega.min())
    hi = min(a.omega.max(), b.omega.max())
    ia = np.flatnonzero((a.omega >= lo) & (a.omega <= hi))
    ia = ia[np.argsort(a.omega[ia])]
    jb = np.abs(b.omega[None, :] - a.omega[ia, None]).argmin(axis=1)
    differ = []
    for i, j in zip(ia, jb):
        ka, kb = a.key(int(i)), b.key(int(j))
        differ.append(ka != kb and "failed" not in (ka[0], kb[0]))
    out = []
    k = 0
    while k < len(ia):
        if not differ[k]:
            k += 1
            continue
        m = k
        while m < len(ia) and differ[m]:
            m += 1
        if m - k >= min_points:
            out.append((float(a.omega[ia[k]]), float(a.omega[ia[m - 1]])))
        k = m
    return out


# ------------------------------------------------------------------ reading for the tables


@dataclass
class SweepReading:
    """Everything read from one sweep: per-w table, segments, transitions, grazings."""

    name: str
    direction: str
    table: BranchTable
    segments: list
    transitions: list
    grazings: list
    failed_omegas: list

    def summary(self) -> dict:
        """JSON-ready digest (figures mark the transitions from it; tables list it)."""
        graz = {(g.transition.omega_before, g.transition.omega_after): g for g in self.grazings}
        trans = []
        for t in self.transitions:
            g = graz.get((t.omega_before, t.omega_after))
            trans.append((g.transition if g else t).to_dict() | {"is_grazing": g is not None})
        return {
            "name": self.name,
            "direction": self.direction,
            "n_omega": len(self.table),
            "omega_step": self.table.step,
            "failed_omegas": self.failed_omegas,
            "per_w": {
                "omega": self.table.omega.tolist(),
                "period": self.table.period.tolist(),
                "impacts": self.table.impacts.tolist(),
            },
            "segments": [s.to_dict() for s in self.segments],
            "transitions": trans,
            "grazings": [
                {
                    "omega_before": g.transition.omega_before,
                    "omega_after": g.transition.omega_after,
                    "omega_zero": g.omega_zero,
                    "slope": g.slope,
                    "rms": g.rms,
                    "gap_last": g.gap_last,
                    "detail": g.transition.detail,
                }
                for g in self.grazings
            ],
        }


def read_sweep(result, name: str, x_tol=1e-6, v_tol=1e-4, isi_tol=1e-4, min_points=2, n_fit=5) -> SweepReading:
    """Classify a sweep and find its segments, transitions and grazings."""
    table = classify_sweep(result, x_tol=x_tol, v_tol=v_tol, isi_tol=isi_tol)
    return SweepReading(
        name=name,
        direction=table.direction,
        table=table,
        segments=segments(table),
        transitions=transitions(table, min_points),
        grazings=find_grazings(table, min_points, n_fit),
        failed_omegas=[float(w) for w in table.omega[table.period == FAILED]],
    )
