"""Event-driven integration of model BC: the one numba core every workflow rule shares.

The trajectory is cut into smooth pieces. A piece ends exactly at a contact onset or exit,
at v = 0 (where |v|^n3 and the friction switch live) and at the Hunt-Crossley cut, so no
step of the 8th-order explicit method straddles a non-smooth point. Inside a piece the sign
of v is fixed, hence x is monotone: an obstacle crossing cannot come in an unseen pair, and
the only pair to guard against is v touching zero twice in a step (checked on the dense
output whenever an acceleration bound cannot exclude it).

A piece that starts or ends at a singular point is integrated in a variable in which it is
smooth (vector_fields.deriv): sqrt(x - xI) next to a contact onset or exit (the force ~ h^1.5),
|v|^n3 around the deepest penetration (the Hunt-Crossley damping ~ |v|^n3), and
asinh(v / eps) through the friction band of a free-flight reversal. The singular point is
then an exact end of the piece, and steps are set by accuracy, not by the singularity.
When v = 0 falls where the net force cannot overcome dry friction (sticking) or barely can
(slow reversal), the piece is handed to the implicit Radau solver until |v| leaves the
friction band again. So is any piece whose explicit steps are held by stability rather
than accuracy (h |da/dv| > STIFF_ENTER): the creep inside the contact where the
Hunt-Crossley damping ~ |v|^n3 balances the other forces (found by randomized testing);
it returns to explicit steps once h |da/dv| < STIFF_EXIT. Any transformed piece that would
become invalid (a vanishing acceleration or velocity) falls back to plain time stepping,
which is always correct.

The loop only dispatches: the solver of the current piece (time steps in time_pieces.py,
transformed steps in transformed_pieces.py, implicit steps in implicit.py) takes one step and
locates the events in it; transitions.py decides every change of piece, and its docstring
is the piece graph with the threshold of each hand-over.

Time steps land exactly on every Poincare time t_i = i * (2 pi / w) (one multiplication, no
accumulated time); inside a transformed piece the section is located on the dense output of
t(s). A run can be split into calls of at most ``max_steps`` steps that resume from the saved
state (``st``) without changing a single step.

Never hang: a watchdog counts step attempts; a run that spends ``st[S_BUDGET]`` of them
without advancing one forcing period stops with ``st[S_STATUS] = STALLED`` (step-size
underflows stop with their own status); ``simulate`` turns a status into an error that
names the time, the piece, the state and the step size.

Event rows written to ``ev`` are (kind, t, a, b):
    IMPACT (t, v at onset), PENETRATION (t, h = x - xI at v = 0), NEAR_MISS (t, gap = xI - x
    at a free-flight maximum), POINCARE (t_i, x, v).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core import closed_flight, implicit, pieces, time_pieces, transformed_pieces, turn_series, vector_fields
from impactosc.core.events import record_poincare
from impactosc.core.layout import (
    C_ATTEMPTS,
    C_RHS,
    CLOSED,
    DEFAULT_STEP_BUDGET,
    N_COUNT,
    N_SETTINGS,
    N_STATE,
    R_ATOL,
    R_FLAGS,
    R_PERIOD,
    R_RTOL,
    R_T_END,
    R_T_RECORD,
    R_WIN_DT,
    R_WIN_T0,
    RUNNING,
    S_BUDGET,
    S_FIELD,
    S_ISEC,
    S_MARK_N,
    S_MARK_T,
    S_MODE,
    S_S,
    S_SGN,
    S_SLOW,
    S_STATUS,
    S_T,
    S_TAU,
    S_TREF,
    S_V,
    S_VCUT,
    S_X,
    STALLED,
    TIME,
)
from impactosc.core.transitions import first_piece
from impactosc.model.equations import STOP


def run_settings(t_end, t_record, rtol, atol, flags, period, win_t0=0.0, win_dt=1.0):
    """The settings array ``rs`` of :func:`run` (indices R_* in layout.py)."""
    rs = np.empty(N_SETTINGS)
    rs[R_T_END], rs[R_T_RECORD], rs[R_RTOL], rs[R_ATOL] = t_end, t_record, rtol, atol
    rs[R_FLAGS], rs[R_PERIOD], rs[R_WIN_T0], rs[R_WIN_DT] = float(flags), period, win_t0, win_dt
    return rs


@njit(cache=True)
def resume(p, st, cnt, d0):
    """Normalise the saved clock (a fresh state only sets S_T) and rebuild the derivative
    the next explicit step starts from."""
    mode = int(st[S_MODE])
    if mode in (TIME, CLOSED):
        st[S_TREF] = 0.0
        st[S_TAU] = st[S_T]
        st[S_S] = st[S_T]
        if mode == CLOSED:  # evaluated where it is needed, no derivative to carry
            return
    field = int(st[S_FIELD])
    if field == STOP:  # behind a contact law's second stop: its force too
        d0[0], d0[1], d0[2] = vector_fields.deriv_stop(p, field, st[S_T], st[S_X], st[S_V])
    else:
        d0[0], d0[1], d0[2] = vector_fields.deriv(
            p, mode, field, st[S_SGN], pieces.inverse_n3(p), st[S_S], st[S_TREF], st[S_TAU], st[S_X], st[S_V]
        )
    cnt[C_RHS] += 1


@njit(cache=True, inline="always")
def on_section(st, t_sec):
    """Has a piece in time (time steps, closed form) landed on the Poincare time t_sec? Their
    steps are clamped to it; a transformed piece records its sections inside its steps."""
    mode = st[S_MODE]
    return mode in (TIME, CLOSED) and st[S_TAU] >= t_sec


@njit(cache=True)
def _stalled(st, cnt, period):
    """Watchdog: count one step attempt; True once st[S_BUDGET] of them passed without a
    forcing period of progress."""
    cnt[C_ATTEMPTS] += 1
    if cnt[C_ATTEMPTS] - st[S_MARK_N] >= st[S_BUDGET]:
        if st[S_T] - st[S_MARK_T] < period:
            st[S_STATUS] = STALLED
            return True
        st[S_MARK_N] = cnt[C_ATTEMPTS]
        st[S_MARK_T] = st[S_T]
    return False


@njit(cache=True, inline="always")  # on every step of run: inlined
def step_piece(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_sec):
    """One step of the current piece (implicit, transformed or in time), towards the next
    Poincare time t_sec or the run's end. Returns (ev, n_ev)."""
    t_target = min(rs[R_T_END], t_sec)
    if st[S_SLOW] != 0.0:
        ev, n_ev = implicit.implicit_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target)
    elif st[S_MODE] == CLOSED:
        ev, n_ev = closed_flight.closed_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target)
    elif st[S_MODE] != TIME:
        ev, n_ev = transformed_pieces.transformed_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v)
    elif st[S_FIELD] == STOP:  # behind a contact law's second stop
        ev, n_ev = time_pieces.stop_time_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target)
    else:
        ev, n_ev = time_pieces.time_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target)
    return ev, n_ev


