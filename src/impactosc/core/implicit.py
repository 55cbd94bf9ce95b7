"""The implicit phase: sticking, slow reversals and stiff creep, one Radau IIA step at a time.

Entered at v = 0 when dry friction can hold the cart or barely lets it reverse, or when
explicit steps are held by stability (the Hunt-Crossley creep). Ends once |v| leaves the
friction band (|v| > BAND eps) or the step is no longer stiff; the explicit solvers
(time_pieces.py, transformed_pieces.py) then take over. transitions.py decides both. Events
inside a step are located by re-stepping from its start.
"""

from __future__ import annotations

from numba import njit

from impactosc.core import radau
from impactosc.core.events import EV_V, EV_X_DOWN, EV_X_UP, sign
from impactosc.core.layout import (
    C_REJECT,
    C_SLOW_STEPS,
    R_ATOL,
    R_PERIOD,
    R_RTOL,
    S_FIELD,
    S_H,
    S_SLOW,
    S_STATUS,
    S_TAU,
    S_TSLOW,
    S_V,
    S_X,
    SLOW_FRICTION,
    UNDERFLOW_IMPLICIT,
)
from impactosc.core.pieces import store
from impactosc.core.sampling import sample_hermite, window_due
from impactosc.core.transitions import after_implicit_step, apply_event
from impactosc.model.equations import FREE, in_contact
from impactosc.model.parameters import P_EPS, P_M, P_T, P_XI


@njit(cache=True)
def _slow_locate(p, field, t, x, v, h, rtol, atol, work, cnt, c, level, sign_lo):
    """Crossing of component c through level inside an implicit step, by re-stepping."""
    lo = 0.0
    hi = 1.0
    xe, ve = x, v
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        ok, xm, vm = radau.radau_step(p, field, t, x, v, mid * h, rtol, atol, work, cnt)
        if not ok:
            break
        g = (xm if c == 0 else vm) - level
        if g * sign_lo > 0.0:
            lo = mid
        else:
            hi = mid
            xe, ve = xm, vm
    if hi == 1.0:
        ok, xe, ve = radau.radau_step(p, field, t, x, v, h, rtol, atol, work, cnt)
    return hi, xe, ve


@njit(cache=True)
def implicit_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target):
    """One Radau step (error from step doubling) of the implicit phase: sticking, slow
    reversal or stiff creep. Locates obstacle crossings and reversals inside it by re-stepping,
    and ends the phase once |v| leaves the friction band (or the stiffness is gone)."""
    _, _, work, d0, _ = ws
    field = int(st[S_FIELD])
    t, x, v, h = st[S_TAU], st[S_X], st[S_V], st[S_H]
    rtol, atol = rs[R_RTOL], rs[R_ATOL]
    if h <= 0.0:  # first step: the friction time scale, or (stiff creep) the held step
        if st[S_SLOW] == SLOW_FRICTION and p[P_T] > 0.0:
            h = 0.1 * p[P_M] * p[P_EPS] / p[P_T]
        else:
            h = -h if h < 0.0 else 1e-6 * rs[R_PERIOD]
    clamped = h >= t_target - t
    hs = t_target - t if clamped else h
    ok, x1, v1, err = radau.doubled_step(p, field, t, x, v, hs, rtol, atol, work, cnt)
    cnt[C_SLOW_STEPS] += 1
    if not ok or err > 1.0:
        cnt[C_REJECT] += 1
        h = hs * (0.25 if not ok else max(0.2, 0.9 * err ** (-1.0 / 6.0)))
        if h < 1e-14 * max(1.0, abs(t)):
            st[S_STATUS] = UNDERFLOW_IMPLICIT
        st[S_H] = h
        return ev, n_ev
    fac = 5.0 if err == 0.0 else min(5.0, 0.9 * err ** (-1.0 / 6.0))
    h_next = hs * fac if not clamped else max(h, hs * fac)
    t1 = t_target if clamped else t + hs
    # events inside the step: obstacle crossing, v changing sign (not from v = 0 exactly)
    g1 = x1 - p[P_XI]
    hit_x = (field == FREE and g1 > 0.0) or (in_contact(field) and g1 < 0.0)
    # a sign change of v inside the tolerance band (|v| <= atol, e.g. the creep of a cart
    # stuck on the obstacle, ~1e-13 m/s) is noise, not a reversal
    hit_v = abs(v) > atol and abs(v1) > atol and sign(v1) != sign(v)
    if hit_x or hit_v:
        th_x = 2.0
        th_v = 2.0
        xe_x, ve_x, xe_v, ve_v = x, v, x, v
        if hit_x:
            th_x, xe_x, ve_x = _slow_locate(
                p, field, t, x, v, hs, rtol, atol, work, cnt, 0, p[P_XI], -1.0 if field == FREE else 1.0
            )
        if hit_v:
            th_v, xe_v, ve_v = _slow_locate(p, field, t, x, v, hs, rtol, atol, work, cnt, 1, 0.0, sign(v))
        te = min(t + min(th_x, th_v) * hs, t1)
        xe = xe_x if th_x <= th_v else xe_v
        ve = ve_x if th_x <= th_v else ve_v
        if window_due(st, rs, win_x, te):
            sample_hermite(t, x, v, te, xe, ve, st, rs, win_x, win_v)
        st[S_TSLOW] += te - t
        kind = EV_V if th_x > th_v else (EV_X_UP if field == FREE else EV_X_DOWN)
        ev, n_ev, xe, ve = apply_event(p, st, cnt, rs, ev, n_ev, kind, te, xe, ve, sign(v), hs)
        store(st, te, xe, ve, te, h_next)
        return ev, n_ev
    if window_due(st, rs, win_x, t1):
        sample_hermite(t, x, v, t1, x1, v1, st, rs, win_x, win_v)
    st[S_TSLOW] += t1 - t
    store(st, t1, x1, v1, t1, h_next)
    return after_implicit_step(p, st, cnt, rs, ev, n_ev, d0, field, t1, x1, v1, h_next)
