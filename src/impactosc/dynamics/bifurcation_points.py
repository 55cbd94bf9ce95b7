"""Bifurcation points of periodic orbits in w, located by test functions of the monodromy matrix.

Why: a sweep sees a period doubling only as a change of the Poincare period between two grid
points (0.02 rad/s apart); the multipliers of the orbit itself change sign smoothly through the
bifurcation, so a root of a test function locates it to the accuracy of the multipliers.

Test functions of M (2 x 2, multipliers mu1, mu2), each real and changing sign at its bifurcation:
  period doubling  det(M + I) = (1 + mu1)(1 + mu2)   a multiplier through -1
  fold             det(M - I) = (1 - mu1)(1 - mu2)   a multiplier through +1
  Neimark-Sacker   det(M) - 1 = |mu|^2 - 1           a complex pair through the unit circle
(the last changes sign also where two real multipliers have a product of 1; it counts only
where the pair is complex, which :func:`locate` checks).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.dynamics.shooting import PeriodicOrbit, shoot

__all__ = ["TEST_FUNCTIONS", "crossings", "follow", "locate"]

TEST_FUNCTIONS = {
    "period_doubling": lambda M: float(np.linalg.det(M + np.eye(2))),
    "fold": lambda M: float(np.linalg.det(M - np.eye(2))),
    "neimark_sacker": lambda M: float(np.linalg.det(M)) - 1.0,
}


def follow(omegas, guess, n_periods: int = 1, params=None, **shoot_options) -> list[PeriodicOrbit]:
    """The orbit at each w of `omegas` in turn, each shot from the previous one (natural-parameter
    continuation: enough away from folds, where the orbit is unique and varies smoothly)."""
    orbits, y = [], list(guess)
    for w in omegas:
        orbit = shoot(y, float(w), n_periods, params, **shoot_options)
        orbits.append(orbit)
        y = orbit.state
    return orbits


def locate(
    kind: str, lo, hi, params=None, *, tol: float = 1e-9, solve=None, **shoot_options
) -> tuple[float, PeriodicOrbit]:
    """Bisect w between two orbits of one branch whose test function `kind` has opposite signs,
    down to a bracket of `tol` rad/s; returns (w at the bracket's middle, the orbit at the end
    nearer the root). Each new w is shot from the bracket end on its side; `solve(w, near)`
    replaces that shot (anything with .omega and .monodromy: a map with a known answer)."""
    if kind not in TEST_FUNCTIONS:
        raise ValueError(f"kind must be one of {sorted(TEST_FUNCTIONS)}, got {kind!r}")
    if solve is None:
        if lo.n_periods != hi.n_periods:
            raise ValueError(f"the two orbits have different periods ({lo.n_periods}, {hi.n_periods})")

        def solve(w, near):
            return shoot(near.state, w, lo.n_periods, params, **shoot_options)

    g = TEST_FUNCTIONS[kind]
    g_lo, g_hi = g(lo.monodromy), g(hi.monodromy)
    if not g_lo * g_hi < 0:
        raise ValueError(f"{kind}: no sign change between w = {lo.omega} ({g_lo:.3g}) and w = {hi.omega} ({g_hi:.3g})")
    while abs(hi.omega - lo.omega) > tol:
        mid = solve(0.5 * (lo.omega + hi.omega), lo if abs(g_lo) < abs(g_hi) else hi)
        g_mid = g(mid.monodromy)
        if g_mid * g_lo < 0:
            hi, g_hi = mid, g_mid
        else:
            lo, g_lo = mid, g_mid
    best = lo if abs(g_lo) < abs(g_hi) else hi
    if kind == "neimark_sacker" and not np.any(np.abs(np.linalg.eigvals(best.monodromy).imag) > 0):
        raise ValueError(f"neimark_sacker: the multipliers at w = {best.omega} are real")
    return 0.5 * (lo.omega + hi.omega), best


def crossings(orbits: list[PeriodicOrbit], kind: str) -> list[tuple[PeriodicOrbit, PeriodicOrbit]]:
    """Pairs of neighbouring orbits of a followed branch between which `kind`'s test function
    changes sign (the brackets to pass to :func:`locate`)."""
    g = TEST_FUNCTIONS[kind]
    values = [g(o.monodromy) for o in orbits]
    return [
        (orbits[i], orbits[i + 1])
        for i in range(len(orbits) - 1)
        if values[i] * values[i + 1] < 0 and math.isfinite(values[i] * values[i + 1])
    ]
