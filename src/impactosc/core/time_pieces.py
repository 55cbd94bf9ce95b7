"""DOP853 steps in time: free flight, and contact wherever no transformed variable applies.

Why a module: :func:`time_step` is the solver every piece can fall back to (a contact model
without the |v|^n3 damping, past the Hunt-Crossley cut, or after a transformed piece broke
down). It finds impacts, exits, the contact law's cut and second stop, and v = 0 (also a v that touches zero inside a step);
:mod:`impactosc.core.transitions` decides what comes next (after an event, and after every
accepted step: the friction band's variable, or the implicit phase for a stick or a stiff
creep).
"""

from __future__ import annotations

from numba import njit

from impactosc.core import dop853, vector_fields
from impactosc.core.events import (
    EV_CUT_OFF,
    EV_CUT_ON,
    EV_NONE,
    EV_STOP_OFF,
    EV_STOP_ON,
    EV_V,
    EV_X_DOWN,
    EV_X_UP,
    sign,
)
from impactosc.core.layout import (
    C_BY_MODE,
    C_DENSE,
    C_DIP,
    C_REJECT,
    C_RHS,
    C_STEPS,
    R_ATOL,
    R_RTOL,
    S_FIELD,
    S_H,
    S_MODE,
    S_REJECTED,
    S_STATUS,
    S_TAU,
    S_V,
    S_VCUT,
    S_X,
    TIME,
    UNDERFLOW_EXPLICIT,
)
from impactosc.core.pieces import accepted_step_factor, inverse_n3, start_piece, store
from impactosc.core.sampling import bisect, locate_surface, sample_window, window_due
from impactosc.core.transitions import after_time_step, apply_event
from impactosc.model.contact_laws.kernel import (
    SURFACE_CUT,
    SURFACE_OBSTACLE,
    SURFACE_STOP,
    behind_stop,
    has_stop,
    past_cut,
    surface_residual,
)
from impactosc.model.equations import CONTACT, CUT, FREE, STOP
from impactosc.model.parameters import P_EPS, P_M, P_T, P_XI

DIP_SAMPLES = 32
RESTART_FRACTION = 1e-3  # first step after an event, as a fraction of the step that held it
APPROACH_BAND = 1e4  # within |v| < APPROACH_BAND * eps of a reversal ...
APPROACH_FRACTION = 0.5  # ... a step covers at most this fraction of the time left to v = 0


@njit(cache=True, inline="always")  # inlined into core.run: as a call, 7 % slower (A/B, 5 runs)
def time_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target):
    """One DOP853 step in time on the current piece, clamped to t_target (the next Poincare
    time or the end of the run); locates the events inside it and applies the first."""
    return _step_in_time(False, p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target)


@njit(cache=True)  # a call: only a contact behind a second stop takes it
def stop_time_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target):
    """time_step behind a contact law's second stop (field STOP), whose force its stepper adds."""
    return _step_in_time(True, p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target)