@njit(cache=True)
def workspace():
    """The steppers' scratch arrays, made once a run: DOP853's stages K and dense output F, the
    implicit step's work, the derivatives d0 at the current state, and the turn's series (whose
    eps-layer moments depend on n3 only: computed at the run's first turn)."""
    return np.zeros((16, 3)), np.zeros((7, 3)), np.zeros((8, 6)), np.zeros(3), turn_series.work()


@njit(cache=True)
def run(p, st, cnt, rs, ev, n_ev, win_x, win_v, max_steps):
    """Integrate from the state ``st`` towards rs[R_T_END]; events at t >= rs[R_T_RECORD] go to ``ev``.

    rs: run_settings (end, recording start, tolerances, layout.RECORD_* flags, period,
    window). Returns after the end or after `max_steps` step attempts, with ``st``/``cnt``
    updated in place so the next call continues the same trajectory; the window samples go
    to win_x / win_v. Returns (ev, n_ev) (ev may be reallocated).
    """
    ws = workspace()
    resume(p, st, cnt, ws[3])
    period = rs[R_PERIOD]
    steps = 0
    while True:
        t_sec = st[S_ISEC] * period
        if on_section(st, t_sec):
            ev, n_ev = record_poincare(st, rs, ev, n_ev, t_sec, st[S_X], st[S_V])
            continue
        if st[S_T] >= rs[R_T_END] or steps >= max_steps:
            break
        steps += 1
        if _stalled(st, cnt, period):
            break
        ev, n_ev = step_piece(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_sec)
        if st[S_STATUS] != RUNNING:
            break
    return ev, n_ev


def initial_state(p, t0, x0, v0, period, vcut, step_budget=DEFAULT_STEP_BUDGET):
    """Resumable state vector for a run that starts at (t0, x0, v0).

    `step_budget`: step attempts allowed per forcing period of simulated time; a run that
    spends them without advancing a period stops with status STALLED (the watchdog).
    """
    st = np.zeros(N_STATE)
    st[S_T], st[S_X], st[S_V] = t0, x0, v0
    st[S_BUDGET] = float(step_budget)
    st[S_MARK_T] = t0
    st[S_VCUT] = vcut
    # next Poincare index strictly after t0 (t0 itself is the initial condition)
    i = math.floor(t0 / period) + 1
    st[S_ISEC] = float(i)
    first_piece(p, st, np.zeros(N_COUNT, dtype=np.int64), t0, x0, v0)
    return st
