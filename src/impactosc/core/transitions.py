"""The piece graph: every change of piece is decided here, and nowhere else.

A piece is smooth: one vector field (FREE, CONTACT or CUT), explicit steps in one variable
(t, sqrt(x - xI), |v|^n3 or asinh(v/eps)) or the implicit solver. The piece solvers
(time_pieces.py, transformed_pieces.py, implicit.py) step and locate events; the functions
here apply what they found and set the next piece's kind through :func:`set_piece`. Each
arrow below is an event with the condition that picks the next piece; [..] is the piece's
variable; v0 is the velocity at impact, "the cut" the root of the contact law's bracket
(v = -v_cut, v_cut = b^(-1/n3), for model BC; a curve in (x, v) for a law whose n2 differs from
n1), and |net force| the force other than dry friction at v = 0 (tests/test_core_transitions.py
checks every number against the constants below). The law's surfaces are residuals of (x, v)
(contact_laws.kernel.surface_residual), located on the dense output; no law is named here::

    free flight [t] --x = xI, not past the cut, v0 > 1e3 eps--> contact onset [sqrt(x - xI)]
        (a slower impact: the turn [|v|^n3], or contact [t]; b = 0, n3 >= 1 or a law with a
        surface inside the contact: contact [t])
    contact onset --v < 0.95 v0--> the contact's middle [t] --v < 0.3 v0, a < 0--> turn [|v|^n3]
        (a >= 0: contact [t])
    turn --v = 0 (deepest penetration), net force < 0--> restitution [|v|^n3]
        (next to v = 0 both run as a series in w where it holds: turn_series.py, transformed_pieces.py)
    restitution --|v| = 0.3 v0, x > xI--> the contact's middle [t] --x - xI < 0.3 of the deepest
        penetration--> exit [sqrt(x - xI)] --x = xI--> free flight [closed form]
        (T = 0, an overdamped oscillator, noise in the dynamics, or an exit slower than the closed
        form's edge: free flight [t])
    free flight [closed form] --x = xI--> as free flight [t] at x = xI
    free flight [closed form] --|v| = 30 eps (the closed form's edge), heading for v = 0--> friction band
        [asinh(v/eps)] (crossed in one go where band_crossing.cross applies: v = 0, then free flight
        [closed form] from the far edge)
    contact [t] --x = xI, v < 0--> free flight [t]
    contact [t] --the cut--> past the cut [t] --the cut--> contact [t]
    contact [t] --h = h1 (a second stop)--> contact behind it [t] --h = h1--> contact [t]
    free flight [t] --|v| < 1e3 eps, heading for v = 0, T > 0--> friction band [asinh(v/eps)]
    friction band --v = 0--> friction band (other side) --the closed form's edge (|v| = 1e3 eps
        without one)--> free flight [closed form] (or [t])
    free flight, contact, turn, band --v = 0, |net force| < 1.5 T--> stick / slow reversal [implicit]
    free flight [t], band --|v| < 100 eps, |net force| < 1.5 T--> stick / slow reversal [implicit]
    stick / slow reversal --|v| > 100 eps--> free flight or contact [t]
    contact [t], |v| < 100 eps [t] --h |da/dv| > 4--> stiff creep [implicit]
    turn, contact [t] --v = 0, creep expected with h |da/dv| > 4--> stiff creep [implicit]
    stiff creep --h |da/dv| < 1--> free flight or contact [t]
    any transformed piece --invalid steps--> the same vector field [t]
    any piece --t = 2 pi i / w--> Poincare point (no hand-over)

While the implicit solver runs, an obstacle crossing changes the vector field only; the
explicit pieces resume once it ends.
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.core.events import (
    EV_CUT_OFF,
    EV_CUT_ON,
    EV_STOP_OFF,
    EV_STOP_ON,
    EV_V,
    EV_X_DOWN,
    EV_X_UP,
    push,
    record_extremum,
    sign,
)
from impactosc.core.layout import (
    C_SLOW_TRANSIT,
    C_STICK,
    C_STIFF,
    CLOSED,
    EXPLICIT,
    IMPACT,
    R_FLAGS,
    R_T_RECORD,
    RECORD_IMPACTS,
    S_EXIT_DEPTH,
    S_FIELD,
    S_H,
    S_MIDDLE,
    S_MODE,
    S_PDIR,
    S_PT,
    S_PX,
    S_S,
    S_SGN,
    S_SLOW,
    S_T,
    S_TREF,
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
from impactosc.core.pieces import start_piece, store
from impactosc.model.contact_laws.kernel import behind_stop, contact_onset, has_stop, onto_cut, past_cut
from impactosc.model.equations import CONTACT, CUT, FREE, STOP, accel, damping_rate, in_contact, stick_force
from impactosc.model.noise_kernel import harmonic_forcing
from impactosc.model.parameters import P_B, P_C, P_EPS, P_H1, P_K, P_KI, P_M, P_N2, P_N3, P_T, P_XI

SLOW_FACTOR = 1.5  # v = 0 with |net force| < 1.5 T: stick or slow reversal -> implicit phase
STIFF_ENTER = 4.0  # h |da/dv| above this: explicit steps are held by stability, not accuracy ...
STIFF_EXIT = 1.0  # ... and the implicit phase that takes over ends once h |da/dv| is below this
# (DOP853 is stable to h |da/dv| ~ 6 on the negative real axis; the gap is a hysteresis.)
SQRTH_ONSET = 1e3  # an impact faster than 1e3 eps starts the contact in sqrt(x - xI)
ONSET_SWITCH = 0.95  # in contact, sqrt(x - xI) while v > 0.95 v_onset, then time ...
TURN_SWITCH = 0.3  # ... while v > 0.3 v_onset, then |v|^n3 to v = 0 and on ...
RESTITUTION_SWITCH = 0.3  # ... until |v| = 0.3 v_onset on the way out, then time ...
EXIT_SWITCH = 0.3  # ... until x - xI < 0.3 of the deepest penetration, then sqrt(x - xI) to the exit
# Why four: each variable is smooth at one singular point of the contact and has the others near
# (sqrt(x - xI): the turn's; |v|^n3, which squeezes |v| from 0.3 v0 to v0 into the last fifth of
# its range: onset and exit), while time, between them, has both far. Chosen by the step attempts
# of the chaotic scene (rtol 1e-10): sqrt / |v|^n3 / sqrt at 0.7 / 0.45 took 72.7 per forcing
# period, with the middle in time 67.1 at 0.95 / 0.3 / 0.3 / 0.3 (0.2 or 0.4 for any of the last
# three: 67.2-68.8); the impact times' error against SciPy did not grow.
BAND = 100.0  # the implicit phase ends when |v| > BAND * eps (friction slope then < 1e-6 T/eps)
U_BAND = 1e3  # free flight with |v| < U_BAND * eps, heading for v = 0, runs in s = asinh(v/eps) ...
U_CLOSED = 30.0  # ... and below U_CLOSED * eps where free flight has a closed form (its first-order
# correction for the regularised friction holds to there: the residual is 6e-4 T at the edge)


@njit(cache=True, inline="always")
def set_piece(st, field, slow, mode):
    """The kind of the next piece: its vector field (FREE / CONTACT / CUT), why the implicit
    solver runs (EXPLICIT: it does not) and the variable of its explicit steps. It is no contact's
    middle unless the caller says so after this (a change of piece ends the middle)."""
    st[S_MIDDLE] = 0.0
    st[S_FIELD] = field
    st[S_SLOW] = slow
    st[S_MODE] = mode


@njit(cache=True, inline="always")
def _set_variable(st, field, mode, sgn, s):
    """An explicit piece in the variable `mode` with orientation sgn, starting at s."""
    set_piece(st, field, EXPLICIT, mode)
    st[S_SGN] = sgn
    st[S_S] = s


@njit(cache=True, inline="always")
def closed_form_holds(p):
    """Has free flight outside the friction band a closed form here (impactosc.core.closed_flight)?
    Constant dry friction (T > 0: without it there is no band, and time steps run smoothly
    through v = 0), an underdamped oscillator (c^2 < 4 k m), as model BC, and the harmonic
    forcing (no noise in the dynamics)."""
    return harmonic_forcing(p) and p[P_T] > 0.0 and p[P_C] * p[P_C] < 4.0 * p[P_K] * p[P_M]


@njit(cache=True, inline="always")
def band_edge(p):
    """|v| / eps at the friction band's edge: U_CLOSED where free flight outside has a closed
    form, else U_BAND (time steps take the friction's curvature no closer)."""
    return U_CLOSED if closed_form_holds(p) else U_BAND


@njit(cache=True)
def set_free_flight(p, st, slow, v):
    """The free-flight piece from velocity v: in closed form where it holds and |v| is outside the
    friction band (its sign fixed, the friction is -T sign(v) there), else in time."""
    if slow == EXPLICIT and closed_form_holds(p) and abs(v) >= U_CLOSED * p[P_EPS] * (1.0 - 1e-9):
        set_piece(st, FREE, EXPLICIT, CLOSED)
        st[S_SGN] = sign(v)
    else:
        set_piece(st, FREE, slow, TIME)


@njit(cache=True)
def enter_band(p, st, cnt, d0, t, x, v):
    """Free flight heading for v = 0 reached the friction band: on in s = sgn asinh(v/eps)."""
    sgn = -sign(v)
    _set_variable(st, FREE, UVEL, sgn, sgn * math.asinh(v / p[P_EPS]))
    start_piece(p, st, cnt, d0, t, x, v, 0.0)


@njit(cache=True)
def band_crossed(p, st, cnt, rs, ev, n_ev, d0, direction, t0, x0, t1, x1, v1):
    """Free flight in closed form crossed the friction band in one go (band_crossing.cross): v = 0
    at (t0, x0) (v had the sign `direction` before), as the band piece records it, and closed-form
    flight from the far edge (t1, x1, v1). Returns (ev, n_ev)."""
    ev, n_ev, x0, _ = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, t0, x0, 0.0, direction, 0.0)
    if st[S_SLOW] != EXPLICIT:  # held by dry friction after all: the implicit phase from v = 0
        start_piece(p, st, cnt, d0, t0, x0, 0.0, 0.0)
        return ev, n_ev
    set_free_flight(p, st, EXPLICIT, v1)
    start_piece(p, st, cnt, d0, t1, x1, v1, 0.0)
    return ev, n_ev


