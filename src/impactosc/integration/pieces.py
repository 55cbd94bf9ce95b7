"""The piece solvers: one step attempt on the current smooth piece, with its own events.

Three solvers cover every piece kind (core.py draws how they hand over):

* :func:`time_step` - DOP853 in time: free flight, and contact wherever no transformed
  variable applies (a contact model without the |v|^n3 damping, past the Hunt-Crossley cut,
  or after a transformed piece broke down). It finds impacts, exits, the cut and v = 0
  (also a v that touches zero inside a step), and hands a reversal's friction band to
  :func:`transformed_step` and a stick or stiff creep to the implicit phase.
* :func:`transformed_step` - DOP853 in the piece's own variable s (dop853.deriv): contact
  onset and exit in sqrt(x - xI), the turn at the deepest penetration in |v|^n3, and the
  free-flight friction band in asinh(v/eps). Its singular end point (impact side, v = 0,
  exit) is an exact end of the piece; Poincare times and the window come from the
  interpolant of t(s).
* implicit.implicit_step - Radau IIA (radau.py): sticking, slow reversals and stiff creep,
  until |v| leaves the friction band or the step is no longer held by stability.

Each reads the state from ``st``, writes it back, and applies what it found through
events.apply_event. ``ws`` = (K, F, work, d0): stage buffer, interpolant, implicit-solver
work array and the derivative at the start of the next step (first same as last).
"""

from __future__ import annotations

import math

from numba import njit

from . import dop853
from .events import (
    CONTACT_SWITCH,
    EV_CUT_OFF,
    EV_CUT_ON,
    EV_NONE,
    EV_V,
    EV_X_DOWN,
    EV_X_UP,
    RESTITUTION_SWITCH,
    apply_event,
    enter_slow,
    goes_implicit,
    record_poincare,
    sign,
    stiff,
)
from .layout import (
    C_BY_MODE,
    C_DENSE,
    C_DIP,
    C_FALLBACK,
    C_REJECT,
    C_RHS,
    C_STEPS,
    C_TRANSFORMED,
    CONTACT,
    CUT,
    FREE,
    P_EPS,
    P_M,
    P_N3,
    P_T,
    P_XI,
    R_ATOL,
    R_PERIOD,
    R_RTOL,
    R_T_END,
    S_ERRACC,
    S_H,
    S_HACC,
    S_ISEC,
    S_MODE,
    S_NINV,
    S_PHASE,
    S_REJECTED,
    S_S,
    S_SGN,
    S_SLOW,
    S_STATUS,
    S_T,
    S_TAU,
    S_TREF,
    S_V,
    S_V1,
    S_VCUT,
    S_X,
    SLOW_STIFF,
    SQRTH,
    TIME,
    UNDERFLOW_EXPLICIT,
    UVEL,
    WVEL,
)
from .model import accel, stick_force
from .sampling import bisect, sample_window, window_due

BAND = 100.0  # the implicit phase ends when |v| > BAND * eps (friction slope then < 1e-6 T/eps)
DIP_SAMPLES = 32
RESTART_FRACTION = 1e-3  # first step after an event, as a fraction of the step that held it
APPROACH_BAND = 1e4  # within |v| < APPROACH_BAND * eps of a reversal ...
APPROACH_FRACTION = 0.5  # ... a step covers at most this fraction of the time left to v = 0
U_BAND = 1e3  # free flight with |v| < U_BAND * eps, heading for v = 0, runs in s = asinh(v/eps)
# Each transformed variable is regular at one end of its stretch and singular at the other
# (sqrt(h) at v = 0, |v|^n3 at h = 0): stepping away from a singular point is cheap
# (steps grow geometrically), approaching one is not, so each is used only where it moves
# away from its own singularity: sqrt(h) just after onset and before exit, |v|^n3 between.
MIN_S_STEP = 1e-7  # a transformed step below this fraction of its s-range means degeneration
MAX_INVALID = 3  # consecutive invalid transformed steps before falling back to time stepping


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
def _step_factor(st, err, h):
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
    if mode == TIME:
        st[S_TREF] = 0.0
        store(st, ta, x, v, ta, h)
    else:  # a transformed piece measures time from its start (tiny increments stay resolved)
        st[S_TREF] = ta
        store(st, 0.0, x, v, st[S_S], h)
    d0[0], d0[1], d0[2] = dop853.deriv(
        p, mode, int(st[S_PHASE]), st[S_SGN], inverse_n3(p), st[S_S], st[S_TREF], st[S_TAU], x, v
    )
    cnt[C_RHS] += 1


