"""The periodic regime of paper section 2.1 and the attractors around the grazing (Figs 3a, 4, 5).

Why: the paper's numbers for the periodic attractor at w = 23.03 rad/s (impacts in 100 s,
distinct inter-impact intervals of equal count and their sum; the values are in
:data:`impactosc_study.paper.numbers.PERIODIC`) and its reading of the Fig. 4c spectrum (a
secondary frequency w1 < w and the combinations k w +/- w1, measured by
:func:`impactosc.statistics.spectral_lines.analyse_spectrum`) are recomputed here from a run
file, together with what the model says about them (the sum of the intervals is a whole
number of forcing periods; w1 is a rational fraction of w, i.e. a subharmonic, not a
second incommensurate frequency). :func:`impactosc_study.paper.rows.periodic.periodic_rows` puts them
beside the paper's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactosc.io.files import read_run
from impactosc.statistics import distinct_levels, inter_impact_intervals
from impactosc.statistics.periods import poincare_period
from impactosc.statistics.spectral_lines import SpectrumAnalysis, analyse_spectrum

__all__ = [
    "ImpactMapNumbers",
    "impact_map_numbers",
    "branch_state",
    "run_summary",
]


@dataclass(frozen=True)
class ImpactMapNumbers:
    """Section 2.1 numbers of one impact train.

    n_impacts: impacts in the record; levels/counts: the distinct ISIs (s) and how many of
    each; total: their sum (s); forcing_period: 2 pi / w (s); periods_in_total: total in
    forcing periods (a whole number for a periodic orbit); orbit_period: the nearest whole
    number of forcing periods times 2 pi / w (s).
    """

    n_impacts: int
    levels: tuple
    counts: tuple
    total: float
    forcing_period: float
    periods_in_total: float
    orbit_period: float

    @property
    def counts_equal(self) -> bool:
        return max(self.counts) - min(self.counts) <= 1

    def to_dict(self) -> dict:
        return {
            "n_impacts": self.n_impacts,
            "levels": list(self.levels),
            "counts": list(self.counts),
            "n_levels": len(self.levels),
            "counts_equal": self.counts_equal,
            "total": self.total,
            "forcing_period": self.forcing_period,
            "periods_in_total": self.periods_in_total,
            "orbit_period": self.orbit_period,
        }


def impact_map_numbers(impact_times, omega: float, rel_tol: float = 1e-3) -> ImpactMapNumbers:
    """Impact count, distinct intervals with counts, and their sum against 2 pi / w.

    Why: paper Fig. 5 reads the period of the orbit off the impact map (the sum of the
    distinct intervals); comparing it with the forcing period says which subharmonic the
    orbit is. `rel_tol` is the level-clustering tolerance of
    :func:`impactosc.statistics.distinct_levels` (ISIs of a periodic orbit agree to the
    event-location accuracy, ~1e-10 s, far inside 1e-3 of the largest interval).
    """
    if not (isinstance(omega, (int, float, np.floating)) and math.isfinite(omega) and omega > 0):
        raise ValueError(f"omega must be a finite number > 0 rad/s, got {omega!r}")
    t = np.asarray(impact_times, dtype=float)
    s = inter_impact_intervals(t)
    lev = distinct_levels(s, rel_tol=rel_tol)
    period = 2 * math.pi / omega
    q = lev.total / period
    return ImpactMapNumbers(
        int(t.size),
        tuple(map(float, lev.levels)),
        tuple(map(int, lev.counts)),
        float(lev.total),
        period,
        float(q),
        max(round(q), 1) * period,
    )


def branch_state(sweep, omega: float, abs_tol: float = 1e-9) -> tuple[float, float]:
    """End state (x, v) of a followed branch at the grid point w = omega (at phi = 0).

    Why: the attractor just before grazing (w = 23.05) exists on the branch followed with
    decreasing w; from rest the same w lands on the post-grazing orbit. Restarting from
    this state at t = 0 continues the branch exactly (the state is at a whole period).
    """
    i = int(np.argmin(np.abs(sweep.omega - omega)))
    if abs(sweep.omega[i] - omega) > abs_tol:
        raise ValueError(f"w = {omega} is not a grid point of the branch (nearest {sweep.omega[i]})")
    return float(sweep.x_end[i]), float(sweep.v_end[i])


def run_summary(path, spectrum_options: dict | None = None) -> tuple[dict, SpectrumAnalysis | None]:
    """Section 2.1 numbers of one run file, its attractor, and (if it has a trajectory) its spectrum.

    Returns (numbers, spectrum): numbers holds omega, the recorded span, the impact-map
    numbers (:func:`impact_map_numbers`), impacts per forcing period, the smallest
    near-miss gap (m) and slowest impact (m/s), and the Poincare period; spectrum is
    :func:`analyse_spectrum` of x over the trajectory window (None without one).
    """
    events, attrs, traj = read_run(path)
    omega = float(attrs["omega"])
    span = float(attrs["duration"])
    imp = events["impacts"]
    nm = events.get("near_misses", {"gap": np.empty(0)})
    pc = events["poincare"]
    numbers = {
        "run": str(path),
        "omega": omega,
        "transient": float(attrs["transient"]),
        "duration": span,
        "impact_map": impact_map_numbers(imp["t"], omega).to_dict(),
        "impacts_per_period": imp["t"].size / (span * omega / (2 * math.pi)),
        "min_gap": float(nm["gap"].min()) if nm["gap"].size else math.nan,
        "min_impact_v": float(imp["v"].min()) if imp["v"].size else math.nan,
        "poincare_period": poincare_period(pc["x"], pc["v"]),
    }
    spectrum = None
    if traj is not None:
        dt = float(traj["t"][1] - traj["t"][0])
        spectrum = analyse_spectrum(traj["x"], dt, omega, **(spectrum_options or {}))
        numbers["spectrum"] = {k: v for k, v in spectrum.to_dict().items() if k not in ("omega_axis", "amplitude")}
    return numbers, spectrum