@njit(cache=True)
def field_of(p, st, x, v):
    """Vector field at the state (x, v): free flight, contact, or contact past the cut."""
    if x - p[P_XI] >= 0.0:
        if past_cut(p, st[S_VCUT], x, v):
            return CUT
        return STOP if has_stop(p) and behind_stop(p, x) else CONTACT
    return FREE


@njit(cache=True)
def first_piece(p, st, cnt, t, x, v):
    """The piece a run starts on at (t, x, v): the vector field there, explicit in time,
    or the implicit phase when it starts at rest where dry friction holds the cart."""
    field = field_of(p, st, x, v)
    set_piece(st, field, EXPLICIT, TIME)
    if v == 0.0 and goes_implicit(p, field, t, x):
        enter_slow(p, st, cnt, t, x, v, 0.0)


@njit(cache=True)
def goes_implicit(p, field, t, x):
    """At v = 0, a net force below 1.5 T means sticking or a slow reversal: the friction
    band is then crossed (or held) by the implicit solver."""
    return abs(stick_force(p, field, t, x)) < SLOW_FACTOR * p[P_T]


@njit(cache=True)
def stiff(p, field, x, v, h):
    """True when a step of size h is held by stability: h |da/dv| beyond STIFF_ENTER.

    The Hunt-Crossley damping ~ |v|^n3 (n3 << 1) acts inside the contact like a very stiff
    dry friction: where the elastic and external forces nearly balance, the cart creeps at
    a tiny velocity and da/dv ~ |v|^(n3 - 1) grows without bound, so an explicit method is
    pinned to steps ~ 6 / |da/dv| (1e-9 s and shrinking: a stall the randomized scenes found).
    """
    return damping_rate(p, field, x, v) * h > STIFF_ENTER