@njit(cache=True, inline="always")  # inlined into core.run: as a call, 7 % slower (A/B, 5 runs)
def time_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target):
    """One DOP853 step in time on the current piece, clamped to t_target (the next Poincare
    time or the end of the run); locates the events inside it and applies the first."""
    K, F, _, d0 = ws
    phase = int(st[S_PHASE])
    t, x, v, h = st[S_TAU], st[S_X], st[S_V], st[S_H]
    rtol, atol = rs[R_RTOL], rs[R_ATOL]
    eps = p[P_EPS]
    q = inverse_n3(p)
    ax = d0[2]
    if h <= 0.0:
        h0 = dop853.initial_step(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, d0[0], d0[1], d0[2], rtol, atol)
        cnt[C_RHS] += 1
        h = h0 if h == 0.0 else min(h0, -h)
    if v * ax < 0.0 and abs(v) < APPROACH_BAND * eps:
        # approaching v = 0, where the friction switches over a time eps/|a|: close in
        # geometrically instead of letting the controller overshoot and reject
        h = min(h, max(APPROACH_FRACTION * abs(v), 0.25 * eps) / abs(ax))
    clamped = h >= t_target - t
    hs = t_target - t if clamped else h
    t1, x1, v1, err = dop853.step(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, d0[0], d0[1], d0[2], hs, rtol, atol, K)
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
    fac = _step_factor(st, err, hs)
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
            dop853.dense_prepare(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, t1, x1, v1, hs, K, F)
            cnt[C_RHS] += 3
            cnt[C_DENSE] += 1
            built = True
            for k in range(1, DIP_SAMPLES):
                if dop853.dense_eval(F, v, k / DIP_SAMPLES, 2) * sgn0 < 0.0:
                    v_cross = True
                    break
    g1 = x1 - p[P_XI]
    x_up = phase == FREE and g1 > 0.0
    x_down = phase != FREE and g1 < 0.0
    cut_on = phase == CONTACT and v1 <= -st[S_VCUT]
    cut_off = phase == CUT and v1 > -st[S_VCUT]
    if v_cross or x_up or x_down or cut_on or cut_off:
        if not built:
            dop853.dense_prepare(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, t1, x1, v1, hs, K, F)
            cnt[C_RHS] += 3
            cnt[C_DENSE] += 1
        th, kind = _first_event(p, st, F, x, v, sgn0, v_cross, x_up, x_down, cut_on, cut_off)
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
            dop853.dense_prepare(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, t1, x1, v1, hs, K, F)
            cnt[C_RHS] += 3
            cnt[C_DENSE] += 1
        sample_window(F, TIME, 0.0, t, x, v, hs, t1, st, rs, win_x, win_v)
    # first-same-as-last; when the step was clamped onto a Poincare time, t + hs can
    # differ from t1 in the last bit: re-evaluate there so a resumed run is identical
    if t + hs == t1:
        d0[0], d0[1], d0[2] = K[12, 0], K[12, 1], K[12, 2]
    else:
        d0[0], d0[1], d0[2] = dop853.deriv(p, TIME, phase, 0.0, q, t1, 0.0, t1, x1, v1)
        cnt[C_RHS] += 1
    store(st, t1, x1, v1, t1, h_next)
    if abs(v1) < BAND * eps and goes_implicit(p, phase, t1, x1):
        enter_slow(p, st, cnt, t1, x1, v1, sign(v1))
    elif (phase == CONTACT or abs(v1) < BAND * eps) and stiff(p, phase, x1, v1, hs):
        enter_slow(p, st, cnt, t1, x1, v1, sign(v1), SLOW_STIFF)
        st[S_H] = hs  # the implicit solver starts from the step that stability held
    elif phase == FREE and p[P_T] > 0.0 and v1 * d0[2] < 0.0 and abs(v1) < U_BAND * eps:
        # heading into the friction band of a reversal: continue in s = sgn asinh(v/eps)
        # (without dry friction there is no band, and time stepping is smooth through v = 0)
        sgn = sign(d0[2])
        st[S_MODE] = UVEL
        st[S_SGN] = sgn
        st[S_S] = sgn * math.asinh(v1 / eps)
        start_piece(p, st, cnt, d0, t1, x1, v1, 0.0)
    return ev, n_ev


