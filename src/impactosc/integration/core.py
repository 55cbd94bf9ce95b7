"""Event-driven integration of model BC: the one numba core every workflow rule shares.

The trajectory is cut into smooth pieces. A piece ends exactly at a contact onset or exit,
at v = 0 (where |v|^n3 and the friction switch live) and at the Hunt-Crossley cut, so no
step of the 8th-order explicit method straddles a non-smooth point. Inside a piece the sign
of v is fixed, hence x is monotone: an obstacle crossing cannot come in an unseen pair, and
the only pair to guard against is v touching zero twice in a step (checked on the dense
output whenever an acceleration bound cannot exclude it).

A piece that starts or ends at a singular point is integrated in a variable in which it is
smooth (dop853.deriv): sqrt(x - xI) next to a contact onset or exit (the force ~ h^1.5),
|v|^n3 around the deepest penetration (the Hunt-Crossley damping ~ |v|^n3), and
asinh(v / eps) through the friction band of a free-flight reversal. The singular point is
then an exact end of the piece, and steps are set by accuracy, not by the singularity.
When v = 0 falls where the net force cannot overcome dry friction (sticking) or barely can
(slow reversal), the piece is handed to the implicit Radau solver until |v| leaves the
friction band again. So is any piece whose explicit steps are held by stability rather
than accuracy (h |da/dv| > STIFF_ENTER): the creep inside the contact where the
Hunt-Crossley damping ~ |v|^n3 balances the other forces (found by randomized testing,
issue 16); it returns to explicit steps once h |da/dv| < STIFF_EXIT. Any transformed
piece that would become invalid (a vanishing acceleration or velocity) falls back to plain
time stepping, which is always correct.

Steps in time land exactly on every Poincare time t_i = i * (2 pi / w) (one
multiplication, no accumulated time); inside a transformed piece the section is located
on the dense output of t(s). A run can be split into calls of at most ``max_steps`` steps
that resume from the saved state (``st``) without changing a single step.

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

from . import dop853, radau
from .layout import (
    C_ATTEMPTS, C_DENSE, C_DIP, C_FALLBACK, C_REJECT, C_RHS, C_SLOW_STEPS, C_SLOW_TRANSIT, C_STEPS, C_STICK, C_STIFF,
    C_TRANSFORMED, CONTACT, CUT, DEFAULT_STEP_BUDGET, FREE, IMPACT, N_COUNT, N_STATE, NEAR_MISS, P_B, P_EPS, P_KI,
    P_M, P_N2, P_N3, P_T, P_XI, PENETRATION, POINCARE, RECORD_IMPACTS, RECORD_NEAR_MISSES, RECORD_PENETRATIONS,
    RECORD_POINCARE, S_BUDGET, S_H, S_ISEC, S_MARK_N, S_MARK_T, S_MODE, S_NINV, S_PDIR, S_PHASE, S_PT, S_PX, S_S,
    S_SGN, S_SLOW, S_STATUS, S_T, S_TAU, S_TREF, S_TSLOW, S_V, S_V1, S_VCUT, S_WIN, S_X, SLOW_FRICTION, SLOW_STIFF,
    SQRTH, STALLED, TIME, UNDERFLOW_EXPLICIT, UNDERFLOW_IMPLICIT, UVEL, WVEL,
)
from .model import accel, damping_rate, stick_force

BAND = 100.0  # the implicit phase ends when |v| > BAND * eps (friction slope then < 1e-6 T/eps)
SLOW_FACTOR = 1.5  # v = 0 with |net force| < 1.5 T: stick or slow reversal -> implicit phase
DIP_SAMPLES = 32
RESTART_FRACTION = 1e-3  # first step after an event, as a fraction of the step that held it
APPROACH_BAND = 1e4  # within |v| < APPROACH_BAND * eps of a reversal ...
APPROACH_FRACTION = 0.5  # ... a step covers at most this fraction of the time left to v = 0
U_BAND = 1e3  # free flight with |v| < U_BAND * eps, heading for v = 0, runs in s = asinh(v/eps)
CONTACT_SWITCH = 0.95  # in contact, sqrt(x - xI) while v > 0.95 v_onset, then |v|^n3 ...
RESTITUTION_SWITCH = 0.2  # ... until |v| = 0.2 v_onset on the way out, then sqrt(x - xI)
# Each transformed variable is regular at one end of its stretch and singular at the other
# (sqrt(h) at v = 0, |v|^n3 at h = 0): stepping away from a singular point is cheap
# (steps grow geometrically), approaching one is not, so each is used only where it moves
# away from its own singularity: sqrt(h) just after onset and before exit, |v|^n3 between.
STIFF_ENTER = 4.0  # h |da/dv| above this: explicit steps are held by stability, not accuracy ...
STIFF_EXIT = 1.0  # ... and the implicit phase that takes over ends once h |da/dv| is below this
# (DOP853 is stable to h |da/dv| ~ 6 on the negative real axis; the gap is a hysteresis.)
MIN_S_STEP = 1e-7  # a transformed step below this fraction of its s-range means degeneration
MAX_INVALID = 3  # consecutive invalid transformed steps before falling back to time stepping

# event candidates inside one explicit step
_EV_NONE, _EV_X_UP, _EV_X_DOWN, _EV_V, _EV_CUT_ON, _EV_CUT_OFF = range(6)

@njit(cache=True)
def _push(ev, n, kind, t, a, b):
    if n >= ev.shape[0]:
        grown = np.empty((2 * ev.shape[0], 4))
        grown[:n] = ev[:n]
        ev = grown
    ev[n, 0] = kind
    ev[n, 1] = t
    ev[n, 2] = a
    ev[n, 3] = b
    return ev, n + 1


@njit(cache=True)
def _sign(a):
    return 1.0 if a > 0.0 else (-1.0 if a < 0.0 else 0.0)


@njit(cache=True)
def _bisect(F, y0, c, level, lo, hi, sign_lo):
    """Crossing of component c through `level` in (lo, hi]; returns the first theta past it."""
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        g = dop853.dense_eval(F, y0, mid, c) - level
        if g * sign_lo > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def _phase_of(p, x, v, vcut):
    if x - p[P_XI] >= 0.0:
        return CONTACT if v > -vcut else CUT
    return FREE


@njit(cache=True)
def _sample_window(F, mode, tref, t0, x0, v0, h, t1, st, win_t0, win_dt, win_x, win_v):
    """Fill the window samples due up to absolute time t1 from the step's dense output
    (whose time component starts at t0, measured from tref)."""
    j = int(st[S_WIN])
    n = win_x.shape[0]
    while j < n:
        ts = win_t0 + j * win_dt
        if ts > t1:
            break
        if mode == TIME:
            th = (ts - t0) / h
        else:  # t is a component: invert the monotone t(s)
            th = _bisect(F, t0, 0, ts - tref, 0.0, 1.0, -1.0)
        win_x[j] = dop853.dense_eval(F, x0, th, 1)
        win_v[j] = dop853.dense_eval(F, v0, th, 2)
        j += 1
    st[S_WIN] = j


@njit(cache=True)
def _sample_hermite(t0, x0, v0, t1, x1, v1, st, win_t0, win_dt, win_x, win_v):
    """Window samples inside an implicit (sticking) step: cubic Hermite in x (x' = v known
    at both ends), linear in v; the creep inside such a step is slow and smooth."""
    j = int(st[S_WIN])
    n = win_x.shape[0]
    h = t1 - t0
    while j < n:
        ts = win_t0 + j * win_dt
        if ts > t1:
            break
        th = (ts - t0) / h if h > 0.0 else 1.0
        h00 = (1.0 + 2.0 * th) * (1.0 - th) ** 2
        h10 = th * (1.0 - th) ** 2
        h01 = th * th * (3.0 - 2.0 * th)
        h11 = th * th * (th - 1.0)
        win_x[j] = h00 * x0 + h10 * h * v0 + h01 * x1 + h11 * h * v1
        win_v[j] = v0 + th * (v1 - v0)
        j += 1
    st[S_WIN] = j


@njit(cache=True)
def _window_due(st, win_t0, win_dt, win_x, t1):
    j = int(st[S_WIN])
    return j < win_x.shape[0] and win_t0 + j * win_dt <= t1


@njit(cache=True)
def _goes_implicit(p, phase, t, x):
    """At v = 0, a net force below 1.5 T means sticking or a slow reversal: the friction
    band is then crossed (or held) by the implicit solver."""
    return abs(stick_force(p, phase, t, x)) < SLOW_FACTOR * p[P_T]


@njit(cache=True)
def _stiff(p, phase, x, v, h):
    """True when a step of size h is held by stability: h |da/dv| beyond STIFF_ENTER.

    The Hunt-Crossley damping ~ |v|^n3 (n3 << 1) acts inside the contact like a very stiff
    dry friction: where the elastic and external forces nearly balance, the cart creeps at
    a tiny velocity and da/dv ~ |v|^(n3 - 1) grows without bound, so an explicit method is
    pinned to steps ~ 6 / |da/dv| (1e-9 s and shrinking: the stall of issue 16).
    """
    return damping_rate(p, phase, x, v) * h > STIFF_ENTER


@njit(cache=True)
def _creeps(p, phase, t, x, h):
    """At v = 0 in contact: will the motion that follows be a stiff creep?

    With net force f (damping aside), v grows until the Hunt-Crossley damping balances f,
    at the creep velocity v_c = (|f| / (kI b h^n2))^(1/n3), where -da/dv = n3 |f| / (m v_c).
    Stiff (hand it to the implicit solver) when that rate times the step h exceeds STIFF_ENTER.
    """
    if phase != CONTACT or p[P_B] <= 0.0 or not (0.0 < p[P_N3] < 1.0):
        return False
    depth = x - p[P_XI]
    if depth <= 0.0:
        return False
    f = abs(stick_force(p, phase, t, x))
    if f == 0.0:
        return True
    scale = p[P_KI] * p[P_B] * depth ** p[P_N2]
    vc = (f / scale) ** (1.0 / p[P_N3])
    if vc == 0.0:
        return True
    return p[P_N3] * f / (p[P_M] * vc) * h > STIFF_ENTER


@njit(cache=True)
def _enter_slow(p, st, cnt, t, x, v, direction, why=SLOW_FRICTION):
    """Start the implicit phase; `direction` is the sign v had before it reached the band."""
    if why == SLOW_STIFF:
        cnt[C_STIFF] += 1
    elif abs(stick_force(p, int(st[S_PHASE]), t, x)) < p[P_T]:
        cnt[C_STICK] += 1
    else:
        cnt[C_SLOW_TRANSIT] += 1
    st[S_SLOW] = float(why)
    st[S_MODE] = TIME
    st[S_PDIR] = direction
    st[S_PT] = t
    st[S_PX] = x
    st[S_H] = 0.0


@njit(cache=True)
def _record_extremum(p, ev, n, flags, t_record, phase, t, x, direction):
    """A maximum of x (direction +1) is a penetration in contact, a near miss in flight."""
    if direction > 0.0 and t >= t_record:
        if phase == CONTACT and flags & RECORD_PENETRATIONS:
            ev, n = _push(ev, n, PENETRATION, t, x - p[P_XI], 0.0)
        elif phase == FREE and flags & RECORD_NEAR_MISSES:
            ev, n = _push(ev, n, NEAR_MISS, t, p[P_XI] - x, 0.0)
    return ev, n


@njit(cache=True)
def _slow_locate(p, phase, t, x, v, h, rtol, atol, work, cnt, c, level, sign_lo):
    """Crossing of component c through level inside an implicit step, by re-stepping."""
    lo = 0.0
    hi = 1.0
    xe, ve = x, v
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        ok, xm, vm = radau.radau_step(p, phase, t, x, v, mid * h, rtol, atol, work, cnt)
        if not ok:
            break
        g = (xm if c == 0 else vm) - level
        if g * sign_lo > 0.0:
            lo = mid
        else:
            hi = mid
            xe, ve = xm, vm
    if hi == 1.0:
        ok, xe, ve = radau.radau_step(p, phase, t, x, v, h, rtol, atol, work, cnt)
    return hi, xe, ve


@njit(cache=True)
def _contact_mode(p, st, t, x, v):
    """Mode for a contact piece starting at (t, x, v) with v > 0 (onset): sqrt(h) while the
    velocity is well away from zero, |v|^n3 when it already is small; time otherwise."""
    if p[P_B] <= 0.0 or not (0.0 < p[P_N3] < 1.0) or v <= 0.0:
        st[S_MODE] = TIME
        return
    a = accel(p, CONTACT, t, x, v)
    st[S_V1] = CONTACT_SWITCH * v
    if x - p[P_XI] <= 0.0 and v > 1e3 * p[P_EPS]:
        st[S_MODE] = SQRTH
        st[S_SGN] = 1.0
        st[S_S] = 0.0
    elif a < 0.0:
        st[S_MODE] = WVEL
        st[S_SGN] = 1.0
        st[S_S] = -(v ** p[P_N3])
    else:
        st[S_MODE] = TIME


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


@njit(cache=True)
def run(p, st, cnt, t_end, t_record, rtol, atol, flags, period, ev, n_ev, win_t0, win_dt, win_x, win_v, max_steps):
    """Integrate from the state ``st`` towards ``t_end``; events at t >= t_record go to ``ev``.

    flags: layout.RECORD_* bits (impacts, penetrations, near misses, Poincare points). Returns after
    t_end or after `max_steps` step attempts, with ``st``/``cnt`` updated in place so the
    next call continues the same trajectory. Returns (ev, n_ev) (ev may be reallocated).
    """
    K = np.zeros((16, 3))
    F = np.zeros((7, 3))
    work = np.zeros((8, 6))
    eps = p[P_EPS]
    vband = BAND * eps
    vcut = st[S_VCUT]
    q = 1.0 / p[P_N3] if p[P_N3] > 0.0 else 0.0
    t = st[S_T]
    x = st[S_X]
    v = st[S_V]
    phase = int(st[S_PHASE])
    mode = int(st[S_MODE])
    tref = st[S_TREF] if mode != TIME else 0.0
    if mode != TIME:
        t = st[S_TAU]
    s = st[S_S] if mode != TIME else t
    sgn = st[S_SGN]
    h = st[S_H]
    n_invalid = int(st[S_NINV])
    d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
    cnt[C_RHS] += 1
    friction_jump = 2.0 * p[P_T] / p[P_M]
    steps = 0

    while True:
        i_sec = st[S_ISEC]
        t_sec = i_sec * period
        if t >= t_sec and mode == TIME:  # landed on a Poincare time (time steps are clamped to it)
            if flags & RECORD_POINCARE and t_sec >= t_record:
                ev, n_ev = _push(ev, n_ev, POINCARE, t_sec, x, v)
            st[S_ISEC] = i_sec + 1.0
            continue
        if tref + t >= t_end or steps >= max_steps:
            break
        steps += 1
        cnt[C_ATTEMPTS] += 1
        if cnt[C_ATTEMPTS] - st[S_MARK_N] >= st[S_BUDGET]:  # watchdog: a period per budget
            if tref + t - st[S_MARK_T] < period:
                st[S_STATUS] = STALLED
                break
            st[S_MARK_N] = cnt[C_ATTEMPTS]
            st[S_MARK_T] = tref + t
        t_target = min(t_end, t_sec)
        if st[S_SLOW] != 0.0:
            # ---------------- implicit phase: sticking or slow reversal ----------------
            if h <= 0.0:  # first step: the friction time scale, or (stiff creep) the held step
                if st[S_SLOW] == SLOW_FRICTION and p[P_T] > 0.0:
                    h = 0.1 * p[P_M] * eps / p[P_T]
                else:
                    h = -h if h < 0.0 else 1e-6 * period
            clamped = h >= t_target - t
            hs = t_target - t if clamped else h
            ok, x1, v1, err = radau.doubled_step(p, phase, t, x, v, hs, rtol, atol, work, cnt)
            cnt[C_SLOW_STEPS] += 1
            if not ok or err > 1.0:
                cnt[C_REJECT] += 1
                fac = 0.25 if not ok else max(0.2, 0.9 * err ** (-1.0 / 6.0))
                h = hs * fac
                if h < 1e-14 * max(1.0, abs(t)):
                    st[S_STATUS] = UNDERFLOW_IMPLICIT
                    break
                continue
            fac = 5.0 if err == 0.0 else min(5.0, 0.9 * err ** (-1.0 / 6.0))
            h_next = hs * fac if not clamped else max(h, hs * fac)
            t1 = t_target if clamped else t + hs
            # events inside the step: obstacle crossing, v changing sign (not from v = 0 exactly)
            g1 = x1 - p[P_XI]
            hit_x = (phase == FREE and g1 > 0.0) or (phase == CONTACT and g1 < 0.0)
            # a sign change of v inside the tolerance band (|v| <= atol, e.g. the creep of a cart
            # stuck on the obstacle, ~1e-13 m/s) is noise, not a reversal
            hit_v = abs(v) > atol and abs(v1) > atol and _sign(v1) != _sign(v)
            if hit_x or hit_v:
                th_x = 2.0
                th_v = 2.0
                xe_x, ve_x, xe_v, ve_v = x, v, x, v
                if hit_x:
                    th_x, xe_x, ve_x = _slow_locate(p, phase, t, x, v, hs, rtol, atol, work, cnt, 0, p[P_XI],
                                                    -1.0 if phase == FREE else 1.0)
                if hit_v:
                    th_v, xe_v, ve_v = _slow_locate(p, phase, t, x, v, hs, rtol, atol, work, cnt, 1, 0.0, _sign(v))
                th = min(th_x, th_v)
                te = min(t + th * hs, t1)
                if _window_due(st, win_t0, win_dt, win_x, te):
                    xe = xe_x if th_x <= th_v else xe_v
                    ve = ve_x if th_x <= th_v else ve_v
                    _sample_hermite(t, x, v, te, xe, ve, st, win_t0, win_dt, win_x, win_v)
                st[S_TSLOW] += te - t
                if th_x <= th_v:
                    if phase == FREE:
                        if flags & RECORD_IMPACTS and te >= t_record:
                            ev, n_ev = _push(ev, n_ev, IMPACT, te, ve_x, 0.0)
                        phase = CONTACT
                        st[S_PDIR] = 0.0  # the pending free-flight maximum became a contact
                    else:
                        phase = FREE
                    t, x, v = te, p[P_XI], ve_x
                else:
                    if _sign(v) == st[S_PDIR]:  # reversal against the pre-stick direction
                        st[S_PT] = te
                        st[S_PX] = xe_v
                    t, x, v = te, xe_v, 0.0
                st[S_PHASE] = phase
                h = h_next
                continue
            if _window_due(st, win_t0, win_dt, win_x, t1):
                _sample_hermite(t, x, v, t1, x1, v1, st, win_t0, win_dt, win_x, win_v)
            st[S_TSLOW] += t1 - t
            t, x, v = t1, x1, v1
            h = h_next
            if st[S_SLOW] == SLOW_STIFF:
                leave = damping_rate(p, phase, x, v) * h < STIFF_EXIT
            else:
                leave = abs(v) > vband
            if leave:
                if _sign(v) == -st[S_PDIR]:
                    ev, n_ev = _record_extremum(p, ev, n_ev, flags, t_record, phase, st[S_PT], st[S_PX], st[S_PDIR])
                st[S_SLOW] = 0.0
                st[S_PDIR] = 0.0
                mode = TIME
                s = t
                d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
                cnt[C_RHS] += 1
                h = 0.0
            continue

        if mode != TIME:
            # ------------- transformed piece: s is sqrt(h), |v|^n3 or asinh(v/eps) -------------
            # the time component t is measured from tref, the start of the piece
            s_end = _mode_end(p, st)
            if h <= 0.0:
                if mode == WVEL and sgn < 0.0:  # starts where every derivative vanishes
                    h = 0.1 * s_end
                else:
                    h = dop853.initial_step(p, mode, phase, sgn, q, s, tref, t, x, v, d0t, d0x, d0v, rtol, atol)
                    cnt[C_RHS] += 1
            clamped = s + h >= s_end
            hs = s_end - s if clamped else h
            t1, x1, v1, err = dop853.step(p, mode, phase, sgn, q, s, tref, t, x, v, d0t, d0x, d0v, hs, rtol, atol, K)
            cnt[C_RHS] += 12
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
                    continue
                # steps collapse towards a point where the map degenerates (e.g. the
                # acceleration vanishes before v reaches zero): continue in time instead
                valid = False
                n_invalid = MAX_INVALID - 1
            if not valid:
                cnt[C_REJECT] += 1
                n_invalid += 1
                st[S_NINV] = n_invalid
                if n_invalid >= MAX_INVALID:  # the transformation breaks down here: use time
                    cnt[C_FALLBACK] += 1
                    n_invalid = 0
                    st[S_NINV] = 0
                    t = tref + t
                    tref = 0.0
                    mode = TIME
                    st[S_MODE] = TIME
                    s = t
                    d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
                    cnt[C_RHS] += 1
                    h = 0.0
                    continue
                h = 0.25 * hs
                continue
            n_invalid = 0
            st[S_NINV] = 0
            cnt[C_STEPS] += 1
            cnt[C_TRANSFORMED] += 1
            fac = dop853.new_step_factor(err, False)
            h_next = hs * fac if not clamped else max(h, hs * fac)
            s1 = s_end if clamped else s + hs
            built = False
            # terminal events and the end of the run inside the step
            th_ev = 2.0
            kind = _EV_NONE
            if phase == FREE and x1 - p[P_XI] > 0.0:
                dop853.dense_prepare(p, mode, phase, sgn, q, s, tref, t, x, v, t1, x1, v1, hs, K, F)
                built = True
                th_ev = _bisect(F, x, 1, p[P_XI], 0.0, 1.0, -1.0)
                kind = _EV_X_UP
            elif phase == CONTACT and x1 - p[P_XI] < 0.0:
                dop853.dense_prepare(p, mode, phase, sgn, q, s, tref, t, x, v, t1, x1, v1, hs, K, F)
                built = True
                th_ev = _bisect(F, x, 1, p[P_XI], 0.0, 1.0, 1.0)
                kind = _EV_X_DOWN
            elif phase == CONTACT and v1 <= -vcut:
                dop853.dense_prepare(p, mode, phase, sgn, q, s, tref, t, x, v, t1, x1, v1, hs, K, F)
                built = True
                th_ev = _bisect(F, v, 2, -vcut, 0.0, 1.0, 1.0)
                kind = _EV_CUT_ON
            if built:
                cnt[C_DENSE] += 1
                cnt[C_RHS] += 3
            th_end = 2.0
            t_stop = tref + t1  # absolute
            if t_stop > t_end or t_stop > t_sec or _window_due(st, win_t0, win_dt, win_x, t_stop):
                if not built:
                    dop853.dense_prepare(p, mode, phase, sgn, q, s, tref, t, x, v, t1, x1, v1, hs, K, F)
                    cnt[C_DENSE] += 1
                    cnt[C_RHS] += 3
                    built = True
                if kind != _EV_NONE:
                    t_stop = tref + dop853.dense_eval(F, t, th_ev, 0)
                if t_stop > t_end:
                    th_end = _bisect(F, t, 0, t_end - tref, 0.0, 1.0, -1.0)
                    t_stop = t_end
                while t_sec < t_stop:  # Poincare times inside the piece: exact t, interpolated state
                    th = _bisect(F, t, 0, t_sec - tref, 0.0, 1.0, -1.0)
                    if flags & RECORD_POINCARE and t_sec >= t_record:
                        ev, n_ev = _push(ev, n_ev, POINCARE, t_sec, dop853.dense_eval(F, x, th, 1),
                                         dop853.dense_eval(F, v, th, 2))
                    i_sec += 1.0
                    st[S_ISEC] = i_sec
                    t_sec = i_sec * period
                if _window_due(st, win_t0, win_dt, win_x, t_stop):
                    _sample_window(F, mode, tref, t, x, v, hs, t_stop, st, win_t0, win_dt, win_x, win_v)
            if th_end <= 1.0 and th_end < th_ev:  # the run ends inside this piece
                x = dop853.dense_eval(F, x, th_end, 1)
                v = dop853.dense_eval(F, v, th_end, 2)
                t = t_end
                tref = 0.0
                mode = TIME
                st[S_MODE] = TIME
                s = t
                h = 0.0
                continue
            if kind != _EV_NONE:
                te = tref + dop853.dense_eval(F, t, th_ev, 0)
                xe = dop853.dense_eval(F, x, th_ev, 1)
                ve = dop853.dense_eval(F, v, th_ev, 2)
                if kind == _EV_X_UP:
                    xe = p[P_XI]
                    if flags & RECORD_IMPACTS and te >= t_record:
                        ev, n_ev = _push(ev, n_ev, IMPACT, te, ve, 0.0)
                    phase = CONTACT
                    _contact_mode(p, st, te, xe, ve)
                elif kind == _EV_X_DOWN:
                    xe = p[P_XI]
                    phase = FREE
                    st[S_MODE] = TIME
                else:
                    ve = -vcut
                    phase = CUT
                    st[S_MODE] = TIME
                x, v = xe, ve
                st[S_PHASE] = phase
                mode = int(st[S_MODE])
                if mode == TIME:
                    tref = 0.0
                    t = te
                    s = t
                else:
                    tref = te
                    t = 0.0
                    s = st[S_S]
                sgn = st[S_SGN]
                d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
                cnt[C_RHS] += 1
                h = 0.0  # the new piece is smooth at its start (free flight) or transformed
                continue
            # accept the step
            if s + hs == s1:
                d0t, d0x, d0v = K[12, 0], K[12, 1], K[12, 2]
            else:
                d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s1, tref, t1, x1, v1)
                cnt[C_RHS] += 1
            dt_step = t1 - t  # the time the accepted step covered
            t, x, v, s = t1, x1, v1, s1
            h = h_next
            new_mode = mode
            ta = tref + t  # absolute time
            if clamped:
                if mode == SQRTH:  # s = 0: exit from the obstacle
                    x = p[P_XI]
                    phase = FREE
                    new_mode = TIME
                elif mode == WVEL and sgn > 0.0:  # s = 0: v = 0 at the deepest penetration
                    v = 0.0
                    fs = stick_force(p, phase, ta, x)
                    st[S_PHASE] = phase
                    if _goes_implicit(p, phase, ta, x):
                        _enter_slow(p, st, cnt, ta, x, v, 1.0)
                        new_mode = TIME
                    elif _creeps(p, phase, ta, x, dt_step):
                        _enter_slow(p, st, cnt, ta, x, v, 1.0, SLOW_STIFF)
                        new_mode = TIME
                    else:
                        ev, n_ev = _record_extremum(p, ev, n_ev, flags, t_record, phase, ta, x, 1.0)
                        if fs < 0.0:  # restitution: v = -w^q with w from 0 up to |V1|^n3
                            sgn = -1.0
                            s = 0.0
                            st[S_V1] = RESTITUTION_SWITCH * st[S_V1] / CONTACT_SWITCH
                        else:
                            new_mode = TIME
                elif mode == WVEL:  # |v| = V1 on the way out: sqrt(h) takes over to the exit
                    if x > p[P_XI]:
                        new_mode = SQRTH
                        sgn = -1.0
                        s = -math.sqrt(x - p[P_XI])
                    else:
                        new_mode = TIME
                elif s == 0.0:  # UVEL at v = 0: an extremum of x in free flight
                    v = 0.0
                    direction = -sgn  # v had the sign opposite to the acceleration
                    st[S_PHASE] = phase
                    if _goes_implicit(p, phase, ta, x):
                        _enter_slow(p, st, cnt, ta, x, v, direction)
                        new_mode = TIME
                    else:
                        ev, n_ev = _record_extremum(p, ev, n_ev, flags, t_record, phase, ta, x, direction)
                else:  # UVEL out of the friction band
                    new_mode = TIME
            elif mode == UVEL and s < 0.0 and abs(v) < vband and _goes_implicit(p, phase, ta, x):
                # Creeping towards v = 0 where dry friction can hold the cart: hand the band to
                # the implicit solver, as time stepping does. (Without this the explicit
                # asinh piece crept along the stick manifold with steps ~ m eps / T until v
                # crossed 0: the cost of each stick grew like 1/eps - issue 7, sticking.)
                _enter_slow(p, st, cnt, ta, x, v, _sign(v))
                new_mode = TIME
            elif mode == SQRTH and sgn > 0.0 and v < st[S_V1]:  # slower: |v|^n3 on to v = 0
                if accel(p, phase, ta, x, v) < 0.0:
                    new_mode = WVEL
                    sgn = 1.0
                    s = -(v ** p[P_N3])
                else:
                    new_mode = TIME
            if new_mode != mode or clamped:
                mode = new_mode
                st[S_MODE] = mode
                st[S_SGN] = sgn
                st[S_PHASE] = phase
                if mode == TIME:
                    tref = 0.0
                    t = ta
                    s = t
                else:
                    tref = ta
                    t = 0.0
                st[S_S] = s
                d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
                cnt[C_RHS] += 1
                h = 0.0
            continue

        # ---------------- time stepping: DOP853 on one smooth piece ----------------
        ax = d0v
        if h <= 0.0:
            h0 = dop853.initial_step(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, d0t, d0x, d0v, rtol, atol)
            cnt[C_RHS] += 1
            h = h0 if h == 0.0 else min(h0, -h)
        if v * ax < 0.0 and abs(v) < APPROACH_BAND * eps:
            # approaching v = 0, where the friction switches over a time eps/|a|: close in
            # geometrically instead of letting the controller overshoot and reject
            h = min(h, max(APPROACH_FRACTION * abs(v), 0.25 * eps) / abs(ax))
        clamped = h >= t_target - t
        hs = t_target - t if clamped else h
        t1, x1, v1, err = dop853.step(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, d0t, d0x, d0v, hs, rtol, atol, K)
        cnt[C_RHS] += 12
        if err > 1.0:
            cnt[C_REJECT] += 1
            h = hs * dop853.new_step_factor(err, False)
            if h < 4e-16 * max(1.0, abs(t)):
                st[S_STATUS] = UNDERFLOW_EXPLICIT
                break
            continue
        cnt[C_STEPS] += 1
        fac = dop853.new_step_factor(err, False)
        h_next = hs * fac if not clamped else max(h, hs * fac)
        t1 = t_target if clamped else t + hs
        built = False

        # --- candidate events in this step ---
        sgn0 = _sign(v) if v != 0.0 else _sign(ax)
        if sgn0 == 0.0:
            sgn0 = _sign(v1)
        v_cross = v1 != 0.0 and _sign(v1) != sgn0 and sgn0 != 0.0
        if not v_cross and sgn0 != 0.0:
            # v keeps its sign at both ends; can it have touched zero in between?
            amax = 0.0
            for j in range(13):
                amax = max(amax, abs(K[j, 2]))
            if abs(v) + abs(v1) - (2.0 * amax + friction_jump) * hs <= 0.0:
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
        cut_on = phase == CONTACT and v1 <= -vcut
        cut_off = phase == CUT and v1 > -vcut
        if v_cross or x_up or x_down or cut_on or cut_off:
            if not built:
                dop853.dense_prepare(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, t1, x1, v1, hs, K, F)
                cnt[C_RHS] += 3
                cnt[C_DENSE] += 1
                built = True
            th = 2.0
            kind = _EV_NONE
            if v_cross:
                th_v = _bisect(F, v, 2, 0.0, 0.0, 1.0, sgn0)
                th = th_v
                kind = _EV_V
                if phase == FREE and sgn0 > 0.0 and dop853.dense_eval(F, x, th_v, 1) >= p[P_XI]:
                    x_up = True  # the maximum lies at or past the obstacle: contact came first
            if x_up:
                hi = th if th <= 1.0 else 1.0
                th_x = _bisect(F, x, 1, p[P_XI], 0.0, hi, -1.0)
                if th_x <= th:
                    th = th_x
                    kind = _EV_X_UP
            if x_down:
                th_x = _bisect(F, x, 1, p[P_XI], 0.0, 1.0, 1.0)
                if th_x < th:
                    th = th_x
                    kind = _EV_X_DOWN
            if cut_on:
                th_c = _bisect(F, v, 2, -vcut, 0.0, 1.0, 1.0)
                if th_c < th:
                    th = th_c
                    kind = _EV_CUT_ON
            if cut_off:
                th_c = _bisect(F, v, 2, -vcut, 0.0, 1.0, -1.0)
                if th_c < th:
                    th = th_c
                    kind = _EV_CUT_OFF
            te = t1 if th >= 1.0 else min(t + th * hs, t1)
            xe = dop853.dense_eval(F, x, th, 1)
            ve = dop853.dense_eval(F, v, th, 2)
            if _window_due(st, win_t0, win_dt, win_x, te):
                _sample_window(F, TIME, 0.0, t, x, v, hs, te, st, win_t0, win_dt, win_x, win_v)
            st[S_MODE] = TIME
            if kind == _EV_X_UP:
                xe = p[P_XI]
                if flags & RECORD_IMPACTS and te >= t_record:
                    ev, n_ev = _push(ev, n_ev, IMPACT, te, ve, 0.0)
                phase = CONTACT if ve > -vcut else CUT
                if phase == CONTACT:
                    _contact_mode(p, st, te, xe, ve)
            elif kind == _EV_X_DOWN:
                xe = p[P_XI]
                phase = FREE
            elif kind == _EV_CUT_ON:
                ve = -vcut
                phase = CUT
            elif kind == _EV_CUT_OFF:
                ve = -vcut
                phase = CONTACT
            else:  # v = 0: an extremum of x; sticking or slow reversal goes implicit
                ve = 0.0
                fs = stick_force(p, phase, te, xe)
                st[S_PHASE] = phase
                if _goes_implicit(p, phase, te, xe):
                    _enter_slow(p, st, cnt, te, xe, ve, sgn0)
                elif _creeps(p, phase, te, xe, hs):
                    _enter_slow(p, st, cnt, te, xe, ve, sgn0, SLOW_STIFF)
                else:
                    ev, n_ev = _record_extremum(p, ev, n_ev, flags, t_record, phase, te, xe, sgn0)
            t, x, v = te, xe, ve
            st[S_PHASE] = phase
            mode = int(st[S_MODE])
            sgn = st[S_SGN]
            s = st[S_S] if mode != TIME else t
            if mode != TIME:
                tref = t
                t = 0.0
            d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
            cnt[C_RHS] += 1
            # restart the step-size selection on the new piece, from a small first step: the
            # friction switch (width eps/|a| in time) or |v|^n3 start right at v = 0, and the
            # h^1.5 contact onset, are resolved by growing steps (x10 each) far more cheaply
            # than by rejecting a large guess (x0.2 each, 12 evaluations lost every time).
            h = -RESTART_FRACTION * hs if mode == TIME else 0.0
            continue

        # --- no event: accept the step ---
        if _window_due(st, win_t0, win_dt, win_x, t1):
            if not built:
                dop853.dense_prepare(p, TIME, phase, 0.0, q, t, 0.0, t, x, v, t1, x1, v1, hs, K, F)
                cnt[C_RHS] += 3
                cnt[C_DENSE] += 1
                built = True
            _sample_window(F, TIME, 0.0, t, x, v, hs, t1, st, win_t0, win_dt, win_x, win_v)
        # first-same-as-last; when the step was clamped onto a Poincare time, t + hs can
        # differ from t1 in the last bit: re-evaluate there so a resumed run is identical
        if t + hs == t1:
            d0t, d0x, d0v = K[12, 0], K[12, 1], K[12, 2]
        else:
            d0t, d0x, d0v = dop853.deriv(p, TIME, phase, 0.0, q, t1, 0.0, t1, x1, v1)
            cnt[C_RHS] += 1
        t, x, v = t1, x1, v1
        s = t
        h = h_next
        if abs(v) < vband and _goes_implicit(p, phase, t, x):
            _enter_slow(p, st, cnt, t, x, v, _sign(v))
            h = 0.0
        elif (phase == CONTACT or abs(v) < vband) and _stiff(p, phase, x, v, hs):
            _enter_slow(p, st, cnt, t, x, v, _sign(v), SLOW_STIFF)
            h = hs  # the implicit solver starts from the step that stability held
        elif phase == FREE and p[P_T] > 0.0 and v * d0v < 0.0 and abs(v) < U_BAND * eps:
            # heading into the friction band of a reversal: continue in s = sgn asinh(v/eps)
            # (without dry friction there is no band, and time stepping is smooth through v = 0)
            sgn = _sign(d0v)
            mode = UVEL
            s = sgn * math.asinh(v / eps)
            st[S_MODE] = mode
            st[S_SGN] = sgn
            st[S_S] = s
            tref = t
            t = 0.0
            d0t, d0x, d0v = dop853.deriv(p, mode, phase, sgn, q, s, tref, t, x, v)
            cnt[C_RHS] += 1
            h = 0.0

    st[S_T] = tref + t
    st[S_TAU] = t
    st[S_TREF] = tref
    st[S_X] = x
    st[S_V] = v
    st[S_PHASE] = phase
    st[S_MODE] = mode
    st[S_S] = s
    st[S_SGN] = sgn
    st[S_H] = h
    st[S_NINV] = n_invalid
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
    st[S_PHASE] = _phase_of(p, x0, v0, vcut)
    # next Poincare index strictly after t0 (t0 itself is the initial condition)
    i = math.floor(t0 / period) + 1
    st[S_ISEC] = float(i)
    if v0 == 0.0 and _goes_implicit(p, int(st[S_PHASE]), t0, x0):
        cnt = np.zeros(N_COUNT, dtype=np.int64)
        _enter_slow(p, st, cnt, t0, x0, v0, 0.0)
    return st
