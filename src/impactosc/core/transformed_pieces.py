"""DOP853 steps in a piece's own variable s, in which a piece that starts or ends at a singular
point is smooth.

Why a module: contact onset and exit run in sqrt(x - xI), the turn at the deepest
penetration in |v|^n3, and the free-flight friction band in asinh(v/eps) (vector_fields.deriv).
A piece's singular end point (impact side, v = 0, exit) is then an exact end of the piece;
Poincare times and the window come from the interpolant of t(s). :func:`transformed_step`
takes one step; :mod:`impactosc.core.transitions` picks the piece that follows (at an event,
at the end of the variable's range, or when the transformation breaks down).

Next to v = 0 the steps in |v|^n3 shrink all the same (t and x hold the powers w^(i + j / n3)):
there the turn's last steps and the restitution's first are replaced by a series on that
lattice of exponents (:mod:`impactosc.core.turn_series`, :func:`_turn_ends`).
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.core import dop853, turn_series, vector_fields
from impactosc.core.events import EV_CUT_ON, EV_NONE, EV_X_DOWN, EV_X_UP, record_poincare
from impactosc.core.layout import (
    C_BY_MODE,
    C_DENSE,
    C_FALLBACK,
    C_REJECT,
    C_RHS,
    C_STEPS,
    C_TRANSFORMED,
    EXPLICIT,
    R_ATOL,
    R_PERIOD,
    R_RTOL,
    R_T_END,
    S_FIELD,
    S_H,
    S_ISEC,
    S_MODE,
    S_NINV,
    S_REJECTED,
    S_S,
    S_SGN,
    S_SLOW,
    S_T,
    S_TAU,
    S_TREF,
    S_V,
    S_V1,
    S_VCUT,
    S_X,
    SQRTH,
    WVEL,
)
from impactosc.core.pieces import accepted_step_factor, inverse_n3, start_piece, store
from impactosc.core.sampling import bisect, locate_surface, sample_window, window_due
from impactosc.core.transitions import (
    ONSET_SWITCH,
    after_transformed_step,
    apply_event,
    band_edge,
    fall_back_to_time,
    stop_in_piece,
)
from impactosc.model.contact_laws.kernel import SURFACE_CUT, SURFACE_OBSTACLE, contact_force, past_cut
from impactosc.model.equations import CONTACT, FREE
from impactosc.model.parameters import P_M, P_N1, P_N3, P_XI

# Each transformed variable is regular at one end of its stretch and singular at the other
# (sqrt(h) at v = 0, |v|^n3 at h = 0): stepping away from a singular point is cheap
# (steps grow geometrically), approaching one is not, so each is used only where it moves
# away from its own singularity: sqrt(h) just after onset and before exit, |v|^n3 between.
MIN_S_STEP = 1e-7  # a transformed step below this fraction of its s-range means degeneration
MAX_INVALID = 3  # consecutive invalid transformed steps before falling back to time stepping


TURN_REACH = 0.4  # the series' window never reaches beyond w = 0.4: its relative error there is 1e-7 to
# 1e-3 on the chaotic scene's turns (1e-10 to 1e-7 at 0.3), and its estimate above it out to w = 0.5
STEP_AFTER_SERIES = 0.3  # DOP853's first step after the series, as a fraction of w

ONSET_FIRST = 0.3  # the onset's first step in sqrt(x - xI): this fraction of the onset piece's range
ONSET_GROWTH = 0.9  # ... and each next step at most this times the last: they shrink towards the turn's
# singular point (v ~ sqrt of the distance to it in sqrt(x - xI)); Hairer's growth after the first
# step was rejected in 93 % of the contacts (chaotic scene, rtol 1e-10). Attempts per forcing period
# 51.1 -> 49.5 (0.25 and 10 before; 0.3 and 1.0: 49.8, 0.2 and 1.0: 50.4; measured with v set exactly
# in |v|^n3, since kept out: with v integrated the onset is the same piece)
ONSET_PROBE = 1e-6  # m: the penetration at which the law's force is read for that range


@njit(cache=True, inline="always")
def onset_step(p, v0):
    """The first step of a contact onset in sqrt(x - xI), from the piece's expected range: the
    penetration h1 at which the contact has taken 1 - ONSET_SWITCH^2 of the impact's kinetic
    energy, for a force ~ h^1.5 through the law's force at ONSET_PROBE. Hairer's heuristic there
    starts at ~1e-4 of the range (x's and v's derivatives in s vanish at s = 0) and the steps then
    take 6-8 attempts to grow. 0 if the law pushes nothing at the probe."""
    f1 = contact_force(p, p[P_XI] + ONSET_PROBE, v0)
    if not f1 > 0.0:
        return 0.0
    work = 0.5 * (1.0 - ONSET_SWITCH * ONSET_SWITCH) * p[P_M] * v0 * v0
    h1 = (2.5 * work * ONSET_PROBE**1.5 / f1) ** 0.4
    return ONSET_FIRST * math.sqrt(h1)


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
    return 0.0 if s < 0.0 else math.asinh(band_edge(p))


@njit(cache=True, inline="always")  # inlined into core.run, as time_step
def transformed_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v):
    """One DOP853 step of a transformed piece in its variable s; t is a component (measured
    from st[S_TREF]). Invalid steps (the map degenerates) shrink, and after MAX_INVALID in a
    row the piece falls back to time stepping."""
    K, F, _, d0, series = ws
    mode, field, sgn, q = int(st[S_MODE]), int(st[S_FIELD]), st[S_SGN], inverse_n3(p)
    s, tref, t, x, v, h = st[S_S], st[S_TREF], st[S_TAU], st[S_X], st[S_V], st[S_H]
    rtol, atol = rs[R_RTOL], rs[R_ATOL]
    s_end = _mode_end(p, st)
    if mode == WVEL and sgn > 0.0 and s_end == 0.0:
        s_end = _turn_window_end(p, st, rs, s, h)
    if h <= 0.0:
        if mode == WVEL and sgn < 0.0:  # starts where every derivative vanishes
            h = 0.1 * s_end
        elif mode == SQRTH and sgn > 0.0 and s == 0.0:
            h = onset_step(p, v)
            if h <= 0.0:
                h = dop853.initial_step(p, mode, field, sgn, q, s, tref, t, x, v, d0[0], d0[1], d0[2], rtol, atol)
                cnt[C_RHS] += 1
        else:
            h = dop853.initial_step(p, mode, field, sgn, q, s, tref, t, x, v, d0[0], d0[1], d0[2], rtol, atol)
            cnt[C_RHS] += 1
    clamped = s + h >= s_end
    hs = s_end - s if clamped else h
    t1, x1, v1, err = dop853.step(p, mode, field, sgn, q, s, tref, t, x, v, d0[0], d0[1], d0[2], hs, rtol, atol, K)
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
            ev, n_ev = fall_back_to_time(p, st, cnt, rs, ev, n_ev, d0, mode, sgn, s, tref + t, x, v)
        else:
            st[S_H] = 0.25 * hs
        return ev, n_ev
    st[S_NINV] = 0
    cnt[C_STEPS] += 1
    cnt[C_TRANSFORMED] += 1
    fac = accepted_step_factor(st, err, hs)
    if mode == SQRTH and sgn > 0.0:
        fac = min(fac, ONSET_GROWTH)
    h_next = hs * fac if not clamped else max(h, hs * fac)
    s1 = s_end if clamped else s + hs

    # terminal events inside the step, and what else falls inside it (the run's end,
    # Poincare times, window samples): all from the interpolant of t(s), x(s), v(s)
    kind = _terminal_event(p, st, field, x1, v1)
    t_stop = tref + t1  # absolute
    inside = t_stop > rs[R_T_END] or t_stop > st[S_ISEC] * rs[R_PERIOD] or window_due(st, rs, win_x, t_stop)
    th_ev = 2.0
    if kind != EV_NONE or inside:
        dop853.dense_prepare(p, mode, field, sgn, q, s, tref, t, x, v, t1, x1, v1, hs, K, F)
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
        stop_in_piece(st, t_end, dop853.dense_eval(F, x, th_end, 1), dop853.dense_eval(F, v, th_end, 2))
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
        d0[0], d0[1], d0[2] = vector_fields.deriv(p, mode, field, sgn, q, s1, tref, t1, x1, v1)
        cnt[C_RHS] += 1
    store(st, t1, x1, v1, s1, h_next)
    if mode == WVEL and sgn > 0.0 and clamped:  # the turn's end: v = 0, or the series' window
        return _turn_ends(p, st, cnt, rs, ev, n_ev, d0, win_x, field, t1 - t, series)
    return after_transformed_step(
        p, st, cnt, rs, ev, n_ev, d0, clamped, mode, field, sgn, tref + t1, x1, v1, s1, t1 - t
    )


@njit(cache=True)
def _turn_ends(p, st, cnt, rs, ev, n_ev, d0, win_x, field, dt_step, c):
    """The turn's steps reached their end: v = 0 (as before), or the edge of the series' window,
    from which the series takes the turn to v = 0 (when its error there is within the
    tolerance; else the steps go on). The restitution that starts there begins with the series."""
    reached = True
    if st[S_S] < 0.0:
        reached, dt_step = _turn_by_series(p, st, rs, win_x, dt_step, c)
    ev, n_ev = after_transformed_step(
        p, st, cnt, rs, ev, n_ev, d0, reached, WVEL, field, 1.0, st[S_T], st[S_X], st[S_V], st[S_S], dt_step
    )
    if int(st[S_MODE]) == WVEL and st[S_SGN] < 0.0 and st[S_S] == 0.0 and st[S_TAU] == 0.0:
        _restitution_by_series(p, st, cnt, rs, d0, win_x, c)
    return ev, n_ev


@njit(cache=True)
def _series_tol(rs):
    """Relative error allowed in the time increments the series delivers: the step's rtol, within
    [1e-13, 1e-9]. The series' increment (~1e-5 s) is a small part of the piece's time, to which a
    step's rtol applies, so this is the tighter of the two; a looser cap (10 rtol up to 1e-8) made
    the impact times 2-8x worse over seven starts of the chaotic scene. Below 1e-13 the windows shrink to
    where DOP853 is cheap anyway. (Capped at 1e-12 before: windows w ~ 0.22 instead of ~0.3, and
    the step after them, at rtol 1e-9, 10x less accurate over the chaotic scene's starts.)"""
    return max(min(rs[R_RTOL], 1e-9), 1e-13)


@njit(cache=True)
def _clear(st, rs, win_x, t):
    """No Poincare time, window sample or end of the run up to absolute time t: a jump of the
    series to t skips nothing the run must record."""
    return t < rs[R_T_END] and t < st[S_ISEC] * rs[R_PERIOD] and not window_due(st, rs, win_x, t)


@njit(cache=True)
def _turn_window_end(p, st, rs, s, h):
    """Where the turn's DOP853 steps end: at the edge -w_t of the series' window, where the
    series takes over to v = 0 (0 if it does not apply, or the steps are already inside).

    The window is estimated a priori: the series' levels fall off like w^(2q) n1 / (2 |a| h),
    so its reach scales as (2 |a| h / n1)^(n3/2); the factor (0.33 at a relative error of
    1e-12) is the smallest ratio of the true window to that scale over the chaotic scene's turns
    (0.33-0.40), and the error is checked again once the steps arrive."""
    if s + h < -TURN_REACH or int(st[S_SLOW]) != EXPLICIT:
        return 0.0
    if not turn_series.applies(p, int(st[S_FIELD]) == CONTACT):
        return 0.0
    x = st[S_X]
    alpha, beta = turn_series.frozen(p, 1.0, st[S_T], x)
    if not turn_series.usable(p, alpha, beta):
        return 0.0
    tol = _series_tol(rs)
    scale = (2.0 * -alpha * (x - p[P_XI]) / (p[P_M] * p[P_N1])) ** (0.5 * p[P_N3])
    w_t = min(0.33 * (tol / 1e-12) ** 0.055 * scale, TURN_REACH)
    return -w_t if s < -w_t else 0.0


@njit(cache=True)
def _turn_by_series(p, st, rs, win_x, dt_step, c):
    """The turn's steps ended at the window's edge (st, s < 0): find the turn point whose series
    passes through this state and put the piece there (v = 0, s = 0). Returns (reached the
    turn, the time step that led there); when the series does not hold, the steps go on."""
    tref, tau_c, x_c = st[S_TREF], st[S_TAU], st[S_X]
    ok, dt1, x_t = turn_series.turn_point(p, tref + tau_c, x_c, -st[S_S], _series_tol(rs), c)
    if not ok or not _clear(st, rs, win_x, tref + tau_c + dt1):
        return False, dt_step
    store(st, tau_c + dt1, x_t, 0.0, 0.0, st[S_H])
    return True, dt_step + dt1


@njit(cache=True)
def _restitution_by_series(p, st, cnt, rs, d0, win_x, c):
    """The restitution piece starts at the turn point (w = 0): the series carries it to the
    largest w its tolerance allows, and DOP853 goes on from there."""
    if int(st[S_SLOW]) != EXPLICIT or not turn_series.applies(p, int(st[S_FIELD]) == CONTACT):
        return
    tref = st[S_TREF]
    w_end = st[S_V1] ** p[P_N3]
    ok, w, tau, xi = turn_series.restitution(p, tref, st[S_X], w_end, _series_tol(rs), c)
    if not ok or w >= w_end or not _clear(st, rs, win_x, tref + tau):
        return
    q = inverse_n3(p)
    x, v = st[S_X] + xi, -(w**q)
    # the next step: a fraction of w (DOP853's accepted steps there were 0.3-0.5 w)
    store(st, tau, x, v, w, STEP_AFTER_SERIES * w)
    d0[0], d0[1], d0[2] = vector_fields.deriv(p, WVEL, int(st[S_FIELD]), -1.0, q, w, tref, tau, x, v)
    cnt[C_RHS] += 1


@njit(cache=True, inline="always")
def _terminal_event(p, st, field, x1, v1):
    """The event that ends the piece inside a transformed step, judged at the step's end
    (inside a piece x and v are monotone, so a crossing shows there)."""
    if field == FREE and x1 - p[P_XI] > 0.0:
        return EV_X_UP
    if field == CONTACT and x1 - p[P_XI] < 0.0:
        return EV_X_DOWN
    if field == CONTACT and past_cut(p, st[S_VCUT], x1, v1):
        return EV_CUT_ON
    return EV_NONE


@njit(cache=True, inline="always")
def _locate(p, st, F, x, v, kind):
    """Fraction of the step at which the event `kind` happens, on its interpolant F."""
    if kind == EV_X_UP:
        return locate_surface(p, st[S_VCUT], SURFACE_OBSTACLE, F, x, v, 0.0, 1.0, -1.0)
    if kind == EV_X_DOWN:
        return locate_surface(p, st[S_VCUT], SURFACE_OBSTACLE, F, x, v, 0.0, 1.0, 1.0)
    if kind == EV_CUT_ON:
        return locate_surface(p, st[S_VCUT], SURFACE_CUT, F, x, v, 0.0, 1.0, 1.0)
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