@njit(cache=True)
def creeps(p, field, t, x, h):
    """At v = 0 in contact: will the motion that follows be a stiff creep?

    With net force f (damping aside), v grows until the Hunt-Crossley damping balances f,
    at the creep velocity v_c = (|f| / (kI b h^n2))^(1/n3), where -da/dv = n3 |f| / (m v_c).
    Stiff (hand it to the implicit solver) when that rate times the step h exceeds STIFF_ENTER.
    """
    if field != CONTACT or p[P_B] <= 0.0 or not (0.0 < p[P_N3] < 1.0):
        return False
    depth = x - p[P_XI]
    if depth <= 0.0:
        return False
    f = abs(stick_force(p, field, t, x))
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
    elif abs(stick_force(p, int(st[S_FIELD]), t, x)) < p[P_T]:
        cnt[C_STICK] += 1
    else:
        cnt[C_SLOW_TRANSIT] += 1
    set_piece(st, st[S_FIELD], float(why), TIME)
    st[S_PDIR] = direction
    st[S_PT] = t
    st[S_PX] = x
    st[S_H] = 0.0


@njit(cache=True)
def _contact_piece(p, st, t, x, v):
    """The contact piece after an impact at (t, x, v), v > 0: sqrt(h) while the velocity is
    well away from zero, |v|^n3 when it already is small; time otherwise."""
    if p[P_B] <= 0.0 or not (0.0 < p[P_N3] < 1.0) or v <= 0.0 or has_stop(p):
        # (a law with a surface inside the contact runs it in time, where that surface is located)
        set_piece(st, CONTACT, EXPLICIT, TIME)
        return
    a = accel(p, CONTACT, t, x, v)
    if x - p[P_XI] <= 0.0 and v > SQRTH_ONSET * p[P_EPS]:
        st[S_V1] = ONSET_SWITCH * v
        _set_variable(st, CONTACT, SQRTH, 1.0, 0.0)
    elif a < 0.0:
        st[S_V1] = TURN_SWITCH * v
        _set_variable(st, CONTACT, WVEL, 1.0, -(v ** p[P_N3]))
    else:
        set_piece(st, CONTACT, EXPLICIT, TIME)