@njit(cache=True, inline="always")
def _step_in_time(stop, p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target):
    """The step of time_step; stop, a literal of each caller, picks the stepper behind a second
    stop (dop853's ``*_stop``): model BC's time step carries no test of it (a test of it in every
    stage's right-hand side cost the chaotic scene 7-10 %). (The first step's guess,
    initial_step, leaves the second stop's force out: its controller corrects the guess.)"""
    K, F, _, d0, _ = ws
    field = int(st[S_FIELD])
    t, x, v, h = st[S_TAU], st[S_X], st[S_V], st[S_H]
    rtol, atol = rs[R_RTOL], rs[R_ATOL]
    eps = p[P_EPS]
    q = inverse_n3(p)
    ax = d0[2]
    if h <= 0.0:
        h0 = dop853.initial_step(p, TIME, field, 0.0, q, t, 0.0, t, x, v, d0[0], d0[1], d0[2], rtol, atol)
        cnt[C_RHS] += 1
        h = h0 if h == 0.0 else min(h0, -h)
    if v * ax < 0.0 and abs(v) < APPROACH_BAND * eps:
        # approaching v = 0, where the friction switches over a time eps/|a|: close in
        # geometrically instead of letting the controller overshoot and reject
        h = min(h, max(APPROACH_FRACTION * abs(v), 0.25 * eps) / abs(ax))
    clamped = h >= t_target - t
    hs = t_target - t if clamped else h
    if stop:
        t1, x1, v1, err = dop853.step_stop(p, field, t, x, v, d0[0], d0[1], d0[2], hs, rtol, atol, K)
    else:
        t1, x1, v1, err = dop853.step(p, TIME, field, 0.0, q, t, 0.0, t, x, v, d0[0], d0[1], d0[2], hs, rtol, atol, K)
    cnt[C_RHS] += 12
    cnt[C_BY_MODE + TIME] += 1
    if err > 1.0:
        cnt[C_REJECT] += 1
        st[S_REJECTED] = 1.0
        h = hs * dop853.new_step_factor(err, False)
        if h < 4e-16 * max(1.0, abs(t)):
            st[S_STATUS] = UNDERFLOW_EXPLICIT
        st[S_H] = h
        return ev, n_ev
    cnt[C_STEPS] += 1
    fac = accepted_step_factor(st, err, hs)
    h_next = hs * fac if not clamped else max(h, hs * fac)
    t1 = t_target if clamped else t + hs
    built = False

    # --- candidate events in this step ---
    sgn0 = sign(v) if v != 0.0 else sign(ax)
    if sgn0 == 0.0:
        sgn0 = sign(v1)
    v_cross = v1 != 0.0 and sign(v1) != sgn0 and sgn0 != 0.0
    if not v_cross and sgn0 != 0.0:
        # v keeps its sign at both ends; can it have touched zero in between?
        amax = 0.0
        for j in range(13):
            amax = max(amax, abs(K[j, 2]))
        if abs(v) + abs(v1) - (2.0 * amax + 2.0 * p[P_T] / p[P_M]) * hs <= 0.0:
            cnt[C_DIP] += 1
            _dense(stop, p, field, q, t, x, v, t1, x1, v1, hs, K, F)
            cnt[C_RHS] += 3
            cnt[C_DENSE] += 1
            built = True
            for k in range(1, DIP_SAMPLES):
                if dop853.dense_eval(F, v, k / DIP_SAMPLES, 2) * sgn0 < 0.0:
                    v_cross = True
                    break
    g1 = surface_residual(p, st[S_VCUT], SURFACE_OBSTACLE, x1, v1)
    x_up = field == FREE and g1 > 0.0
    x_down = field != FREE and g1 < 0.0
    cut_on = field == CONTACT and past_cut(p, st[S_VCUT], x1, v1)
    cut_off = field == CUT and not past_cut(p, st[S_VCUT], x1, v1)
    # a surface of the law inside the contact (a second stop), crossed either way
    crosses_stop = (field == CONTACT and has_stop(p) and behind_stop(p, x1)) or (
        field == STOP and not behind_stop(p, x1)
    )
    if v_cross or x_up or x_down or cut_on or cut_off or crosses_stop:
        if not built:
            _dense(stop, p, field, q, t, x, v, t1, x1, v1, hs, K, F)
            cnt[C_RHS] += 3
            cnt[C_DENSE] += 1
        th, kind = _first_event(p, st, F, x, v, sgn0, v_cross, x_up, x_down, cut_on, cut_off, crosses_stop)
        te = t1 if th >= 1.0 else min(t + th * hs, t1)
        xe = dop853.dense_eval(F, x, th, 1)
        ve = dop853.dense_eval(F, v, th, 2)
        if window_due(st, rs, win_x, te):
            sample_window(F, TIME, 0.0, t, x, v, hs, te, st, rs, win_x, win_v)
        ev, n_ev, xe, ve = apply_event(p, st, cnt, rs, ev, n_ev, kind, te, xe, ve, sgn0, hs)
        # restart the step-size selection on the new piece, from a small first step: the
        # friction switch (width eps/|a| in time) or |v|^n3 start right at v = 0, and the
        # h^1.5 contact onset, are resolved by growing steps (x10 each) far more cheaply
        # than by rejecting a large guess (x0.2 each, 12 evaluations lost every time).
        start_piece(p, st, cnt, d0, te, xe, ve, -RESTART_FRACTION * hs if st[S_MODE] == TIME else 0.0)
        return ev, n_ev

    # --- no event: accept the step ---
    if window_due(st, rs, win_x, t1):
        if not built:
            _dense(stop, p, field, q, t, x, v, t1, x1, v1, hs, K, F)
            cnt[C_RHS] += 3
            cnt[C_DENSE] += 1
        sample_window(F, TIME, 0.0, t, x, v, hs, t1, st, rs, win_x, win_v)
    # first-same-as-last; when the step was clamped onto a Poincare time, t + hs can
    # differ from t1 in the last bit: re-evaluate there so a resumed run is identical
    if t + hs == t1:
        d0[0], d0[1], d0[2] = K[12, 0], K[12, 1], K[12, 2]
    else:
        if stop:
            d0[0], d0[1], d0[2] = vector_fields.deriv_stop(p, field, t1, x1, v1)
        else:
            d0[0], d0[1], d0[2] = vector_fields.deriv(p, TIME, field, 0.0, q, t1, 0.0, t1, x1, v1)
        cnt[C_RHS] += 1
    store(st, t1, x1, v1, t1, h_next)
    after_time_step(p, st, cnt, d0, field, t1, x1, v1, hs)
    return ev, n_ev


