"""Explicit Dormand-Prince 8(5,3) step with 7th-order dense output, for the 2-D state (x, v).

Everything is written for the two scalar components so the numba-compiled step allocates
nothing: the stage buffer ``K`` (16 x 2) and the interpolant ``F`` (7 x 2) are owned by
the caller and reused. Error norm and step-size rules follow Hairer's DOP853 (as in SciPy),
so a step taken here and one taken by ``scipy.integrate.solve_ivp(method="DOP853")`` from
the same state with the same h agree to rounding (tested).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from . import _dop853_tableau as tab
from .model import accel

A = np.ascontiguousarray(tab.A)
B = np.ascontiguousarray(tab.B)
C = np.ascontiguousarray(tab.C)
E3 = np.ascontiguousarray(tab.E3)
E5 = np.ascontiguousarray(tab.E5)
D = np.ascontiguousarray(tab.D)
N_STAGES = tab.N_STAGES  # 12 stages; K[12] holds f(t + h, y_new) (first-same-as-last)
ORDER = 8
ERROR_EXPONENT = -1.0 / 8.0  # error estimator order 7
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0


@njit(cache=True)
def step(p, phase, t, x, v, ax, h, rtol, atol, K):
    """One DOP853 step from (t, x, v) with x'' = ax at t; fills K[0:13].

    Returns (x_new, v_new, error_norm); error_norm < 1 means the step is acceptable.
    """
    K[0, 0] = v
    K[0, 1] = ax
    for s in range(1, N_STAGES):
        dx = 0.0
        dv = 0.0
        for j in range(s):
            a = A[s, j]
            if a != 0.0:
                dx += a * K[j, 0]
                dv += a * K[j, 1]
        xs = x + h * dx
        vs = v + h * dv
        K[s, 0] = vs
        K[s, 1] = accel(p, phase, t + C[s] * h, xs, vs)
    dx = 0.0
    dv = 0.0
    for j in range(N_STAGES):
        dx += B[j] * K[j, 0]
        dv += B[j] * K[j, 1]
    x1 = x + h * dx
    v1 = v + h * dv
    K[N_STAGES, 0] = v1
    K[N_STAGES, 1] = accel(p, phase, t + h, x1, v1)

    sx = atol + rtol * max(abs(x), abs(x1))
    sv = atol + rtol * max(abs(v), abs(v1))
    e5x = 0.0
    e5v = 0.0
    e3x = 0.0
    e3v = 0.0
    for j in range(N_STAGES + 1):
        e5x += E5[j] * K[j, 0]
        e5v += E5[j] * K[j, 1]
        e3x += E3[j] * K[j, 0]
        e3v += E3[j] * K[j, 1]
    e5 = (e5x / sx) ** 2 + (e5v / sv) ** 2
    e3 = (e3x / sx) ** 2 + (e3v / sv) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return x1, v1, 0.0
    err = abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * 2.0)
    return x1, v1, err


@njit(cache=True)
def new_step_factor(err, rejected):
    """Step-size multiplier after a step with error norm `err` (SciPy/Hairer rule)."""
    if err == 0.0:
        factor = MAX_FACTOR
    else:
        factor = SAFETY * err**ERROR_EXPONENT
    if err < 1.0:
        factor = min(MAX_FACTOR, factor)
        if rejected:
            factor = min(1.0, factor)
    else:
        factor = max(MIN_FACTOR, factor)
    return factor


@njit(cache=True)
def dense_prepare(p, phase, t, x0, v0, x1, v1, h, K, F):
    """Three extra stages and the coefficients F of the 7th-order interpolant of the step."""
    for s in range(N_STAGES + 1, 16):
        dx = 0.0
        dv = 0.0
        for j in range(s):
            a = A[s, j]
            if a != 0.0:
                dx += a * K[j, 0]
                dv += a * K[j, 1]
        xs = x0 + h * dx
        vs = v0 + h * dv
        K[s, 0] = vs
        K[s, 1] = accel(p, phase, t + C[s] * h, xs, vs)
    for c in range(2):
        dy = (x1 - x0) if c == 0 else (v1 - v0)
        F[0, c] = dy
        F[1, c] = h * K[0, c] - dy
        F[2, c] = 2.0 * dy - h * (K[N_STAGES, c] + K[0, c])
        for r in range(4):
            acc = 0.0
            for j in range(16):
                acc += D[r, j] * K[j, c]
            F[3 + r, c] = h * acc


@njit(cache=True)
def dense_eval(F, y0, theta, c):
    """Interpolated component c at fraction theta in [0, 1] of the step (y0: its start value)."""
    y = 0.0
    for i in range(7):
        y += F[6 - i, c]
        if i % 2 == 0:
            y *= theta
        else:
            y *= 1.0 - theta
    return y + y0


@njit(cache=True)
def initial_step(p, phase, t, x, v, ax, order, rtol, atol):
    """Hairer's starting step-size heuristic (one extra right-hand-side evaluation)."""
    sx = atol + abs(x) * rtol
    sv = atol + abs(v) * rtol
    d0 = math.sqrt(((x / sx) ** 2 + (v / sv) ** 2) / 2.0)
    d1 = math.sqrt(((v / sx) ** 2 + (ax / sv) ** 2) / 2.0)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    x1 = x + h0 * v
    v1 = v + h0 * ax
    a1 = accel(p, phase, t + h0, x1, v1)
    d2 = math.sqrt((((v1 - v) / sx) ** 2 + ((a1 - ax) / sv) ** 2) / 2.0) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1)
