"""The grazing of a periodic orbit as a continuation event: where its smallest near-miss gap
reaches zero.

Why: at a grazing the orbit touches the obstacle with zero velocity; there the stroboscopic map
is not smooth (a square-root singularity of the new low-velocity impact), so no test function
of the monodromy matrix sees it. Along a branch followed in w, the smallest gap between the
obstacle and the orbit's free-flight maxima falls linearly to zero; past it the near miss has
become an impact. Bisection on "the orbit still has that near miss" locates the grazing.
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.core.simulate import simulate
from impactosc.dynamics.shooting import ATOL, DEFAULT_STEP, RTOL, SCALE, PeriodicOrbit, ShootingError, shoot

__all__ = ["locate_orbit_grazing", "orbit_events"]


def orbit_events(orbit: PeriodicOrbit, params=None) -> dict:
    """Impacts per orbit and the smallest near-miss gap (m; inf without a near miss) of one
    period of the orbit, from the core run over it."""
    run = simulate(
        orbit.omega, 0.0, orbit.n_periods * 2 * math.pi / orbit.omega, x0=orbit.x0, v0=orbit.v0,
        params=params, rtol=RTOL, atol=ATOL, record=("impacts", "near_misses"),
    )  # fmt: skip
    gaps = run.events["near_misses"]["gap"]
    return {"impacts": int(run.events["impacts"]["t"].size), "min_gap": float(gaps.min()) if gaps.size else math.inf}


def locate_orbit_grazing(
    a: PeriodicOrbit, b: PeriodicOrbit, params=None, *, gap_floor: float = 1e-9, max_steps: int = 30
):
    """w where the smallest near-miss gap of a branch reaches zero, from two of its orbits
    (`a`, `b`, both with the near miss): secant steps on gap(w) = 0, each new orbit shot from
    the last, until the gap is below `gap_floor`; then the parabola through the last three
    points gives the grazing. Near the obstacle each orbit is shot with difference steps of
    1e-3 of the current gap, so that the monodromy's perturbed orbits miss the obstacle too
    (with the default 0.1 um they reach it once the gap is below 0.2 um, and the branch's
    Newton stalls). On model BC's period-1 branch, floors 1e-6, 1e-7, 1e-8 and 1e-9 m give
    23.04412235, 23.044122337, 23.044122336048 and 23.044122336048 rad/s, and two different
    starting pairs agree to 2e-8, 1e-9, 4e-13 and 4e-15 rad/s at those floors.
    Returns (w at zero gap, the orbit nearest to it, its gap in m)."""
    pts = [(o, orbit_events(o, params)["min_gap"]) for o in (a, b)]
    if not all(math.isfinite(g) and g > 0 for _, g in pts):
        raise ValueError("both orbits must have a near miss (a finite, positive gap) to follow to a grazing")
    for _ in range(max_steps):
        (o1, g1), (o2, g2) = pts[-2], pts[-1]
        w_zero = o2.omega - g2 * (o2.omega - o1.omega) / (g2 - g1)
        if g2 < gap_floor:
            return _quadratic_zero(pts[-3:], w_zero), o2, g2
        # aim at half the floor's gap rather than at zero, so the next orbit stays shootable
        w_next = o2.omega + (w_zero - o2.omega) * (1 - 0.5 * gap_floor / g2)
        # difference steps well inside the gap, so that the monodromy's perturbed orbits miss
        # the obstacle too (1e-3 of it: the map is still resolved, the core's error is 1e-14 m)
        step = min(DEFAULT_STEP, 1e-3 * g2 / SCALE[0])
        o3 = shoot([o2.x0, o2.v0], w_next, o2.n_periods, params, step=step)
        g3 = orbit_events(o3, params)["min_gap"]
        if not (math.isfinite(g3) and g3 > 0):
            raise ShootingError(f"the near miss vanished at w = {w_next} before the gap fell below {gap_floor} m")
        pts.append((o3, g3))
    raise ShootingError(f"grazing: the gap did not fall below {gap_floor} m in {max_steps} steps")


def _quadratic_zero(pts, w_linear: float) -> float:
    """Root nearest `w_linear` of the parabola through (w, gap) of the last three points (the
    straight line's root where there are only two)."""
    if len(pts) < 3:
        return w_linear
    w = np.array([o.omega for o, _ in pts])
    roots = np.roots(np.polyfit(w - w_linear, [g for _, g in pts], 2))
    real = roots[np.isreal(roots)].real
    return float(w_linear + real[np.argmin(np.abs(real))]) if real.size else w_linear