@njit(cache=True, inline="always")
def _dense(stop, p, field, q, t, x, v, t1, x1, v1, hs, K, F):
    """The step's interpolant, behind a second stop (stop, a literal) with its force."""
    if stop:
        dop853.dense_prepare_stop(p, field, t, x, v, t1, x1, v1, hs, K, F)
    else:
        dop853.dense_prepare(p, TIME, field, 0.0, q, t, 0.0, t, x, v, t1, x1, v1, hs, K, F)


@njit(cache=True)
def _first_event(p, st, F, x, v, sgn0, v_cross, x_up, x_down, cut_on, cut_off, crosses_stop):
    """The earliest of the candidate events of a time step, on its interpolant F: (theta, kind).
    A contact law's surfaces (the obstacle, the cut, a second stop) by their residuals."""
    th = 2.0
    kind = EV_NONE
    vcut = st[S_VCUT]
    if v_cross:
        th = bisect(F, v, 2, 0.0, 0.0, 1.0, sgn0)
        kind = EV_V
        if int(st[S_FIELD]) == FREE and sgn0 > 0.0 and dop853.dense_eval(F, x, th, 1) >= p[P_XI]:
            x_up = True  # the maximum lies at or past the obstacle: contact came first
    if x_up:
        th_x = locate_surface(p, vcut, SURFACE_OBSTACLE, F, x, v, 0.0, th if th <= 1.0 else 1.0, -1.0)
        if th_x <= th:
            th = th_x
            kind = EV_X_UP
    if x_down:
        th_x = locate_surface(p, vcut, SURFACE_OBSTACLE, F, x, v, 0.0, 1.0, 1.0)
        if th_x < th:
            th = th_x
            kind = EV_X_DOWN
    if cut_on or cut_off:
        th_c = locate_surface(p, vcut, SURFACE_CUT, F, x, v, 0.0, 1.0, 1.0 if cut_on else -1.0)
        if th_c < th:
            th = th_c
            kind = EV_CUT_ON if cut_on else EV_CUT_OFF
    if crosses_stop:
        on = int(st[S_FIELD]) == CONTACT
        th_s = locate_surface(p, vcut, SURFACE_STOP, F, x, v, 0.0, 1.0, -1.0 if on else 1.0)
        if th_s < th:
            th = th_s
            kind = EV_STOP_ON if on else EV_STOP_OFF
    return th, kind
