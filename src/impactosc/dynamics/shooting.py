"""Periodic orbits of model BC by shooting, and their Floquet multipliers.

Why: the brute-force diagrams see only stable orbits and locate a bifurcation to the sweep's
grid step. A period-N orbit is a fixed point of the N-th iterate of the stroboscopic map
P: (x, v) at phase w t = 2 pi i  ->  (x, v) one forcing period later. Newton on
F(y) = P^N(y) - y finds it, stable or not, to the solver's tolerance; the eigenvalues of the
Jacobian M = dP^N/dy (the monodromy matrix) are its Floquet multipliers, which say whether it
is stable (all |mu| < 1) and how it loses stability (mu = -1 period doubling, +1 fold, a
complex pair on the unit circle Neimark-Sacker).

M comes from fourth-order central differences of P^N, each evaluation a run of the core at a
tight tolerance (rtol 1e-12). The map is smooth where the orbit's impacts are transversal: the
contact force is continuous at the obstacle (it grows like (x - xI)^1.5), so no saltation
matrix is needed; the differences must stay inside one such smooth region: DEFAULT_STEP, 1e-4
of the state's scale (0.1 um, 10 um/s), is far below the micrometre penetrations and far above
the level where the solver's error shows. Measured on model BC's period-1 orbits at w = 25 and
30: M agrees to 2e-8 for steps 1e-3 and 1e-5 of the scale, drifts by 2e-7 at 1e-6 and 1e-6 at
1e-7 (the solver's error divided by the step); the period doubling at w = 37.28 located with
steps 1e-3 and 1e-4 agrees to 4e-10 rad/s. On the linear oscillator, where M is known in
closed form, the multipliers agree to 1e-7 (tests/test_shooting.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactosc.core.layout import S_V, S_X
from impactosc.core.simulation import simulate
from impactosc.model.parameters import ModelParams

__all__ = ["PeriodicOrbit", "ShootingError", "stroboscopic_map", "monodromy", "shoot"]

RTOL = 1e-12  # the core's tolerances for every map evaluation of the shooting
ATOL = 1e-14
SCALE = np.array([1e-3, 1e-1])  # m, m/s: the sizes of x and v on model BC's orbits
DEFAULT_STEP = 1e-4  # finite-difference step, relative to SCALE


class ShootingError(RuntimeError):
    """Newton did not converge; the message says where it stopped."""


@dataclass(frozen=True)
class PeriodicOrbit:
    """A fixed point y = (x, v) of P^N at phase 0 (t = 0 mod 2 pi / w), its monodromy matrix
    and Floquet multipliers (largest modulus first)."""

    omega: float  # rad/s
    n_periods: int  # N: forcing periods per orbit
    x0: float  # m
    v0: float  # m/s
    monodromy: np.ndarray  # dP^N/dy at the fixed point, 2 x 2
    multipliers: np.ndarray  # eigenvalues of monodromy, complex, by decreasing modulus
    residual: float  # |P^N(y) - y| / SCALE at the returned point (max over components)
    newton_steps: int

    @property
    def stable(self) -> bool:
        return bool(np.all(np.abs(self.multipliers) < 1.0))


def stroboscopic_map(y, omega: float, n_periods: int = 1, params: ModelParams | None = None, *, rtol=RTOL, atol=ATOL):
    """P^N(y): the state (x, v) after `n_periods` forcing periods from y at phase 0."""
    if int(n_periods) < 1:
        raise ValueError(f"n_periods must be >= 1, got {n_periods}")
    res = simulate(
        omega, 0.0, n_periods * 2 * math.pi / omega, x0=float(y[0]), v0=float(y[1]),
        params=params, rtol=rtol, atol=atol, record=(),
    )  # fmt: skip
    return np.array([res.final_state[S_X], res.final_state[S_V]])


def monodromy(y, omega: float, n_periods: int = 1, params: ModelParams | None = None, *, step=DEFAULT_STEP, **tol):
    """(P^N(y), M): the map and its Jacobian by fourth-order central differences (steps h and
    2h, h = `step` x SCALE per component: truncation error O(h^4), so the curvature of the
    map does not show and h can stay well above the solver's noise)."""
    y = np.asarray(y, float)
    image = stroboscopic_map(y, omega, n_periods, params, **tol)
    M = np.empty((2, 2))
    for j in range(2):
        unit = np.eye(2)[j]
        M[:, j] = central_difference(
            lambda s, unit=unit: stroboscopic_map(y + s * unit, omega, n_periods, params, **tol), step * SCALE[j]
        )
    return image, M


def central_difference(f, h: float):
    """f'(0) to fourth order: (8 (f(h) - f(-h)) - (f(2h) - f(-2h))) / 12h."""
    return (8 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12 * h)


def _multipliers(M: np.ndarray) -> np.ndarray:
    mu = np.linalg.eigvals(M).astype(complex)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def shoot(
    guess,
    omega: float,
    n_periods: int = 1,
    params: ModelParams | None = None,
    *,
    tol: float = 1e-10,
    max_steps: int = 20,
    step: float = DEFAULT_STEP,
    rtol: float = RTOL,
    atol: float = ATOL,
) -> PeriodicOrbit:
    """Newton on P^N(y) - y from `guess` = (x, v) until the step is below `tol` x SCALE.

    Each step solves (M - I) dy = -(P^N(y) - y) with M from :func:`monodromy`; a step that
    would leave the region the guess came from (more than 10 x SCALE) is cut to that length.
    Raises ShootingError when `max_steps` are spent, or when M - I is singular (a multiplier
    at +1: a fold, where the orbit is not locally unique)."""
    y = np.asarray(guess, float).copy()
    if y.shape != (2,) or not np.all(np.isfinite(y)):
        raise ValueError(f"guess must be a finite (x, v), got {guess!r}")
    for k in range(1, int(max_steps) + 1):
        image, M = monodromy(y, omega, n_periods, params, step=step, rtol=rtol, atol=atol)
        F = image - y
        try:
            dy = np.linalg.solve(M - np.eye(2), -F)
        except np.linalg.LinAlgError:
            raise ShootingError(f"w = {omega}: M - I is singular at {y} (a multiplier at +1)") from None
        longest = np.max(np.abs(dy) / SCALE)
        if longest > 10.0:
            dy *= 10.0 / longest
        y = y + dy
        if np.max(np.abs(dy) / SCALE) < tol:
            image, M = monodromy(y, omega, n_periods, params, step=step, rtol=rtol, atol=atol)
            residual = float(np.max(np.abs(image - y) / SCALE))
            return PeriodicOrbit(
                float(omega), int(n_periods), float(y[0]), float(y[1]), M, _multipliers(M), residual, k
            )
    raise ShootingError(
        f"w = {omega}, N = {n_periods}: no convergence in {max_steps} Newton steps "
        f"(last step {longest:.2e} of SCALE at x = {y[0]:.6e} m, v = {y[1]:.6e} m/s)"
    )