@njit(cache=True)
def _reversal(p, st, cnt, rs, ev, n, t, x, direction, dt_step):
    """v = 0 on an explicit piece (v had the sign `direction` before): the implicit phase
    takes over if dry friction can hold the cart or a stiff creep follows; otherwise this
    is an extremum of x, recorded when it is a maximum."""
    field = int(st[S_FIELD])
    if goes_implicit(p, field, t, x):
        enter_slow(p, st, cnt, t, x, 0.0, direction)
    elif creeps(p, field, t, x, dt_step):
        enter_slow(p, st, cnt, t, x, 0.0, direction, SLOW_STIFF)
    else:
        ev, n = record_extremum(p, rs, ev, n, field, t, x, direction)
    return ev, n


@njit(cache=True)
def apply_event(p, st, cnt, rs, ev, n, kind, t, x, v, direction, dt_step):
    """Apply the event `kind` located at time t with state (x, v), for any piece kind.

    Records it, sets the next piece (the vector field; explicit pieces restart in time, or
    in a contact variable after an impact, or go implicit after a reversal; the implicit
    phase keeps running) and returns (ev, n, x, v) with the state put exactly on the event's
    surface. `direction`: the sign of v before a reversal; `dt_step`: the time step that found it.
    """
    slow = st[S_SLOW]  # the implicit phase runs on in time (its pieces are always in time)
    vcut = st[S_VCUT]
    if kind == EV_X_UP:  # impact
        x = p[P_XI]
        vcut = contact_onset(p, v, vcut)  # the state the law keeps for this contact (its v0)
        st[S_VCUT] = vcut
        if int(rs[R_FLAGS]) & RECORD_IMPACTS and t >= rs[R_T_RECORD]:
            ev, n = push(ev, n, IMPACT, t, v, 0.0)
        st[S_PDIR] = 0.0  # a pending free-flight maximum (implicit phase) became a contact
        cut = past_cut(p, st[S_VCUT], x, v)  # an impact fast enough to start past the cut
        if not cut and slow == EXPLICIT:
            _contact_piece(p, st, t, x, v)
        else:
            set_piece(st, CUT if cut else CONTACT, slow, TIME)
    elif kind == EV_X_DOWN:  # contact exit
        x = p[P_XI]
        set_free_flight(p, st, slow, v)
    elif kind in (EV_CUT_ON, EV_CUT_OFF):
        v = onto_cut(p, vcut, v)  # onto the line v = -v_cut where the cut is one
        set_piece(st, CUT if kind == EV_CUT_ON else CONTACT, slow, TIME)
    elif kind in (EV_STOP_ON, EV_STOP_OFF):  # the surface inside the contact: onto it, and the other side
        x = p[P_XI] + p[P_H1]
        set_piece(st, STOP if kind == EV_STOP_ON else CONTACT, slow, TIME)
    else:  # v = 0
        v = 0.0
        if slow != EXPLICIT:  # inside the implicit phase: a reversal against the pre-stick direction
            if direction == st[S_PDIR]:  # moves the pending extremum here
                st[S_PT] = t
                st[S_PX] = x
        else:
            set_piece(st, st[S_FIELD], EXPLICIT, TIME)
            ev, n = _reversal(p, st, cnt, rs, ev, n, t, x, direction, dt_step)
    return ev, n, x, v


