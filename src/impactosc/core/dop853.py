"""Explicit Dormand-Prince 8(5,3) step with 7th-order dense output, for the state (t, x, v).

The independent variable s is time itself on ordinary pieces (mode TIME) or a variable in
which a piece that starts or ends at a singular point of the vector field is smooth (the
vector field in each variable: :mod:`impactosc.core.vector_fields`). Everything is written
for the three scalar components so the numba-compiled step allocates nothing: the stage buffer ``K`` (16 x 3) and the interpolant ``F`` (7 x 3)
are owned by the caller and reused. Error norm and step-size rules follow Hairer's DOP853
(as in SciPy).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core import tableau as tab
from impactosc.core.layout import TIME, UVEL
from impactosc.core.vector_fields import deriv, deriv_stop

A = np.ascontiguousarray(tab.A)
B = np.ascontiguousarray(tab.B)
C = np.ascontiguousarray(tab.C)
E3 = np.ascontiguousarray(tab.E3)
E5 = np.ascontiguousarray(tab.E5)
D = np.ascontiguousarray(tab.D)
N_STAGES = tab.N_STAGES  # 12 stages; K[12] holds the derivative at the step end (FSAL)
ORDER = 8
ERROR_EXPONENT = -1.0 / 8.0  # error estimator order 7
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0


@njit(cache=True, inline="always")  # inlined: a plain call cost 18 % on the chaotic scene
def _stage(p, mode, field, sgn, q, s, tref, t, x, v, h, st, K, stop=False):
    """Stage st of the step from (t, x, v): K[st] from the stages before it."""
    dt = 0.0
    dx = 0.0
    dv = 0.0
    for j in range(st):
        a = A[st, j]
        if a != 0.0:
            dt += a * K[j, 0]
            dx += a * K[j, 1]
            dv += a * K[j, 2]
    if stop:  # a literal of each caller: numba prunes the other branch
        K[st, 0], K[st, 1], K[st, 2] = deriv_stop(p, field, t + h * dt, x + h * dx, v + h * dv)
    else:
        K[st, 0], K[st, 1], K[st, 2] = deriv(
            p, mode, field, sgn, q, s + C[st] * h, tref, t + h * dt, x + h * dx, v + h * dv
        )


@njit(cache=True)
def step(p, mode, field, sgn, q, s, tref, t, x, v, d0t, d0x, d0v, h, rtol, atol, K):
    """One DOP853 step of size h in s from (t, x, v) with derivative d0 there; fills K[0:13].

    Returns (t1, x1, v1, error_norm). In TIME mode the time component is exact (t1 = t + h)
    and left out of the error norm; otherwise it is tau (see ``vector_fields.deriv``). In the
    |v|^n3 variable v is integrated and kept in the error norm although it is known exactly
    (sgn w^q): its error estimate is what holds the steps next to v = 0, where the embedded
    estimate of t's error, on the lattice w^(i + j q), falls short of the true one (without it the
    chaotic work-precision scene's impacts came 1e-9 s off SciPy at rtol 1e-13).
    """
    return _step(p, mode, field, sgn, q, s, tref, t, x, v, d0t, d0x, d0v, h, rtol, atol, K, False)


@njit(cache=True)
def step_stop(p, field, t, x, v, d0t, d0x, d0v, h, rtol, atol, K):
    """step in time behind a contact law's second stop (field STOP), whose force it adds. Apart
    from step so that step's stages carry no test of it: a test in every stage's right-hand side
    cost model BC's chaotic scene 7-10 % (core_speed against the revision before)."""
    return _step(p, TIME, field, 0.0, 1.0, t, 0.0, t, x, v, d0t, d0x, d0v, h, rtol, atol, K, True)


