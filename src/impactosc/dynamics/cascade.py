"""A period-doubling cascade followed orbit by orbit: each doubling located, the doubled branch
switched to and followed to its own doubling, and the ratios of successive intervals.

Why: the paper reads the cascade that closes towards the chaos at w = 40.86 off brute-force
diagrams (37.25, 38.99-39.01, 39.48, 39.55 rad/s). Near a doubling the multiplier is close to
-1, transients decay slowly and a sweep's reading lags; the orbits themselves locate each
doubling to ~1e-9 rad/s, and the ratios of successive intervals can be set against
Feigenbaum's 4.669.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.dynamics.arclength import continue_branch, switch_at_period_doubling
from impactosc.dynamics.bifurcation_points import TEST_FUNCTIONS, locate
from impactosc.dynamics.shooting import PeriodicOrbit, ShootingError, shoot

__all__ = ["Doubling", "cascade", "feigenbaum_ratios"]

FEIGENBAUM_DELTA = 4.669201609
MAX_SWITCH_STEPS = 200  # arclength steps after a switch before giving up on the doubled branch


@dataclass(frozen=True)
class Doubling:
    """Period n_periods -> 2 n_periods at w (rad/s); the orbit there (a multiplier at -1)."""

    omega: float
    n_periods: int
    orbit: PeriodicOrbit


def _next_doubling(orbit: PeriodicOrbit, dw: float, w_stop: float, params, tol) -> Doubling | None:
    """Follow `orbit`'s branch in steps of dw until det(M + I) changes sign; locate it there."""
    g = TEST_FUNCTIONS["period_doubling"]
    prev = orbit
    for w in np.arange(orbit.omega + dw, w_stop, dw):
        cur = shoot([prev.x0, prev.v0], float(w), prev.n_periods, params)
        if g(prev.monodromy) * g(cur.monodromy) < 0:
            w_pd, at = locate("period_doubling", prev, cur, params, tol=tol)
            return Doubling(w_pd, cur.n_periods, at)
        prev = cur
    return None


def cascade(
    orbit: PeriodicOrbit, levels: int, *, dw: float = 0.02, shrink: float = 4.0, w_stop: float = 40.86,
    params=None, tol: float = 1e-9, log=None,
) -> list[Doubling]:  # fmt: skip
    """Up to `levels` successive doublings above `orbit` (a stable orbit below the first), each
    branch followed in w steps of dw / shrink^k (the intervals shrink by about 4.7 per level)."""
    found = []
    for k in range(levels):
        d = _next_doubling(orbit, dw / shrink**k, w_stop, params, tol)
        if d is None:
            break
        found.append(d)
        if log:
            log(f"period {d.n_periods} -> {2 * d.n_periods} at w = {d.omega:.10f} rad/s")
        # onto the doubled branch, and along it by arclength (small steps: its w grows only
        # quadratically there) until it is one w step past the doubling, then in w again
        point = switch_at_period_doubling(d.orbit, params)[-1]
        for _ in range(MAX_SWITCH_STEPS):
            if point.orbit.omega >= d.omega + dw / shrink ** (k + 1):
                break
            point = continue_branch(point.orbit, 0.005, 2, params, tangent=point.tangent)[-1]
        else:  # the doubled branch does not move to higher w (a subcritical doubling)
            raise ShootingError(
                f"the period-{2 * d.n_periods} branch born at w = {d.omega:.10f} does not go to higher w"
            )
        orbit = point.orbit
    return found


def feigenbaum_ratios(doublings) -> list[float]:
    """(w_k - w_{k-1}) / (w_{k+1} - w_k) for successive doublings (Doublings or their w):
    tends to 4.669 in a Feigenbaum cascade."""
    w = [getattr(d, "omega", d) for d in doublings]
    return [(w[k] - w[k - 1]) / (w[k + 1] - w[k]) for k in range(1, len(w) - 1)]