@njit(cache=True, inline="always")  # on every accepted time step: inlined as time_step is
def after_time_step(p, st, cnt, d0, field, t1, x1, v1, hs):
    """An accepted time step without events ended at (t1, x1, v1): the implicit phase takes
    over where dry friction can hold the cart or the step was held by stability, the
    friction band's variable where free flight heads for v = 0, and the contact's middle hands over
    to the turn's or the exit's variable."""
    eps = p[P_EPS]
    if st[S_MIDDLE] != 0.0 and _middle_ends(p, st, cnt, d0, field, t1, x1, v1):
        return
    if abs(v1) < BAND * eps and goes_implicit(p, field, t1, x1):
        enter_slow(p, st, cnt, t1, x1, v1, sign(v1))
    elif (in_contact(field) or abs(v1) < BAND * eps) and stiff(p, field, x1, v1, hs):
        enter_slow(p, st, cnt, t1, x1, v1, sign(v1), SLOW_STIFF)
        st[S_H] = hs  # the implicit solver starts from the step that stability held
    elif field == FREE and p[P_T] > 0.0 and v1 * d0[2] < 0.0 and abs(v1) < U_BAND * eps:
        # heading into the friction band of a reversal: continue in s = sgn asinh(v/eps)
        # (without dry friction there is no band, and time stepping is smooth through v = 0)
        enter_band(p, st, cnt, d0, t1, x1, v1)


@njit(cache=True, inline="always")  # on every accepted transformed step, as after_time_step
def after_transformed_step(p, st, cnt, rs, ev, n_ev, d0, clamped, mode, field, sgn, ta, x1, v1, s1, dt_step):
    """An accepted transformed step without events ended at absolute time ta: the end of its
    variable's range, the friction band handed to the implicit phase, or the contact onset
    slowed down enough for |v|^n3."""
    if clamped:
        ev, n_ev = _transformed_end(p, st, cnt, rs, ev, n_ev, d0, dt_step)
    elif mode == UVEL and s1 < 0.0 and abs(v1) < BAND * p[P_EPS] and goes_implicit(p, field, ta, x1):
        # Creeping towards v = 0 where dry friction can hold the cart: hand the band to
        # the implicit solver, as time stepping does. (Without this the explicit
        # asinh piece crept along the stick manifold with steps ~ m eps / T until v
        # crossed 0: the cost of each stick grew like 1/eps.)
        enter_slow(p, st, cnt, ta, x1, v1, sign(v1))
        start_piece(p, st, cnt, d0, ta, x1, v1, 0.0)
    elif mode == SQRTH and sgn > 0.0 and v1 < st[S_V1]:  # past the onset: the contact's middle in time
        st[S_V1] *= TURN_SWITCH / ONSET_SWITCH
        set_piece(st, field, EXPLICIT, TIME)
        st[S_MIDDLE] = 1.0
        _switch_variable(p, st, cnt, d0, ta, x1, v1)
    return ev, n_ev


@njit(cache=True)
def _middle_ends(p, st, cnt, d0, field, t1, x1, v1):
    """After a time step in a contact's middle: on the way in, slow enough for |v|^n3 on to v = 0
    (while decelerating; else time goes on); on the way out, shallow enough for sqrt(x - xI) on to
    the exit. True if the piece changed."""
    if st[S_MIDDLE] > 0.0 and 0.0 < v1 < st[S_V1]:
        st[S_MIDDLE] = 0.0
        if accel(p, field, t1, x1, v1) < 0.0:
            _set_variable(st, field, WVEL, 1.0, -(v1 ** p[P_N3]))
            _switch_variable(p, st, cnt, d0, t1, x1, v1)
            return True
    elif st[S_MIDDLE] < 0.0 and v1 < 0.0 and x1 - p[P_XI] < st[S_EXIT_DEPTH]:
        st[S_MIDDLE] = 0.0
        _set_variable(st, field, SQRTH, -1.0, -math.sqrt(x1 - p[P_XI]))
        _switch_variable(p, st, cnt, d0, t1, x1, v1)
        return True
    return False