@njit(cache=True)
def _first_event(p, st, F, x, v, sgn0, v_cross, x_up, x_down, cut_on, cut_off):
    """The earliest of the candidate events of a time step, on its interpolant F: (theta, kind)."""
    th = 2.0
    kind = EV_NONE
    vcut = st[S_VCUT]
    if v_cross:
        th = bisect(F, v, 2, 0.0, 0.0, 1.0, sgn0)
        kind = EV_V
        if int(st[S_PHASE]) == FREE and sgn0 > 0.0 and dop853.dense_eval(F, x, th, 1) >= p[P_XI]:
            x_up = True  # the maximum lies at or past the obstacle: contact came first
    if x_up:
        th_x = bisect(F, x, 1, p[P_XI], 0.0, th if th <= 1.0 else 1.0, -1.0)
        if th_x <= th:
            th = th_x
            kind = EV_X_UP
    if x_down:
        th_x = bisect(F, x, 1, p[P_XI], 0.0, 1.0, 1.0)
        if th_x < th:
            th = th_x
            kind = EV_X_DOWN
    if cut_on:
        th_c = bisect(F, v, 2, -vcut, 0.0, 1.0, 1.0)
        if th_c < th:
            th = th_c
            kind = EV_CUT_ON
    if cut_off:
        th_c = bisect(F, v, 2, -vcut, 0.0, 1.0, -1.0)
        if th_c < th:
            th = th_c
            kind = EV_CUT_OFF
    return th, kind


@njit(cache=True)
def _mode_end(p, st):
    """Value of s at which the current transformed piece ends (inf: ends by an event)."""
    mode = int(st[S_MODE])
    s = st[S_S]
    if mode == SQRTH:
        return math.inf if st[S_SGN] > 0.0 else 0.0
    if mode == WVEL:
        return 0.0 if st[S_SGN] > 0.0 else st[S_V1] ** p[P_N3]
    # UVEL: first to v = 0 (s = 0), then out of the band
    return 0.0 if s < 0.0 else math.asinh(U_BAND)


