"""A Taylor-series stepper for three of the core's pieces: the measurement behind the method choice.

Why it exists: a Taylor method replaces DOP853's 12 stages by one pass of recurrences
(normalised coefficients by automatic differentiation) and can take longer steps where the
solution is smooth. Whether that pays on this model is measured piece by piece
(:mod:`.taylor_pieces`) with this stepper on

* free flight in time between two friction bands (|v| > 1e3 eps),
* the turn at the deepest penetration in the variable s = -|v|^n3 (the core's WVEL piece),
* a free-flight reversal through the friction band in s = sgn asinh(v/eps) (UVEL),

the same vector fields as vector_fields.deriv. One function per operation (product, quotient, sqrt,
real power, sin/cos of a series), composed per vector field; no allocation inside a step.
Step size from the last two coefficients of each component against its tolerance
(atol + rtol |y|), as in Jorba & Zou (2005) with the tolerance per component. The core does
not use this stepper (the measurement says why: benchmark_taylor's table).

Coefficient arrays hold normalised coefficients y_k = y^(k)(s0) / k!.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.model.parameters import P_B, P_C, P_EPS, P_K, P_KI, P_M, P_M0E, P_N3, P_OMEGA, P_T, P_XI

SAFETY = 0.9  # of the step at which the last two terms reach the tolerance
MAX_STEPS = 1_000_000  # a loop that has not arrived by then returns with the count (never hangs)


# --- recurrences: coefficient k of a composite series from the lower ones ------------------
@njit(cache=True, inline="always")
def product(a, b, k):
    """(a b)_k."""
    s = 0.0
    for j in range(k + 1):
        s += a[j] * b[k - j]
    return s


@njit(cache=True, inline="always")
def quotient(a, b, c, k):
    """(a / b)_k given c = a / b up to k - 1."""
    s = a[k]
    for j in range(1, k + 1):
        s -= b[j] * c[k - j]
    return s / b[0]


@njit(cache=True, inline="always")
def square_root(a, r, k):
    """(sqrt a)_k given r = sqrt a up to k - 1."""
    if k == 0:
        return math.sqrt(a[0])
    s = a[k]
    for j in range(1, k):
        s -= r[j] * r[k - j]
    return s / (2.0 * r[0])


@njit(cache=True, inline="always")
def real_power(a, c, alpha, k):
    """(a^alpha)_k given c = a^alpha up to k - 1 (a_0 > 0)."""
    if k == 0:
        return a[0] ** alpha
    s = 0.0
    for j in range(k):
        s += (alpha * (k - j) - j) * a[k - j] * c[j]
    return s / (k * a[0])


@njit(cache=True, inline="always")
def sine_cosine(u, sn, cs, k):
    """(sin u)_k and (cos u)_k for k >= 1, given both up to k - 1."""
    ss = 0.0
    cc = 0.0
    for j in range(1, k + 1):
        ss += j * u[j] * cs[k - j]
        cc += j * u[j] * sn[k - j]
    return ss / k, -cc / k


@njit(cache=True)
def evaluate(c, order, h):
    """The polynomial sum c_k h^k (Horner): the dense output of a step."""
    y = c[order]
    for k in range(order - 1, -1, -1):
        y = y * h + c[k]
    return y


@njit(cache=True)
def step_size(y, order, tol):
    """The step at which the last two terms of every component reach its tolerance tol[i]."""
    h = math.inf
    for k in (order - 1, order):
        for i in range(y.shape[0]):
            a = abs(y[i, k])
            if a > 0.0:
                h = min(h, (tol[i] / a) ** (1.0 / k))
    return SAFETY * h


@njit(cache=True, inline="always")
def _forcing(p, tau, tref, sn, cs, arg, k):
    """sin and cos of w (tref + tau(s)), coefficient k, from the coefficients of tau."""
    w = p[P_OMEGA]
    arg[k] = w * (tau[k] + (tref if k == 0 else 0.0))
    if k == 0:
        sn[0], cs[0] = math.sin(arg[0]), math.cos(arg[0])
    else:
        sn[k], cs[k] = sine_cosine(arg, sn, cs, k)


# --- vector fields: the coefficients of one step ------------------------------------------
@njit(cache=True)
def coefficients_time(p, t0, x0, v0, order, y, work):
    """Free flight in time: y[0] = x, y[1] = v; sin(w t) by its closed form."""
    w = p[P_OMEGA]
    sq, root, fric = work[0], work[1], work[2]
    y[0, 0], y[1, 0] = x0, v0
    s0, c0 = math.sin(w * t0), math.cos(w * t0)
    amp = p[P_M0E] * w * w
    scale = 1.0  # w^k / k!
    for k in range(order):
        sk = (s0, c0, -s0, -c0)[k % 4] * scale
        scale *= w / (k + 1)
        sq[k] = product(y[1], y[1], k) + (p[P_EPS] ** 2 if k == 0 else 0.0)
        root[k] = square_root(sq, root, k)
        fric[k] = quotient(y[1], root, fric, k)
        a = (amp * sk - p[P_K] * y[0, k] - p[P_C] * y[1, k] - p[P_T] * fric[k]) / p[P_M]
        y[0, k + 1] = y[1, k] / (k + 1)
        y[1, k + 1] = a / (k + 1)


@njit(cache=True)
def coefficients_turn(p, tref, s0, tau0, x0, order, y, work):
    """Contact turn in s = -|v|^n3 (v > 0 heading for 0): y[0] = tau = t - tref, y[1] = x.

    v = w^q and dv/ds = -q w^(q-1) with w = -s linear in s: binomial series, no recurrence."""
    q = 1.0 / p[P_N3]
    w0 = -s0
    vel, dvel, sq, root, fric, gap = work[0], work[1], work[2], work[3], work[4], work[5]
    gap15, sn, cs, arg, acc, dtau = work[6], work[7], work[8], work[9], work[10], work[11]
    bq, bq1 = w0**q, -q * w0 ** (q - 1.0)
    for k in range(order + 1):
        vel[k], dvel[k] = bq, bq1
        bq *= -(q - k) / ((k + 1) * w0)
        bq1 *= -(q - 1.0 - k) / ((k + 1) * w0)
    y[0, 0], y[1, 0] = tau0, x0
    w = p[P_OMEGA]
    for k in range(order):
        _forcing(p, y[0], tref, sn, cs, arg, k)
        sq[k] = product(vel, vel, k) + (p[P_EPS] ** 2 if k == 0 else 0.0)
        root[k] = square_root(sq, root, k)
        fric[k] = quotient(vel, root, fric, k)
        gap[k] = y[1, k] - (p[P_XI] if k == 0 else 0.0)
        gap15[k] = real_power(gap, gap15, 1.5, k)
        damping = gap15[k] * w0 - (gap15[k - 1] if k >= 1 else 0.0)  # h^1.5 |v|^n3, |v|^n3 = w0 - (s - s0)
        force = p[P_M0E] * w * w * sn[k] - p[P_K] * y[1, k] - p[P_C] * vel[k] - p[P_T] * fric[k]
        acc[k] = (force - p[P_KI] * (gap15[k] + p[P_B] * damping)) / p[P_M]
        dtau[k] = quotient(dvel, acc, dtau, k)
        y[0, k + 1] = dtau[k] / (k + 1)
        y[1, k + 1] = product(vel, dtau, k) / (k + 1)


@njit(cache=True)
def coefficients_band(p, tref, s0, sgn, tau0, x0, order, y, work):
    """Free flight through the friction band in s = sgn asinh(v/eps): y[0] = tau, y[1] = x.

    v = eps sinh(u), u = sgn s: sinh and cosh by their closed forms; friction T tanh(u)."""
    sh, ch, vel, dvel, th = work[0], work[1], work[2], work[3], work[4]
    sn, cs, arg, acc, dtau = work[5], work[6], work[7], work[8], work[9]
    eps = p[P_EPS]
    s_u, c_u = math.sinh(sgn * s0), math.cosh(sgn * s0)
    scale = 1.0  # sgn^k / k!
    for k in range(order + 1):
        sh[k] = (s_u if k % 2 == 0 else c_u) * scale
        ch[k] = (c_u if k % 2 == 0 else s_u) * scale
        vel[k] = eps * sh[k]
        dvel[k] = sgn * eps * ch[k]
        scale *= sgn / (k + 1)
    y[0, 0], y[1, 0] = tau0, x0
    w = p[P_OMEGA]
    for k in range(order):
        _forcing(p, y[0], tref, sn, cs, arg, k)
        th[k] = quotient(sh, ch, th, k)
        force = p[P_M0E] * w * w * sn[k] - p[P_K] * y[1, k] - p[P_C] * vel[k] - p[P_T] * th[k]
        acc[k] = force / p[P_M]
        dtau[k] = quotient(dvel, acc, dtau, k)
        y[0, k + 1] = dtau[k] / (k + 1)
        y[1, k + 1] = product(vel, dtau, k) / (k + 1)


# --- one piece, start to end --------------------------------------------------------------
TIME_PIECE, TURN_PIECE, BAND_PIECE = 0, 1, 2
PIECE_NAMES = ("free flight (time)", "contact turn (|v|^n3)", "friction band (asinh(v/eps))")


@njit(cache=True)
def integrate_piece(p, kind, s0, s1, sgn, tref, a0, b0, order, rtol, atol):
    """Integrate a piece from s0 to s1 with steps of the given order.

    TIME_PIECE: s = t, (a, b) = (x, v); TURN_PIECE and BAND_PIECE: (a, b) = (tau, x) with
    tau = t - tref. Returns (a, b, steps) at s1."""
    y = np.zeros((2, order + 1))
    work = np.zeros((12, order + 2))
    tol = np.empty(2)
    s, a, b = s0, a0, b0
    steps = 0
    while s < s1 and steps < MAX_STEPS:
        if kind == TIME_PIECE:
            coefficients_time(p, s, a, b, order, y, work)
        elif kind == TURN_PIECE:
            coefficients_turn(p, tref, s, a, b, order, y, work)
        else:
            coefficients_band(p, tref, s, sgn, a, b, order, y, work)
        tol[0], tol[1] = atol + rtol * abs(a), atol + rtol * abs(b)
        h = min(step_size(y, order, tol), s1 - s)
        a, b = evaluate(y[0], order, h), evaluate(y[1], order, h)
        s = s1 if h == s1 - s else s + h
        steps += 1
    return a, b, steps