@njit(cache=True, inline="always")
def _step(p, mode, field, sgn, q, s, tref, t, x, v, d0t, d0x, d0v, h, rtol, atol, K, stop):
    """The body of step (stop: a literal, True behind a second stop)."""
    K[0, 0] = d0t
    K[0, 1] = d0x
    K[0, 2] = d0v
    for st in range(1, N_STAGES):
        _stage(p, mode, field, sgn, q, s, tref, t, x, v, h, st, K, stop)
    dt = 0.0
    dx = 0.0
    dv = 0.0
    for j in range(N_STAGES):
        dt += B[j] * K[j, 0]
        dx += B[j] * K[j, 1]
        dv += B[j] * K[j, 2]
    t1 = t + h if mode == TIME else t + h * dt
    x1 = x + h * dx
    v1 = v + h * dv
    if stop:
        K[N_STAGES, 0], K[N_STAGES, 1], K[N_STAGES, 2] = deriv_stop(p, field, t1, x1, v1)
    else:
        K[N_STAGES, 0], K[N_STAGES, 1], K[N_STAGES, 2] = deriv(p, mode, field, sgn, q, s + h, tref, t1, x1, v1)

    st_ = atol + rtol * max(abs(t), abs(t1))
    sx = atol + rtol * max(abs(x), abs(x1))
    sv = atol + rtol * max(abs(v), abs(v1))
    e5t = 0.0
    e5x = 0.0
    e5v = 0.0
    e3t = 0.0
    e3x = 0.0
    e3v = 0.0
    for j in range(N_STAGES + 1):
        e5t += E5[j] * K[j, 0]
        e5x += E5[j] * K[j, 1]
        e5v += E5[j] * K[j, 2]
        e3t += E3[j] * K[j, 0]
        e3x += E3[j] * K[j, 1]
        e3v += E3[j] * K[j, 2]
    n = 2.0
    e5 = (e5x / sx) ** 2 + (e5v / sv) ** 2
    e3 = (e3x / sx) ** 2 + (e3v / sv) ** 2
    if mode != TIME:
        e5 += (e5t / st_) ** 2
        e3 += (e3t / st_) ** 2
        n = 3.0
    if e5 == 0.0 and e3 == 0.0:
        return t1, x1, v1, 0.0
    err = abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
    if not (err == err):  # NaN from an invalid transformed piece: reject hard
        err = math.inf
    return t1, x1, v1, err


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
def dense_prepare(p, mode, field, sgn, q, s, tref, t0, x0, v0, t1, x1, v1, h, K, F):
    """Three extra stages and the coefficients F of the 7th-order interpolant of the step."""
    _dense_prepare(p, mode, field, sgn, q, s, tref, t0, x0, v0, t1, x1, v1, h, K, F, False)


@njit(cache=True)
def dense_prepare_stop(p, field, t0, x0, v0, t1, x1, v1, h, K, F):
    """dense_prepare of a step_stop."""
    _dense_prepare(p, TIME, field, 0.0, 1.0, t0, 0.0, t0, x0, v0, t1, x1, v1, h, K, F, True)


@njit(cache=True, inline="always")
def _dense_prepare(p, mode, field, sgn, q, s, tref, t0, x0, v0, t1, x1, v1, h, K, F, stop):
    for st in range(N_STAGES + 1, 16):
        _stage(p, mode, field, sgn, q, s, tref, t0, x0, v0, h, st, K, stop)
    for c in range(3):
        if c == 0:
            dy = t1 - t0
        elif c == 1:
            dy = x1 - x0
        else:
            dy = v1 - v0
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
def initial_step(p, mode, field, sgn, q, s, tref, t, x, v, d0t, d0x, d0v, rtol, atol):
    """Hairer's starting step-size heuristic (one extra derivative evaluation)."""
    sx = atol + abs(x) * rtol
    sv = atol + abs(v) * rtol
    d0 = math.sqrt(((x / sx) ** 2 + (v / sv) ** 2) / 2.0)
    d1 = math.sqrt(((d0x / sx) ** 2 + (d0v / sv) ** 2) / 2.0)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    if mode == UVEL:  # the scales above are x's and v's; in s = asinh(v/eps) a probe beyond one
        h0 = min(h0, 1.0)  # e-fold of |v| overflows where |v| is near atol (a band of a few eps)
    _d1t, d1x, d1v = deriv(p, mode, field, sgn, q, s + h0, tref, t + h0 * d0t, x + h0 * d0x, v + h0 * d0v)
    d2 = math.sqrt((((d1x - d0x) / sx) ** 2 + ((d1v - d0v) / sv) ** 2) / 2.0) / h0
    if not (d2 == d2):
        return h0 * 1e-3
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (ORDER + 1))
    return min(100.0 * h0, h1)
