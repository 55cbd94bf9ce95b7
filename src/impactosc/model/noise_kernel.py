"""The forcing of a noisy run, compiled for the core: the realised noise evaluated at any time t.

Why a module of its own: the model's right-hand side (:mod:`impactosc.model.equations`) reads the
forcing here only when a run has noise, so that a noise-free run keeps its arithmetic. The realised
noise travels in the parameter array ``p`` behind the model's parameters (``p`` is then longer than
N_PARAMS: :func:`harmonic_forcing` is the one test of it), as piecewise polynomials on uniform cells
(:mod:`impactosc.model.noise_realisation` fills them):

    p[N_PARAMS + NZ_MOTOR_CELLS], p[N_PARAMS + NZ_MOTOR_DT]    cells and spacing of theta (0 cells: none)
    p[N_PARAMS + NZ_FORCE_CELLS], p[N_PARAMS + NZ_FORCE_DT]    the same for the random force
    then MOTOR_DEGREE + 1 coefficients per cell of theta, then FORCE_DEGREE + 1 per cell of the force,
    lowest power first, in s = t - i dt on cell i = floor(t / dt).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.model.parameters import N_PARAMS, P_M0E, P_OMEGA

NZ_MOTOR_CELLS, NZ_MOTOR_DT, NZ_FORCE_CELLS, NZ_FORCE_DT = range(4)
NZ_HEADER = 4
#: Degree of the splines through the draws (odd: every draw is a knot); theta is the antiderivative of one
SPLINE_DEGREE = 7
MOTOR_DEGREE, FORCE_DEGREE = SPLINE_DEGREE + 1, SPLINE_DEGREE


@njit(cache=True, inline="always")
def harmonic_forcing(p):
    """Is the forcing today's m0e w^2 sin(w t), without noise? A closed-form piece holds only then."""
    return p.shape[0] == N_PARAMS


@njit(cache=True, inline="always")
def _cell(p, n, dt, t):
    """(cell i = floor(t / dt), clamped to the realised cells; s = t - i dt)."""
    i = int(math.floor(t / dt))
    if i < 0:
        i = 0
    elif i > n - 1:
        i = n - 1
    return i, t - i * dt


@njit(cache=True)
def _poly2(p, start, degree, s):
    """Value, first and second derivative in s of the polynomial p[start : start + degree + 1]."""
    y = p[start + degree]
    d1 = 0.0
    d2 = 0.0
    for k in range(degree - 1, -1, -1):
        d2 = d2 * s + 2.0 * d1
        d1 = d1 * s + y
        y = y * s + p[start + k]
    return y, d1, d2


@njit(cache=True, inline="always")  # a call in every right-hand side cost noise-free runs ~10 %, inlined ~4 %
def noisy_forcing(p, t):
    """The unbalance's force with the motor's phase jitter, m0e (phi'^2 sin phi - phi'' cos phi),
    phi = w t + theta(t), plus the random force on the cart, at time t."""
    base = N_PARAMS
    w = p[P_OMEGA]
    phi = w * t
    dphi = w
    ddphi = 0.0
    n = int(p[base + NZ_MOTOR_CELLS])
    start = base + NZ_HEADER
    if n > 0:
        i, s = _cell(p, n, p[base + NZ_MOTOR_DT], t)
        th, dth, ddth = _poly2(p, start + i * (MOTOR_DEGREE + 1), MOTOR_DEGREE, s)
        phi += th
        dphi += dth
        ddphi = ddth
    f = p[P_M0E] * (dphi * dphi * math.sin(phi) - ddphi * math.cos(phi))
    start += n * (MOTOR_DEGREE + 1)
    n = int(p[base + NZ_FORCE_CELLS])
    if n > 0:
        i, s = _cell(p, n, p[base + NZ_FORCE_DT], t)
        f += _poly2(p, start + i * (FORCE_DEGREE + 1), FORCE_DEGREE, s)[0]
    return f


@njit(cache=True)
def noise_values(p, t):
    """(theta, speed deviation theta', theta'', random force) at each time of the array t: the
    realised noise as the core sees it, for checks and plots."""
    out = np.zeros((t.shape[0], 4))
    base = N_PARAMS
    n_m = int(p[base + NZ_MOTOR_CELLS])
    n_f = int(p[base + NZ_FORCE_CELLS])
    start_f = base + NZ_HEADER + n_m * (MOTOR_DEGREE + 1)
    for j in range(t.shape[0]):
        if n_m > 0:
            i, s = _cell(p, n_m, p[base + NZ_MOTOR_DT], t[j])
            out[j, 0], out[j, 1], out[j, 2] = _poly2(p, base + NZ_HEADER + i * (MOTOR_DEGREE + 1), MOTOR_DEGREE, s)
        if n_f > 0:
            i, s = _cell(p, n_f, p[base + NZ_FORCE_DT], t[j])
            out[j, 3] = _poly2(p, start_f + i * (FORCE_DEGREE + 1), FORCE_DEGREE, s)[0]
    return out
