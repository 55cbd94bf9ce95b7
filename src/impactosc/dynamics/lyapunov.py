"""Lyapunov exponents of the stroboscopic map P (one forcing period), through the core.

Why: the paper calls the w = 40.86 regime chaotic; the exponents measure it. The tangent map of
one period is P's Jacobian at the current Poincare point, taken by central differences of the
core (the same construction as the shooting's monodromy, which agrees with the variational
equations to 1e-9 of |M| on impacting orbits: periodic_orbits.variational). Differences of the
map step over the model's hard spots instead of integrating through them: the infinite slope
d|v|^n3/dv at the deepest penetration and the friction band's slope T/eps are inside the core's
pieces (its own variables there), and the map's derivative is finite. The tangent vectors are
re-orthonormalised every period (QR, Benettin et al. 1980), and the exponents are the means of
log |R_ii|.

Checks: the forced linear oscillator has both exponents -c/(2m) per second (closed form); the
sum of the two is the mean of log |det J| per period, which Liouville's formula makes the time
average of the divergence -(c + friction slope + contact damping slope)/m of the vector field:
measured independently by the variational equations (periodic_orbits.variational, SciPy) on the
same Poincare points (tests/test_lyapunov.py, the workflow's lyapunov table).

A restitution law's Poincare point inside a contact is (x, v, v0) (shooting's module docstring):
the tangent map there has a v0 column, and its image a v0 row when it lies inside one. The
tangent vectors then live in the plane of states the flow reaches, so they are carried in the
state's components (2 or 3) and the QR keeps two columns: R is 2 x 2 and its diagonal still
gives both exponents (the third, v0's, is -inf: it is forgotten at the contact's exit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactosc.core.simulation import end_state, simulate, start_of
from impactosc.dynamics.shooting import SCALE, SCALE_V0, as_state, monodromy_columns, stroboscopic_map

__all__ = [
    "LyapunovRun",
    "exponents_along",
    "kaplan_yorke",
    "largest_exponent",
    "lyapunov_spectrum",
    "map_jacobian",
    "settle",
]

STEP = 1e-5  # difference step relative to SCALE (10 nm, 1 um/s): far above the core's error at rtol 1e-12
RTOL, ATOL = 1e-12, 1e-14


def map_jacobian(y, omega: float, params=None, *, step: float = STEP, rtol: float = RTOL, atol: float = ATOL):
    """(P(y), dP/dy) by second-order central differences (five runs of one period; seven from a
    point inside a restitution contact, whose v0 is a column: shooting.monodromy_columns)."""
    y = np.asarray(y, float)
    image = stroboscopic_map(y, omega, 1, params, rtol=rtol, atol=atol)
    scale, rows = monodromy_columns(y, image)
    J = np.empty((len(rows), len(scale)))
    for j in range(len(scale)):
        e = np.zeros(len(y))
        e[j] = step * scale[j]
        plus = stroboscopic_map(y + e, omega, 1, params, rtol=rtol, atol=atol)
        minus = stroboscopic_map(y - e, omega, 1, params, rtol=rtol, atol=atol)
        J[:, j] = (plus[: len(rows)] - minus[: len(rows)]) / (2 * e[j])
    return image, J


def settle(y, omega: float, seconds: float, params=None, *, rtol: float = RTOL, atol: float = ATOL) -> np.ndarray:
    """The Poincare point after whole forcing periods covering `seconds` from y (phase 0), as
    shooting.as_state gives it (with v0 for a restitution law)."""
    y = as_state(y, params)
    periods = max(0, math.ceil(seconds * omega / (2 * math.pi) - 1e-9))
    if periods == 0:
        return y
    run = simulate(omega, 0.0, periods * 2 * math.pi / omega, **start_of(y), params=params,
                   rtol=rtol, atol=atol, record=())  # fmt: skip
    return end_state(run)[: len(y)]


def _scaled(J: np.ndarray) -> np.ndarray:
    """J in units of SCALE (x / 1 mm, v / 0.1 m/s, v0 / 0.1 m/s). The exponents do not depend on
    the units, but a finite run's estimate carries a term ~ log(condition of the eigenvectors) / n:
    in SI units (m against m/s, a factor ~w apart) that term is ~7 / n, scaled it is ~1 / n."""
    scale = np.append(SCALE, SCALE_V0)
    return J * scale[None, : J.shape[1]] / scale[: J.shape[0], None]


def _tangent_step(J: np.ndarray, Q: np.ndarray):
    """(Q', R): the tangent vectors Q carried by the scaled J and re-orthonormalised. Q has the
    rows of the point's components; a v0 component the point lacks enters as 0 (the tangents of a
    point in free flight do not move v0), one the image lacks is dropped with J's row."""
    Q = np.vstack([Q, np.zeros((J.shape[1] - Q.shape[0], 2))])[: J.shape[1]]
    return np.linalg.qr(_scaled(J) @ Q)


