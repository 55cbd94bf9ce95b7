"""Pseudo-arclength continuation of periodic orbits in w, through folds.

Why: natural continuation (:func:`bifurcation_points.follow`, w stepped, the orbit shot from the
previous one) fails at a fold, where the branch turns back in w and M - I is singular. Here the
branch is a curve in (x, v, w), followed by its arclength (Keller): a predictor along the unit
tangent, a Newton corrector on the orbit condition plus the constraint of staying on the plane
normal to the tangent at the predicted point. The bordered Jacobian is regular at a fold, so the
branch passes it; the fold shows as a sign change of the tangent's w component (and of
det(M - I)).

Coordinates are scaled (x / 1 mm, v / 0.1 m/s, w / 1 rad/s) so that one arclength unit weighs
the three alike.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from impactosc.dynamics.shooting import (
    DEFAULT_STEP,
    SCALE,
    PeriodicOrbit,
    ShootingError,
    _multipliers,
    central_difference,
    monodromy,
    stroboscopic_map,
)

__all__ = ["BranchPoint", "branch_points", "continue_branch", "folds", "locate_fold", "switch_at_period_doubling"]

W_SCALE = 1.0  # rad/s: the scale of w in the arclength
W_STEP = 1e-5  # rad/s: difference step of dP/dw (fourth order, as the monodromy)


@dataclass(frozen=True)
class BranchPoint:
    """One point of a continued branch: the orbit, the unit tangent (scaled x, v, w) there."""

    orbit: PeriodicOrbit
    tangent: np.ndarray


def _residual_and_jacobian(z, n_periods, params, step):
    """F(z) = (P^N(y) - y) / SCALE at scaled z = (x, v, w), and dF/dz (2 x 3)."""
    y, w = z[:2] * SCALE, z[2] * W_SCALE
    image, M = monodromy(y, w, n_periods, params, step=step)
    dP_dw = central_difference(lambda s: stroboscopic_map(y, w + s, n_periods, params), W_STEP)
    J = np.empty((2, 3))
    J[:, :2] = (M - np.eye(2)) * SCALE[None, :] / SCALE[:, None]
    J[:, 2] = dP_dw * W_SCALE / SCALE
    return (image - y) / SCALE, J, M


def _tangent(J, previous=None):
    """Unit null vector of the 2 x 3 Jacobian, oriented along `previous` (or towards +w)."""
    t = np.linalg.svd(J)[2][-1]
    ref = previous if previous is not None else np.array([0.0, 0.0, 1.0])
    return t if float(t @ ref) >= 0 else -t


def _point(z, J, M, n_periods, previous_tangent, newton_steps, residual):
    y, w = z[:2] * SCALE, z[2] * W_SCALE
    orbit = PeriodicOrbit(
        float(w), int(n_periods), float(y[0]), float(y[1]), M, _multipliers(M), residual, newton_steps
    )
    return BranchPoint(orbit, _tangent(J, previous_tangent))


def _scaled(orbit: PeriodicOrbit) -> np.ndarray:
    return np.array([orbit.x0 / SCALE[0], orbit.v0 / SCALE[1], orbit.omega / W_SCALE])


def _correct(prev: BranchPoint, h: float, params, step, tol, max_newton) -> BranchPoint | None:
    """The branch point at arclength h from `prev` along its tangent (Newton on the orbit
    condition and the plane normal to the tangent); None if Newton does not converge."""
    t, n = prev.tangent, prev.orbit.n_periods
    z_pred = _scaled(prev.orbit) + h * t
    z = z_pred.copy()
    for k in range(1, max_newton + 1):
        F, J, M = _residual_and_jacobian(z, n, params, step)
        dz = np.linalg.solve(np.vstack([J, t]), -np.concatenate([F, [float(t @ (z - z_pred))]]))
        z = z + dz
        if np.max(np.abs(dz)) < tol:
            F, J, M = _residual_and_jacobian(z, n, params, step)
            return _point(z, J, M, n, t, k, float(np.max(np.abs(F))))
    return None


def branch_points(
    start: PeriodicOrbit,
    ds: float,
    params=None,
    *,
    direction: float = 1.0,
    tol: float = 1e-10,
    max_newton: int = 8,
    step: float = DEFAULT_STEP,
    min_ds: float = 1e-6,
    tangent=None,
):
    """The points of the branch through `start`, `start` first, each at arclength up to `ds`
    (scaled units) from the last, without end: the caller stops (:func:`continue_branch`, or
    a segment's own end conditions). The first step goes towards increasing w for direction
    = +1, decreasing for -1, or along `tangent` (scaled x, v, w) where the branch through
    `start` is not unique (branch switching: :func:`switch_at_period_doubling`). A corrector
    that does not converge halves the step (below `min_ds`: ShootingError); a quick one lets
    it grow back by 1.5 up to `ds`."""
    if ds <= 0:
        raise ValueError(f"ds must be > 0, got {ds}")
    z = _scaled(start)
    F, J, M = _residual_and_jacobian(z, start.n_periods, params, step)
    toward = np.array([0.0, 0.0, float(np.sign(direction) or 1.0)])
    point = _point(z, J, M, start.n_periods, toward, 0, float(np.max(np.abs(F))))
    if tangent is not None:
        point = BranchPoint(point.orbit, np.asarray(tangent, float) / np.linalg.norm(tangent))
    yield point
    h = ds
    while True:
        nxt = _correct(point, h, params, step, tol, max_newton)
        if nxt is None:
            h /= 2
            if h < min_ds:
                raise ShootingError(f"arclength continuation stuck at w = {point.orbit.omega:.8f} (ds < {min_ds:g})")
            continue
        point = nxt
        yield point
        h = min(ds, 1.5 * h) if nxt.orbit.newton_steps <= 3 else h


def continue_branch(
    start: PeriodicOrbit, ds: float, n_points: int, params=None, *, w_range=(0.0, math.inf), **options
) -> list[BranchPoint]:
    """Up to `n_points` points of the branch through `start` (:func:`branch_points`, whose
    options it takes), stopping after the first point whose w leaves `w_range`."""
    if n_points < 1:
        raise ValueError(f"n_points must be >= 1, got {n_points}")
    branch = []
    for point in branch_points(start, ds, params, **options):
        branch.append(point)
        if len(branch) >= n_points or not w_range[0] <= point.orbit.omega <= w_range[1]:
            break
    return branch


def folds(branch: list[BranchPoint]) -> list[tuple[BranchPoint, BranchPoint]]:
    """Neighbouring points between which the tangent's w component changes sign: a fold."""
    return [(a, b) for a, b in itertools.pairwise(branch) if a.tangent[2] * b.tangent[2] < 0]


def locate_fold(a: BranchPoint, b: BranchPoint, params=None, *, tol: float = 1e-9, step: float = DEFAULT_STEP):
    """The fold between two neighbouring branch points (:func:`folds`): bisection on the
    arclength from `a` until the tangent's w component changes sign within `tol` (scaled
    units; w at a fold varies quadratically along the branch, so its error is far smaller).
    Returns the branch point there."""
    lo, hi = 0.0, float(np.linalg.norm(_scaled(b.orbit) - _scaled(a.orbit))) * 1.5
    sign = np.sign(a.tangent[2])
    best = a
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        p = _correct(a, mid, params, step, 1e-12, 10)
        if p is None:
            raise ShootingError(
                f"fold location: no corrector convergence at arclength {mid:g} from w = {a.orbit.omega}"
            )
        best = p
        if np.sign(p.tangent[2]) == sign:
            lo = mid
        else:
            hi = mid
    return best


def switch_at_period_doubling(orbit: PeriodicOrbit, params=None, *, ds: float = 1e-3, **options) -> list[BranchPoint]:
    """Branch switching at a period doubling: `orbit` has a multiplier at -1 (located by
    bifurcation_points.locate), so as an orbit of 2N periods it has one at +1 and the doubled
    branch leaves it along that multiplier's eigenvector, at constant w to first order. The
    first two points of that branch (arclength `ds`, scaled), from which continue_branch goes on."""
    mu, vectors = np.linalg.eig(orbit.monodromy)
    e = np.real(vectors[:, int(np.argmin(np.abs(mu + 1)))]) / SCALE
    doubled = PeriodicOrbit(orbit.omega, 2 * orbit.n_periods, orbit.x0, orbit.v0, orbit.monodromy @ orbit.monodromy,
                            _multipliers(orbit.monodromy @ orbit.monodromy), orbit.residual, 0)  # fmt: skip
    return continue_branch(doubled, ds, 2, params, tangent=np.array([e[0], e[1], 0.0]), **options)