@njit(cache=True, inline="always")  # on every implicit step
def after_implicit_step(p, st, cnt, rs, ev, n_ev, d0, field, t1, x1, v1, h_next):
    """An implicit step without events ended at (t1, x1, v1): the phase ends once |v| leaves
    the friction band (stick, slow reversal) or the next step is no longer held by stability
    (stiff creep); a pending extremum of x is recorded if v came back with the other sign.
    A surface inside the contact (a second stop) is not located by the implicit steps: the side
    of it the step ended on sets the vector field."""
    if in_contact(field) and has_stop(p):
        field = STOP if behind_stop(p, x1) else CONTACT
        set_piece(st, field, st[S_SLOW], st[S_MODE])
    if st[S_SLOW] == SLOW_STIFF:
        leave = damping_rate(p, field, x1, v1) * h_next < STIFF_EXIT
    else:
        leave = abs(v1) > BAND * p[P_EPS]
    if leave:
        if sign(v1) == -st[S_PDIR]:
            ev, n_ev = record_extremum(p, rs, ev, n_ev, field, st[S_PT], st[S_PX], st[S_PDIR])
        set_piece(st, field, EXPLICIT, TIME)
        st[S_PDIR] = 0.0
        start_piece(p, st, cnt, d0, t1, x1, v1, 0.0)
    return ev, n_ev


@njit(cache=True)
def fall_back_to_time(p, st, cnt, rs, ev, n_ev, d0, mode, sgn, s, ta, x, v):
    """A transformed piece broke down at absolute time ta: the same vector field goes on in
    time. A piece heading for v = 0 (the turn in |v|^n3, the band's first half) whose v
    component already crossed zero by round-off has reached its end: apply the reversal
    here, or time stepping from the far side would never see it (a penetration went
    unrecorded this way)."""
    set_piece(st, st[S_FIELD], EXPLICIT, TIME)
    direction = 1.0 if mode == WVEL else -sgn
    if ((mode == WVEL and sgn > 0.0) or (mode == UVEL and s < 0.0)) and v * direction <= 0.0:
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, ta, x, v, direction, 0.0)
    start_piece(p, st, cnt, d0, ta, x, v, 0.0)
    return ev, n_ev


@njit(cache=True)
def stop_in_piece(st, t_end, x, v):
    """The run ends inside a transformed piece at t_end: the state there, in time (a later
    run resumes from it on a time piece)."""
    set_piece(st, st[S_FIELD], st[S_SLOW], TIME)
    st[S_TREF] = 0.0
    store(st, t_end, x, v, t_end, 0.0)


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
    if mode == SQRTH:  # s = 0: exit from the obstacle, into the free flight apply_event chose
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_X_DOWN, ta, x, v, 0.0, dt_step)
        start_piece(p, st, cnt, d0, ta, x, v, 0.0)
        return ev, n_ev
    elif mode == WVEL and sgn > 0.0:  # s = 0: v = 0 at the deepest penetration
        fs = stick_force(p, int(st[S_FIELD]), ta, x)
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, ta, x, v, 1.0, dt_step)
        new_mode = TIME
        if st[S_SLOW] == EXPLICIT and fs < 0.0:  # restitution: v = -w^q with w from 0 up to |V1|^n3
            new_mode = WVEL
            st[S_SGN] = -1.0
            st[S_S] = 0.0
            st[S_V1] *= RESTITUTION_SWITCH / TURN_SWITCH
            st[S_EXIT_DEPTH] = EXIT_SWITCH * (x - p[P_XI])
    elif mode == WVEL:  # |v| = V1 on the way out: the contact's middle in time, or sqrt(h) to the exit
        if x - p[P_XI] > st[S_EXIT_DEPTH]:
            set_piece(st, st[S_FIELD], EXPLICIT, TIME)
            st[S_MIDDLE] = -1.0
            _switch_variable(p, st, cnt, d0, ta, x, v)
            return ev, n_ev
        if x > p[P_XI]:
            _set_variable(st, st[S_FIELD], SQRTH, -1.0, -math.sqrt(x - p[P_XI]))
            _switch_variable(p, st, cnt, d0, ta, x, v)
            return ev, n_ev
        new_mode = TIME
    elif st[S_S] == 0.0:  # UVEL at v = 0: an extremum of x in free flight
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_V, ta, x, v, -sgn, dt_step)
        if st[S_SLOW] == EXPLICIT:
            # asinh(v/eps) is as smooth through v = 0 as before it: keep the step
            h = st[S_H]
            new_mode = UVEL
        else:
            new_mode = TIME
    else:  # UVEL out of the friction band: free flight
        set_free_flight(p, st, st[S_SLOW], v)
        start_piece(p, st, cnt, d0, ta, x, v, h)
        return ev, n_ev
    set_piece(st, st[S_FIELD], st[S_SLOW], new_mode)
    start_piece(p, st, cnt, d0, ta, x, v, h)
    return ev, n_ev
