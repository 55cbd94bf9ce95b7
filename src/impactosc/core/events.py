"""The events the piece solvers locate, and the event rows ``ev`` the core records.

An event is a point where the vector field or the piece's variable changes: an impact
(x = xI upwards), a contact exit (x = xI downwards), the contact law's cut (its bracket = 0, on or
off) and any surface of the law inside the contact (a second stop), a reversal (v = 0) and a Poincare time. The piece solvers (time_pieces.py,
transformed_pieces.py, implicit.py) locate them and report their kind (EV_*);
transitions.py applies them and picks the next piece; this module writes the rows: impacts,
penetrations and near misses (extrema of x), Poincare points.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from impactosc.core.layout import (
    NEAR_MISS,
    PENETRATION,
    POINCARE,
    R_FLAGS,
    R_T_RECORD,
    RECORD_NEAR_MISSES,
    RECORD_PENETRATIONS,
    RECORD_POINCARE,
    S_ISEC,
)
from impactosc.model.equations import FREE, in_contact
from impactosc.model.parameters import P_XI

# event kinds located inside a step (EV_V: v = 0; EV_STOP_*: a contact law's surface inside the contact)
EV_NONE, EV_X_UP, EV_X_DOWN, EV_V, EV_CUT_ON, EV_CUT_OFF, EV_STOP_ON, EV_STOP_OFF = range(8)


@njit(cache=True)
def push(ev, n, kind, t, a, b):
    """Append the row (kind, t, a, b), doubling ``ev`` when full; returns (ev, n)."""
    if n >= ev.shape[0]:
        grown = np.empty((2 * ev.shape[0], 4))
        for i in range(n):  # a loop, not grown[:n] = ev[:n]: the slice copy's shape-error
            for j in range(4):  # formatting costs numba about 8 s of compile per kind
                grown[i, j] = ev[i, j]
        ev = grown
    ev[n, 0] = kind
    ev[n, 1] = t
    ev[n, 2] = a
    ev[n, 3] = b
    return ev, n + 1


@njit(cache=True)
def sign(a):
    return 1.0 if a > 0.0 else (-1.0 if a < 0.0 else 0.0)


@njit(cache=True)
def record_poincare(st, rs, ev, n, t_sec, x, v):
    """The Poincare time t_sec = i * period has been reached at (x, v): record it, move on to i + 1."""
    if int(rs[R_FLAGS]) & RECORD_POINCARE and t_sec >= rs[R_T_RECORD]:
        ev, n = push(ev, n, POINCARE, t_sec, x, v)
    st[S_ISEC] += 1.0
    return ev, n


@njit(cache=True)
def record_extremum(p, rs, ev, n, field, t, x, direction):
    """A maximum of x (direction +1) is a penetration in contact, a near miss in flight."""
    flags = int(rs[R_FLAGS])
    if direction > 0.0 and t >= rs[R_T_RECORD]:
        if in_contact(field) and flags & RECORD_PENETRATIONS:
            ev, n = push(ev, n, PENETRATION, t, x - p[P_XI], 0.0)
        elif field == FREE and flags & RECORD_NEAR_MISSES:
            ev, n = push(ev, n, NEAR_MISS, t, p[P_XI] - x, 0.0)
    return ev, n