@njit(cache=True, inline="always")  # inlined into core.run, as time_step
def transformed_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v):
    """One DOP853 step of a transformed piece in its variable s; t is a component (measured
    from st[S_TREF]). Invalid steps (the map degenerates) shrink, and after MAX_INVALID in a
    row the piece falls back to time stepping."""
    K, F, _, d0 = ws
    mode, phase, sgn, q = int(st[S_MODE]), int(st[S_PHASE]), st[S_SGN], inverse_n3(p)
    s, tref, t, x, v, h = st[S_S], st[S_TREF], st[S_TAU], st[S_X], st[S_V], st[S_H]
    rtol, atol = rs[R_RTOL], rs[R_ATOL]
    s_end = _mode_end(p, st)
    if h <= 0.0:
        if mode == WVEL and sgn < 0.0:  # starts where every derivative vanishes
            h = 0.1 * s_end
        else:
            h = dop853.initial_step(p, mode, phase, sgn, q, s, tref, t, x, v, d0[0], d0[1], d0[2], rtol, atol)
            cnt[C_RHS] += 1
    clamped = s + h >= s_end
    hs = s_end - s if clamped else h
    t1, x1, v1, err = dop853.step(p, mode, phase, sgn, q, s, tref, t, x, v, d0[0], d0[1], d0[2], hs, rtol, atol, K)
    cnt[C_RHS] += 12
    cnt[C_BY_MODE + mode] += 1
    valid = t1 > t and err < math.inf
    for j in range(13):
        if not K[j, 0] >= 0.0:
            valid = False
    if mode == SQRTH and sgn > 0.0 and not v1 > 0.0:
        valid = False
    if valid and err > 1.0:
        h = hs * dop853.new_step_factor(err, False)
        scale = max(abs(s), abs(s_end) if s_end < math.inf else 0.0, 1e-3)
        if h >= MIN_S_STEP * scale:
            cnt[C_REJECT] += 1
            st[S_REJECTED] = 1.0
            st[S_H] = h
            return ev, n_ev
        # steps collapse towards a point where the map degenerates (e.g. the
        # acceleration vanishes before v reaches zero): continue in time instead
        valid = False
        st[S_NINV] = MAX_INVALID - 1
    if not valid:
        cnt[C_REJECT] += 1
        st[S_NINV] += 1
        if st[S_NINV] >= MAX_INVALID:  # the transformation breaks down here: use time
            cnt[C_FALLBACK] += 1
            st[S_NINV] = 0
            st[S_MODE] = TIME
            # a piece heading for v = 0 (the turn in |v|^n3, the band's first half) whose v
            # component already crossed zero by round-off has reached its end: apply the
            # reversal here, or time stepping from the far side would never see it (a
            # penetration went unrecorded this way)
            direction = 1.0 if mode == WVEL else -sgn
            if ((mode == WVEL and sgn > 0.0) or (mode == UVEL and s < 0.0)) and v * direction <= 0.0:
                ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, tref + t, x, v, direction, 0.0)
            start_piece(p, st, cnt, d0, tref + t, x, v, 0.0)
        else:
            st[S_H] = 0.25 * hs
        return ev, n_ev
    st[S_NINV] = 0
    cnt[C_STEPS] += 1
    cnt[C_TRANSFORMED] += 1
    fac = _step_factor(st, err, hs)
    h_next = hs * fac if not clamped else max(h, hs * fac)
    s1 = s_end if clamped else s + hs

    # terminal events inside the step, and what else falls inside it (the run's end,
    # Poincare times, window samples): all from the interpolant of t(s), x(s), v(s)
    kind = _terminal_event(p, st, phase, x1, v1)
    t_stop = tref + t1  # absolute
    inside = t_stop > rs[R_T_END] or t_stop > st[S_ISEC] * rs[R_PERIOD] or window_due(st, rs, win_x, t_stop)
    th_ev = 2.0
    if kind != EV_NONE or inside:
        dop853.dense_prepare(p, mode, phase, sgn, q, s, tref, t, x, v, t1, x1, v1, hs, K, F)
        cnt[C_DENSE] += 1
        cnt[C_RHS] += 3
        th_ev = _locate(p, st, F, x, v, kind)
    th_end = 2.0
    if inside:
        if kind != EV_NONE:
            t_stop = tref + dop853.dense_eval(F, t, th_ev, 0)
        ev, n_ev, th_end = _sections_and_window(st, rs, F, ev, n_ev, win_x, win_v, mode, tref, t, x, v, hs, t_stop)
    t_end = rs[R_T_END]
    if th_end <= 1.0 and th_end < th_ev:  # the run ends inside this piece
        st[S_MODE] = TIME
        st[S_TREF] = 0.0
        store(st, t_end, dop853.dense_eval(F, x, th_end, 1), dop853.dense_eval(F, v, th_end, 2), t_end, 0.0)
        return ev, n_ev
    if kind != EV_NONE:
        te = tref + dop853.dense_eval(F, t, th_ev, 0)
        xe = dop853.dense_eval(F, x, th_ev, 1)
        ve = dop853.dense_eval(F, v, th_ev, 2)
        ev, n_ev, xe, ve = apply_event(p, st, cnt, rs, ev, n_ev, kind, te, xe, ve, 0.0, t1 - t)
        start_piece(p, st, cnt, d0, te, xe, ve, 0.0)  # smooth at its start (free flight) or transformed
        return ev, n_ev

    # accept the step
    if s + hs == s1:
        d0[0], d0[1], d0[2] = K[12, 0], K[12, 1], K[12, 2]
    else:
        d0[0], d0[1], d0[2] = dop853.deriv(p, mode, phase, sgn, q, s1, tref, t1, x1, v1)
        cnt[C_RHS] += 1
    store(st, t1, x1, v1, s1, h_next)
    if clamped:
        ev, n_ev = _transformed_end(p, st, cnt, rs, ev, n_ev, d0, t1 - t)
    elif mode == UVEL and s1 < 0.0 and abs(v1) < BAND * p[P_EPS] and goes_implicit(p, phase, tref + t1, x1):
        # Creeping towards v = 0 where dry friction can hold the cart: hand the band to
        # the implicit solver, as time stepping does. (Without this the explicit
        # asinh piece crept along the stick manifold with steps ~ m eps / T until v
        # crossed 0: the cost of each stick grew like 1/eps.)
        enter_slow(p, st, cnt, tref + t1, x1, v1, sign(v1))
        start_piece(p, st, cnt, d0, tref + t1, x1, v1, 0.0)
    elif mode == SQRTH and sgn > 0.0 and v1 < st[S_V1]:  # slower: |v|^n3 on to v = 0
        ta = tref + t1
        if accel(p, phase, ta, x1, v1) < 0.0:
            st[S_MODE] = WVEL
            st[S_SGN] = 1.0
            st[S_S] = -(v1 ** p[P_N3])
            _switch_variable(p, st, cnt, d0, ta, x1, v1)
        else:
            st[S_MODE] = TIME
            start_piece(p, st, cnt, d0, ta, x1, v1, 0.0)
    return ev, n_ev


@njit(cache=True)
def _switch_variable(p, st, cnt, d0, ta, x, v):
    """Continue the motion in the variable st[S_MODE] (set by the caller): the next step
    covers the time the old variable's next step would have (h_s dt/ds carried over),
    instead of a fresh start from a small step."""
    h_time = st[S_H] * d0[0]
    start_piece(p, st, cnt, d0, ta, x, v, 0.0)
    if h_time > 0.0 and d0[0] > 0.0 and h_time / d0[0] < math.inf:
        st[S_H] = h_time / d0[0]


