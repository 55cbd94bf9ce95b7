"""The vector field of model BC in each variable a piece can run in: (dt/ds, dx/ds, dv/ds).

A piece that starts or ends at a singular point of the vector field (the contact force
~ (x - xI)^1.5 at onset and exit, the Hunt-Crossley damping ~ |v|^n3 at v = 0, the friction
switch of width eps) is smooth in a variable of its own; the explicit stepper
(:mod:`impactosc.core.dop853`) integrates whichever :func:`deriv` gives it. The variables
(layout.TIME, SQRTH, WVEL, UVEL) and where each is used: the piece graph of the core.
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.core.layout import SQRTH, TIME, WVEL
from impactosc.model.equations import accel, accel_any, accel_vn
from impactosc.model.parameters import P_EPS, P_XI


@njit(cache=True)
def deriv(p, mode, field, sgn, q, s, tref, t, x, v):
    """(dt/ds, dx/ds, dv/ds) of the piece; in TIME mode (1, v, a).

    SQRTH: y = sgn*s = sqrt(x - xI), so dt/ds = sgn 2y/v, dv/ds = sgn 2y a/v (v away from 0).
    WVEL: w = -sgn*s = |v|^n3, v = sgn w^q (q = 1/n3): dv/ds = -q w^(q-1), dt/ds = (dv/ds)/a.
    UVEL: u = sgn*s, v = eps sinh(u): dv/ds = sgn eps cosh(u), dt/ds = (dv/ds)/a.
    In every mode dt/ds > 0 while the piece is valid; the caller checks it. Off TIME mode
    the time component is tau = t - tref, measured from the start of the piece, so that
    increments far below the resolution of the absolute time still register.
    """
    if mode == TIME:
        return 1.0, v, accel(p, field, t, x, v)
    if mode == SQRTH:
        y = sgn * s
        a = accel(p, field, tref + t, p[P_XI] + y * y, v)
        dt = sgn * 2.0 * y / v if v != 0.0 else math.inf  # v = 0: outside this map's range
        return dt, sgn * 2.0 * y, dt * a
    if mode == WVEL:
        w = max(-sgn * s, 0.0)
        wq1 = w ** (q - 1.0)
        vv = sgn * w * wq1  # v = sgn w^q, and |v|^n3 = w: one power for all three
        a = accel_vn(p, field, tref + t, x, vv, w)
        dv = -q * wq1
        dt = dv / a if a != 0.0 else math.inf  # a = 0: outside this map's range
        return dt, vv * dt, dv
    # sinh and cosh from one exponential (expm1 keeps sinh accurate near u = 0)
    em = math.expm1(sgn * s)
    e = 1.0 + em
    vv = p[P_EPS] * (0.5 * em * (1.0 + 1.0 / e))
    a = accel(p, field, tref + t, x, vv)
    dv = sgn * p[P_EPS] * (0.5 * (e + 1.0 / e))
    dt = dv / a if a != 0.0 else math.inf  # a = 0: outside this map's range
    return dt, vv * dt, dv


@njit(cache=True, inline="always")
def deriv_stop(p, field, t, x, v):
    """deriv in time on any field, behind a contact law's second stop (STOP) too: the steppers'
    variant for such a piece (dop853's ``*_stop`` functions), so that model BC's steppers carry no
    test of it."""
    return 1.0, v, accel_any(p, field, t, x, v)
