"""The piece solvers: one step attempt on the current smooth piece, with its own events.

Three solvers cover every piece kind (transitions.py draws how they hand over):

* :func:`impactosc.core.time_pieces.time_step` - DOP853 in time: free flight, and
  contact wherever no transformed variable applies.
* :func:`impactosc.core.transformed_pieces.transformed_step` - DOP853 in the piece's
  own variable s (vector_fields.deriv): contact onset and exit in sqrt(x - xI), the turn at the
  deepest penetration in |v|^n3, and the free-flight friction band in asinh(v/eps).
* implicit.implicit_step - Radau IIA (radau.py): sticking, slow reversals and stiff creep,
  until |v| leaves the friction band or the step is no longer held by stability.

This module holds what they share: starting a piece (its clock, and the derivative its first
step starts from), writing the state back and the step-size factor after an accepted step.

Each reads the state from ``st``, writes it back, and hands what it found to transitions.py
(apply_event, and the after_*_step hand-overs), which picks the next piece. ``ws`` = (K, F, work, d0): stage buffer, interpolant, implicit-solver
work array and the derivative at the start of the next step (first same as last).
"""

from __future__ import annotations

from numba import njit

from impactosc.core import dop853, vector_fields
from impactosc.core.layout import (
    C_RHS,
    CLOSED,
    S_ERRACC,
    S_FIELD,
    S_H,
    S_HACC,
    S_MODE,
    S_REJECTED,
    S_S,
    S_SGN,
    S_T,
    S_TAU,
    S_TREF,
    S_V,
    S_X,
    TIME,
)
from impactosc.model.equations import STOP
from impactosc.model.parameters import P_N3


@njit(cache=True, inline="always")
def inverse_n3(p):
    """q = 1/n3, the exponent of v = w^q in the |v|^n3 variable."""
    return 1.0 / p[P_N3] if p[P_N3] > 0.0 else 0.0


@njit(cache=True, inline="always")
def store(st, tau, x, v, s, h):
    """Write the state of the current piece back (tau: time since st[S_TREF])."""
    st[S_TAU] = tau
    st[S_T] = st[S_TREF] + tau
    st[S_X] = x
    st[S_V] = v
    st[S_S] = s
    st[S_H] = h


@njit(cache=True, inline="always")
def accepted_step_factor(st, err, h):
    """Step-size factor after an accepted step of size h with error norm err.

    Hairer's rule (no growth right after a rejection), and Gustafsson's predictive
    controller: when the error grows from step to step (approaching a singular point,
    where each step shrinks the distance to it), the next step shrinks by the trend
    instead of being tried at the same size and rejected (every other step before)."""
    fac = dop853.new_step_factor(err, st[S_REJECTED] != 0.0)
    if st[S_HACC] > 0.0 and err > 0.0:
        trend = (st[S_HACC] / h) * (err * err / st[S_ERRACC]) ** (-dop853.ERROR_EXPONENT) / dop853.SAFETY
        fac = min(fac, 1.0 / max(trend, 1.0 / dop853.MAX_FACTOR))
    fac = max(fac, dop853.MIN_FACTOR)
    st[S_REJECTED] = 0.0
    st[S_HACC] = h
    st[S_ERRACC] = max(1e-2, err)
    return fac


@njit(cache=True)
def start_piece(p, st, cnt, d0, ta, x, v, h):
    """Begin the piece st[S_MODE] (variable st[S_S], orientation st[S_SGN]) at absolute time
    ta from (x, v): set its clock, and the derivative d0 its first step starts from.

    h: the first step to try (0: choose one; < 0: choose one, but at most -h)."""
    mode = int(st[S_MODE])
    st[S_REJECTED] = 0.0
    st[S_HACC] = 0.0
    if mode in (TIME, CLOSED):
        st[S_TREF] = 0.0
        store(st, ta, x, v, ta, h)
        if mode == CLOSED:  # evaluated where it is needed, no derivative to carry
            return
    else:  # a transformed piece measures time from its start (tiny increments stay resolved)
        st[S_TREF] = ta
        store(st, 0.0, x, v, st[S_S], h)
    field = int(st[S_FIELD])
    if field == STOP:  # behind a contact law's second stop: its force too
        d0[0], d0[1], d0[2] = vector_fields.deriv_stop(p, field, st[S_TAU], x, v)
    else:
        d0[0], d0[1], d0[2] = vector_fields.deriv(
            p, mode, field, st[S_SGN], inverse_n3(p), st[S_S], st[S_TREF], st[S_TAU], x, v
        )
    cnt[C_RHS] += 1