@njit(cache=True, inline="always")
def _terminal_event(p, st, phase, x1, v1):
    """The event that ends the piece inside a transformed step, judged at the step's end
    (inside a piece x and v are monotone, so a crossing shows there)."""
    if phase == FREE and x1 - p[P_XI] > 0.0:
        return EV_X_UP
    if phase == CONTACT and x1 - p[P_XI] < 0.0:
        return EV_X_DOWN
    if phase == CONTACT and v1 <= -st[S_VCUT]:
        return EV_CUT_ON
    return EV_NONE


@njit(cache=True, inline="always")
def _locate(p, st, F, x, v, kind):
    """Fraction of the step at which the event `kind` happens, on its interpolant F."""
    if kind == EV_X_UP:
        return bisect(F, x, 1, p[P_XI], 0.0, 1.0, -1.0)
    if kind == EV_X_DOWN:
        return bisect(F, x, 1, p[P_XI], 0.0, 1.0, 1.0)
    if kind == EV_CUT_ON:
        return bisect(F, v, 2, -st[S_VCUT], 0.0, 1.0, 1.0)
    return 2.0


@njit(cache=True)
def _sections_and_window(st, rs, F, ev, n_ev, win_x, win_v, mode, tref, t, x, v, hs, t_stop):
    """Poincare times and window samples up to absolute time t_stop inside a transformed
    step (exact times, interpolated state); returns (ev, n_ev, theta at the run's end or 2)."""
    th_end = 2.0
    if t_stop > rs[R_T_END]:
        th_end = bisect(F, t, 0, rs[R_T_END] - tref, 0.0, 1.0, -1.0)
        t_stop = rs[R_T_END]
    t_sec = st[S_ISEC] * rs[R_PERIOD]
    while t_sec < t_stop:
        th = bisect(F, t, 0, t_sec - tref, 0.0, 1.0, -1.0)
        ev, n_ev = record_poincare(
            st, rs, ev, n_ev, t_sec, dop853.dense_eval(F, x, th, 1), dop853.dense_eval(F, v, th, 2)
        )
        t_sec = st[S_ISEC] * rs[R_PERIOD]
    if window_due(st, rs, win_x, t_stop):
        sample_window(F, mode, tref, t, x, v, hs, t_stop, st, rs, win_x, win_v)
    return ev, n_ev, th_end


@njit(cache=True)
def _transformed_end(p, st, cnt, rs, ev, n_ev, d0, dt_step):
    """A transformed piece reached the end of its variable's range: the exit (sqrt(h)), the
    deepest penetration and the switch back to sqrt(h) (|v|^n3), v = 0 and the edge of the
    friction band (asinh(v/eps)). Sets the next piece and starts it."""
    mode, sgn = int(st[S_MODE]), st[S_SGN]
    ta, x, v = st[S_T], st[S_X], st[S_V]
    new_mode = mode
    h = 0.0  # the next piece chooses its first step
    if mode == SQRTH:  # s = 0: exit from the obstacle
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_X_DOWN, ta, x, v, 0.0, dt_step)
        new_mode = TIME
    elif mode == WVEL and sgn > 0.0:  # s = 0: v = 0 at the deepest penetration
        fs = stick_force(p, int(st[S_PHASE]), ta, x)
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, ta, x, v, 1.0, dt_step)
        new_mode = TIME
        if st[S_SLOW] == 0.0 and fs < 0.0:  # restitution: v = -w^q with w from 0 up to |V1|^n3
            new_mode = WVEL
            st[S_SGN] = -1.0
            st[S_S] = 0.0
            st[S_V1] = RESTITUTION_SWITCH * st[S_V1] / CONTACT_SWITCH
    elif mode == WVEL:  # |v| = V1 on the way out: sqrt(h) takes over to the exit
        if x > p[P_XI]:
            st[S_MODE] = SQRTH
            st[S_SGN] = -1.0
            st[S_S] = -math.sqrt(x - p[P_XI])
            _switch_variable(p, st, cnt, d0, ta, x, v)
            return ev, n_ev
        new_mode = TIME
    elif st[S_S] == 0.0:  # UVEL at v = 0: an extremum of x in free flight
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, ta, x, v, -sgn, dt_step)
        if st[S_SLOW] == 0.0:
            # asinh(v/eps) is as smooth through v = 0 as before it: keep the step
            h = st[S_H]
            new_mode = UVEL
        else:
            new_mode = TIME
    else:  # UVEL out of the friction band
        new_mode = TIME
    st[S_MODE] = new_mode
    start_piece(p, st, cnt, d0, ta, x, v, h)
    return ev, n_ev
