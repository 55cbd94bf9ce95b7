"""The oscillator's stroboscopic map (phase 0) as the map that :mod:`.recurrence` iterates.

Why a module: the discovery is written for any map (the tests give it maps whose attractors are
known); this is the one place that turns it into runs of the core: a block of n forcing periods is
one run from the state at phase 0 (inside a restitution contact the state carries the contact's
onset velocity, ``core.simulation.end_state``), a stalled run is :class:`.recurrence.Stopped`, and
an attractor is described by its impacts per period and its largest Lyapunov exponent per period
(:func:`.lyapunov.largest_exponent`).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.core.simulation import DEFAULT_ATOL, DEFAULT_RTOL, StallError, end_state, simulate, start_of
from impactosc.dynamics.lyapunov import largest_exponent
from impactosc.dynamics.recurrence import RecurrenceSettings, Stopped
from impactosc.model.parameters import ModelParams
from impactosc.statistics.periods import impacts_per_orbit

__all__ = ["StroboscopicMap", "oscillator_settings"]

#: periods of the exponent's run after `EXPONENT_DISCARD` in which the tangent vector turns to the
#: most unstable direction; 200 give lambda1 of the chaotic scene within about 0.05 per period of a
#: long run's, enough to tell chaos (about 0.3 there) from a stable orbit (below -0.1 off bifurcations)
EXPONENT_PERIODS = 200
EXPONENT_DISCARD = 20
#: impacts are counted over this many forcing periods at least (impacts_per_orbit: whole orbits, K >= 3)
IMPACT_PERIODS = 60


def oscillator_settings(**counts) -> RecurrenceSettings:
    """Settings in the oscillator's units (m, m/s); `counts` override the iteration counts
    (max_period 33: the longest period the sweeps' reading tells in its 100 recorded points).

    box 1 um, 20 um/s: the basins' box, measured inside both basins at w = 23.05 (:mod:`.basins`);
    tight 1e-9 m, 1e-7 m/s: a settled orbit repeats to 1e-13 m, and a start repeating to 1e-9 m
    with |mu| <= 0.99 lies within 0.1 um of its orbit; reading 1 um, 0.1 mm/s: the sweeps'
    reading (config bifurcation.reading); cells 0.1 mm x 4 mm/s: the chaotic set at w = 40.3
    spans 9 mm and 0.2 m/s and covers about 250 of them, so a start on it recurs within a few
    hundred periods (with cells half as wide, 454 and often not within 2000 periods)."""
    return RecurrenceSettings(box=(1e-6, 2e-5), tight=(1e-9, 1e-7), reading=(1e-6, 1e-4), cell=(1e-4, 4e-3), **counts)


class StroboscopicMap:
    """P at forcing w: ``iterate(state, n)`` runs n periods from a state (x, v[, contact v0]) at
    phase 0 and returns the n Poincare points (x, v) and the end state."""

    def __init__(self, omega: float, params: ModelParams | None = None, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
        if not (isinstance(omega, (int, float, np.floating)) and math.isfinite(omega) and omega > 0):
            raise ValueError(f"omega must be a finite number > 0 rad/s, got {omega!r}")
        self.omega, self.params, self.rtol, self.atol = float(omega), params or ModelParams(), rtol, atol
        self.period = 2 * math.pi / self.omega

    def _run(self, state, n: int, record):
        try:
            return simulate(self.omega, 0.0, n * self.period, **start_of(state), params=self.params,
                            rtol=self.rtol, atol=self.atol, record=record)  # fmt: skip
        except StallError as e:
            raise Stopped(str(e)) from None

    def iterate(self, state, n: int):
        run = self._run(state, n, ("poincare",))
        pc = run.events["poincare"]
        points, end = np.column_stack([pc["x"], pc["v"]]), end_state(run)
        if pc["x"].size == n - 1 and (n == 1 or pc["t"][-1] < (n - 0.5) * self.period):
            # the section at the run's end time itself can fall an ulp outside the run (seen at
            # w = 43.75): the end state is that section's point
            points = np.vstack([points, end[:2]])
        if points.shape[0] != n:
            raise RuntimeError(f"the core gave {pc['x'].size} Poincare points for a run of {n} forcing periods")
        return points, end

    def describe(self, point, period: int):
        """(impacts per orbit of `period` periods, or per period when 0; largest exponent per period)."""
        span = period * max(3, math.ceil(IMPACT_PERIODS / max(period, 1))) if period else IMPACT_PERIODS
        t = self._run(point, span, ("impacts",)).events["impacts"]["t"]
        impacts = impacts_per_orbit(t, self.period, span, period) if period else t.size / span
        exponent = largest_exponent(point, self.omega, EXPONENT_PERIODS, self.params, n_discard=EXPONENT_DISCARD)
        return float(impacts), float(exponent)
