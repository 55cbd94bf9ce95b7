"""Where the core goes next: the decisions that change the piece (vector field, implicit or
explicit, the variable), for every piece kind.

The piece solvers (time_pieces.py, transformed_pieces.py, implicit.py) locate events;
:func:`apply_event` applies them and makes the decisions taken at v = 0: stick or slow
reversal (implicit phase), stiff creep (implicit phase), or an extremum of x (a penetration
in contact, a near miss in free flight). :func:`_transformed_end` picks the piece after a
transformed piece reaches the end of its variable's range.
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.core.events import EV_CUT_OFF, EV_CUT_ON, EV_V, EV_X_DOWN, EV_X_UP, push, record_extremum
from impactosc.core.layout import (
    C_SLOW_TRANSIT,
    C_STICK,
    C_STIFF,
    IMPACT,
    R_FLAGS,
    R_T_RECORD,
    RECORD_IMPACTS,
    S_H,
    S_MODE,
    S_PDIR,
    S_PHASE,
    S_PT,
    S_PX,
    S_S,
    S_SGN,
    S_SLOW,
    S_T,
    S_V,
    S_V1,
    S_VCUT,
    S_X,
    SLOW_FRICTION,
    SLOW_STIFF,
    SQRTH,
    TIME,
    UVEL,
    WVEL,
)
from impactosc.core.pieces import start_piece
from impactosc.model.equations import CONTACT, CUT, FREE, accel, damping_rate, stick_force
from impactosc.model.parameters import P_B, P_EPS, P_KI, P_M, P_N2, P_N3, P_T, P_XI

SLOW_FACTOR = 1.5  # v = 0 with |net force| < 1.5 T: stick or slow reversal -> implicit phase
STIFF_ENTER = 4.0  # h |da/dv| above this: explicit steps are held by stability, not accuracy ...
STIFF_EXIT = 1.0  # ... and the implicit phase that takes over ends once h |da/dv| is below this
# (DOP853 is stable to h |da/dv| ~ 6 on the negative real axis; the gap is a hysteresis.)
CONTACT_SWITCH = 0.7  # in contact, sqrt(x - xI) while v > 0.7 v_onset, then |v|^n3 ...
RESTITUTION_SWITCH = 0.45  # ... until |v| = 0.45 v_onset on the way out, then sqrt(x - xI)
# (chosen by the work they cost on the chaotic scene: 0.95 / 0.2 took 116 step attempts per
# forcing period, 0.7 / 0.45 take 105; the error of the impact times did not grow)

BAND = 100.0  # the implicit phase ends when |v| > BAND * eps (friction slope then < 1e-6 T/eps)
U_BAND = 1e3  # free flight with |v| < U_BAND * eps, heading for v = 0, runs in s = asinh(v/eps)


@njit(cache=True)
def phase_of(p, x, v, vcut):
    """Vector field at the state (x, v): free flight, contact, or contact past the cut."""
    if x - p[P_XI] >= 0.0:
        return CONTACT if v > -vcut else CUT
    return FREE


@njit(cache=True)
def goes_implicit(p, phase, t, x):
    """At v = 0, a net force below 1.5 T means sticking or a slow reversal: the friction
    band is then crossed (or held) by the implicit solver."""
    return abs(stick_force(p, phase, t, x)) < SLOW_FACTOR * p[P_T]


@njit(cache=True)
def stiff(p, phase, x, v, h):
    """True when a step of size h is held by stability: h |da/dv| beyond STIFF_ENTER.

    The Hunt-Crossley damping ~ |v|^n3 (n3 << 1) acts inside the contact like a very stiff
    dry friction: where the elastic and external forces nearly balance, the cart creeps at
    a tiny velocity and da/dv ~ |v|^(n3 - 1) grows without bound, so an explicit method is
    pinned to steps ~ 6 / |da/dv| (1e-9 s and shrinking: a stall the randomized scenes found).
    """
    return damping_rate(p, phase, x, v) * h > STIFF_ENTER


@njit(cache=True)
def creeps(p, phase, t, x, h):
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
def enter_slow(p, st, cnt, t, x, v, direction, why=SLOW_FRICTION):
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
def contact_mode(p, st, t, x, v):
    """Variable of a contact piece starting at (t, x, v) with v > 0 (onset): sqrt(h) while the
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
def _reversal(p, st, cnt, rs, ev, n, t, x, direction, dt_step):
    """v = 0 on an explicit piece (v had the sign `direction` before): the implicit phase
    takes over if dry friction can hold the cart or a stiff creep follows; otherwise this
    is an extremum of x, recorded when it is a maximum."""
    phase = int(st[S_PHASE])
    if goes_implicit(p, phase, t, x):
        enter_slow(p, st, cnt, t, x, 0.0, direction)
    elif creeps(p, phase, t, x, dt_step):
        enter_slow(p, st, cnt, t, x, 0.0, direction, SLOW_STIFF)
    else:
        ev, n = record_extremum(p, rs, ev, n, phase, t, x, direction)
    return ev, n


@njit(cache=True)
def apply_event(p, st, cnt, rs, ev, n, kind, t, x, v, direction, dt_step):
    """Apply the event `kind` located at time t with state (x, v), for any piece kind.

    Records it, sets the vector field (st[S_PHASE]) and the next piece (explicit pieces:
    st[S_MODE], a contact variable after an impact, or the implicit phase after a reversal)
    and returns (ev, n, x, v) with the state put exactly on the event's surface.
    `direction`: the sign of v before a reversal; `dt_step`: the time step that found it.
    """
    slow = st[S_SLOW] != 0.0
    if not slow:
        st[S_MODE] = TIME
    phase = int(st[S_PHASE])
    vcut = st[S_VCUT]
    if kind == EV_X_UP:  # impact
        x = p[P_XI]
        if int(rs[R_FLAGS]) & RECORD_IMPACTS and t >= rs[R_T_RECORD]:
            ev, n = push(ev, n, IMPACT, t, v, 0.0)
        phase = CONTACT if v > -vcut else CUT
        st[S_PDIR] = 0.0  # a pending free-flight maximum (implicit phase) became a contact
        st[S_PHASE] = phase
        if phase == CONTACT and not slow:
            contact_mode(p, st, t, x, v)
    elif kind == EV_X_DOWN:  # contact exit
        x = p[P_XI]
        st[S_PHASE] = FREE
    elif kind in (EV_CUT_ON, EV_CUT_OFF):
        v = -vcut
        st[S_PHASE] = CUT if kind == EV_CUT_ON else CONTACT
    else:  # v = 0
        v = 0.0
        if slow:  # inside the implicit phase: a reversal against the pre-stick direction
            if direction == st[S_PDIR]:  # moves the pending extremum here
                st[S_PT] = t
                st[S_PX] = x
        else:
            ev, n = _reversal(p, st, cnt, rs, ev, n, t, x, direction, dt_step)
    return ev, n, x, v


@njit(cache=True)
def _switch_variable(p, st, cnt, d0, ta, x, v):
    """Continue the motion in the variable st[S_MODE] (set by the caller): the next step
    covers the time the old variable's next step would have (h_s dt/ds carried over),
    instead of a fresh start from a small step."""
    h_time = st[S_H] * d0[0]
    start_piece(p, st, cnt, d0, ta, x, v, 0.0)
    if h_time > 0.0 and d0[0] > 0.0 and h_time / d0[0] < math.inf:
        st[S_H] = h_time / d0[0]


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
