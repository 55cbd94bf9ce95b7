"""Pseudo-arclength continuation of periodic orbits in w, through folds.

Why: natural continuation (:func:`bifurcation_points.follow`, w stepped, the orbit shot from the
previous one) fails at a fold, where the branch turns back in w and M - I is singular. Here the
branch is a curve in (x, v, w), followed by its arclength (Keller): a predictor along the unit
tangent, a Newton corrector on the orbit condition plus the constraint of staying on the plane
normal to the tangent at the predicted point. The bordered Jacobian is regular at a fold, so the
branch passes it; the fold shows as a sign change of the tangent's w component (and of
det(M - I)).

Coordinates are scaled (x / 1 mm, v / 0.1 m/s, w / 1 rad/s) so that one arclength unit weighs
the three alike. Where the section point lies inside a restitution law's contact the corrector
also solves for the contact's onset velocity v0 (a fourth unknown, after w, with its own fixed
point equation: shooting's module docstring), while the arclength and the tangent stay in
(x, v, w): v0 follows the branch as a function of its point.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from impactosc.dynamics.shooting import (
    DEFAULT_STEP,
    SCALE,
    SCALE_V0,
    PeriodicOrbit,
    ShootingError,
    _multipliers,
    central_difference,
    monodromy,
    reduced,
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


def _state(z):
    """(y, its scale, w) of scaled z = (x, v, w) or (x, v, w, v0)."""
    scale = np.append(SCALE, [SCALE_V0] * (len(z) - 3))
    return np.append(z[:2], z[3:]) * scale, scale, z[2] * W_SCALE


def _residual_and_jacobian(z, n_periods, params, step):
    """F(z) = (P^N(y) - y) / SCALE at scaled z = (x, v, w) (or (x, v, w, v0) inside a contact),
    and dF/dz (2 x 3, or 3 x 4)."""
    y, scale, w = _state(z)
    k = len(y)
    image, M = monodromy(y, w, n_periods, params, step=step)
    if M.shape != (k, k):
        raise ShootingError(f"w = {w}: the orbit's section point enters or leaves a contact within one step")
    dP_dw = central_difference(lambda s: stroboscopic_map(y, w + s, n_periods, params), W_STEP)
    J = np.empty((k, k + 1))
    J[:, [0, 1, 3][:k]] = (M - np.eye(k)) * scale[None, :] / scale[:, None]
    J[:, 2] = dP_dw * W_SCALE / scale
    return (image - y) / scale, J, M


def _tangent(J, previous=None, *, dims=None):
    """Unit null vector of the Jacobian, oriented along `previous` (or towards +w); of its first
    `dims` components only (the branch's (x, v, w) without v0 inside a contact) when given."""
    t = np.linalg.svd(J)[2][-1]
    if dims is not None and dims < t.size:
        t = t[:dims] / np.linalg.norm(t[:dims])
    ref = previous if previous is not None else np.array([0.0, 0.0, 1.0])
    return t if float(t @ ref) >= 0 else -t


def _point(z, J, M, n_periods, previous_tangent, newton_steps, residual):
    y, _, w = _state(z)
    M2 = reduced(M)
    orbit = PeriodicOrbit(
        float(w), int(n_periods), float(y[0]), float(y[1]), M2, _multipliers(M2), residual, newton_steps,
        float(y[2]) if len(y) > 2 else math.nan,
    )  # fmt: skip
    return BranchPoint(orbit, _tangent(J, previous_tangent, dims=3))


def _scaled(orbit: PeriodicOrbit) -> np.ndarray:
    z = np.array([orbit.x0 / SCALE[0], orbit.v0 / SCALE[1], orbit.omega / W_SCALE])
    return z if math.isnan(orbit.contact_v0) else np.append(z, orbit.contact_v0 / SCALE_V0)


def _correct(prev: BranchPoint, h: float, params, step, tol, max_newton) -> BranchPoint | None:
    """The branch point at arclength h from `prev` along its tangent (Newton on the orbit
    condition and the plane normal to the tangent); None if Newton does not converge."""
    t, n = prev.tangent, prev.orbit.n_periods
    z_pred = _scaled(prev.orbit)
    z_pred[:3] += h * t  # v0 (inside a contact) from the last point: Newton solves for it
    z = z_pred.copy()
    border = np.append(t, np.zeros(len(z) - 3))  # the plane normal to the tangent, in (x, v, w)
    for k in range(1, max_newton + 1):
        F, J, M = _residual_and_jacobian(z, n, params, step)
        dz = np.linalg.solve(np.vstack([J, border]), -np.concatenate([F, [float(t @ (z[:3] - z_pred[:3]))]]))
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
    lo, hi = 0.0, float(np.linalg.norm(_scaled(b.orbit)[:3] - _scaled(a.orbit)[:3])) * 1.5
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
                            _multipliers(orbit.monodromy @ orbit.monodromy), orbit.residual, 0,
                            orbit.contact_v0)  # fmt: skip
    return continue_branch(doubled, ds, 2, params, tangent=np.array([e[0], e[1], 0.0]), **options)