@dataclass(frozen=True)
class LyapunovRun:
    """Exponents of the stroboscopic map along one run of `n` periods from `start`."""

    omega: float
    start: np.ndarray  # the Poincare point the tangent run started from
    exponents: np.ndarray  # (2,), per forcing period (largest first)
    running: np.ndarray  # (n, 2): the estimate after each period
    log_det: np.ndarray  # (n,): log |det J| of each period (its mean is the exponents' sum)
    points: np.ndarray  # (n, 2): the Poincare point at the start of each period

    @property
    def per_second(self) -> np.ndarray:
        return self.exponents * self.omega / (2 * math.pi)

    @property
    def kaplan_yorke(self) -> float:
        return kaplan_yorke(self.exponents)


def lyapunov_spectrum(y0, omega: float, n_periods: int, params=None, *, step=STEP, rtol=RTOL, atol=ATOL, log=None):
    """Both exponents of P by QR re-orthonormalisation every period, from the Poincare point y0
    (on the attractor: settle first). `log(k, estimate)` is called every 10 % of the run."""
    if int(n_periods) < 1:
        raise ValueError(f"n_periods must be >= 1, got {n_periods}")
    if len(np.asarray(y0)) not in (2, 3) or not np.all(np.isfinite(np.asarray(y0, float)[:2])):
        raise ValueError(f"y0 must be a finite (x, v) or (x, v, v0), got {y0!r}")
    y = as_state(y0, params)
    n = int(n_periods)
    Q, sums = np.eye(2), np.zeros(2)
    running, log_det, points = np.empty((n, 2)), np.empty(n), np.empty((n, len(y)))
    for k in range(n):
        points[k] = y
        y, J = map_jacobian(y, omega, params, step=step, rtol=rtol, atol=atol)
        Q, R = _tangent_step(J, Q)
        d = np.abs(np.diag(R))
        sums += np.log(d)
        # the area's growth: det J itself, or R's inside a contact (J is not square there)
        log_det[k] = math.log(abs(np.linalg.det(J))) if J.shape == (2, 2) else float(np.log(d).sum())
        running[k] = sums / (k + 1)
        if log and (k + 1) % max(1, n // 10) == 0:
            log(k + 1, running[k])
    order = np.argsort(-running[-1])
    return LyapunovRun(float(omega), as_state(y0, params), running[-1][order], running[:, order], log_det, points)


def exponents_along(points, omega: float, params=None, *, step=STEP, rtol=RTOL, atol=ATOL) -> np.ndarray:
    """Both exponents per period from the Jacobians at given Poincare points (consecutive points
    of one run): the tangent numerics (step, tolerance) compared on the same points, which a
    rerun cannot do (a chaotic run with other numerics follows another trajectory)."""
    Q, sums = np.eye(2), np.zeros(2)
    for y in np.asarray(points, float):
        _, J = map_jacobian(as_state(y, params), omega, params, step=step, rtol=rtol, atol=atol)
        Q, R = _tangent_step(J, Q)
        sums += np.log(np.abs(np.diag(R)))
    return np.sort(sums / len(points))[::-1]


def largest_exponent(
    y0, omega: float, n_periods: int, params=None, *, n_discard: int = 0, step=STEP, rtol=1e-10, atol=1e-12
) -> float:
    """The largest exponent per period from one tangent vector (two runs per period: the map
    and a forward difference along the vector, renormalised every period), counted after
    `n_discard` periods in which the vector turns towards the most unstable direction (without
    them a short run near a bifurcation, where lambda1 is near 0, reads the vector's transient
    growth as a positive exponent). Cheaper than the spectrum, for every w of a sweep."""
    y = as_state(y0, params)
    q = np.array([1.0, 1.0]) / math.sqrt(2)  # in units of SCALE
    total = 0.0
    for k in range(int(n_discard) + int(n_periods)):
        image = stroboscopic_map(y, omega, 1, params, rtol=rtol, atol=atol)
        scale, rows = monodromy_columns(y, image)
        q = np.append(q, np.zeros(len(scale) - len(q)))[: len(scale)]  # as in _tangent_step
        e = np.zeros(len(y))
        e[: len(scale)] = step * q * scale
        moved = stroboscopic_map(y + e, omega, 1, params, rtol=rtol, atol=atol)
        d = (moved - image)[: len(rows)] / (step * rows)
        growth = float(np.linalg.norm(d))
        if not math.isfinite(growth) or growth == 0.0:
            return math.nan
        if k >= n_discard:
            total += math.log(growth)
        q, y = d / growth, image
    return total / int(n_periods)


def kaplan_yorke(exponents) -> float:
    """Kaplan-Yorke dimension of a two-dimensional map's attractor: 0 for a stable orbit
    (lambda1 < 0), 1 + lambda1 / |lambda2| when lambda1 >= 0 > lambda1 + lambda2, else 2."""
    l1, l2 = sorted(np.asarray(exponents, float), reverse=True)
    if l1 < 0:
        return 0.0
    if l1 + l2 >= 0:
        return 2.0
    return 1.0 + l1 / abs(l2)
