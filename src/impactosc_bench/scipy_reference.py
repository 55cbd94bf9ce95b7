"""Independent reference solutions with SciPy ``solve_ivp`` (for tests and benchmarks).

The model is integrated piece by piece: every contact onset and exit (and the
Hunt-Crossley cut) is a terminal event, so no step of the reference straddles the
switching surface; penetrations are SciPy's own non-terminal v = 0 events inside
contact. Nothing here shares code with the numba core except the model parameters: each
contact law is written again here, from its published form (:data:`RESTITUTION_CHI`, and the
forces in :func:`model_forces`), on purpose, so that the core's reading of a law as a member
of model BC's family is checked against the law itself.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from impactosc.model.parameters import ModelParams


class ReferenceBudgetExceeded(RuntimeError):
    """The reference spent more right-hand-side evaluations than it was allowed."""


#: chi(e, v0) of each restitution law, F = kI h^n1 max(0, 1 + chi v) (Flores et al. 2011)
RESTITUTION_CHI = {
    "hunt-crossley": lambda e, v0: 3 * (1 - e) / (2 * v0),
    "lankarani-nikravesh": lambda e, v0: 3 * (1 - e**2) / (4 * v0),
    "flores": lambda e, v0: 8 * (1 - e) / (5 * e * v0),
    "gonthier": lambda e, v0: (1 - e**2) / (e * v0),
}


def model_forces(p: ModelParams, omega: float, contact_state: dict | None = None, forcing=None):
    """(external(t, x, v), contact(x, v), bracket(x, v)): the forces of the model and its law in
    plain Python, independent of the numba core, for the SciPy references (`forcing(t)`, N, in place
    of m0e w^2 sin(w t): a noisy run's, :mod:`impactosc_bench.noisy_reference`); the contact force is
    0 where ``bracket`` is negative. A restitution law reads this contact's chi from
    ``contact_state["chi"]`` (set at each onset by the caller); the two-stage law adds its second
    stop's force where ``contact_state["stage"]`` is set (behind h = h1, set by the caller)."""
    state = contact_state if contact_state is not None else {"chi": 0.0, "stage": 0}

    def external(t, x, v):
        fr = p.T * v / math.sqrt(v * v + p.eps * p.eps)
        drive = p.m0e * omega * omega * math.sin(omega * t) if forcing is None else forcing(t)
        return drive - p.k * x - p.c * v - fr

    def bracket(x, v):
        h = max(x - p.xI, 0.0)
        if p.law == "bc":
            return h**p.n1 + p.b * h**p.n2 * math.copysign(abs(v) ** p.n3, v)
        if p.law in ("hertz", "two-stage"):
            return h**p.n1
        if p.law == "kelvin-voigt":
            return p.kI * h + p.cI * v
        if p.law == "hertz-viscous":
            return p.kI * h**p.n1 + p.cI * v
        return h**p.n1 * (1 + state["chi"] * v)

    def contact(x, v):
        if x - p.xI <= 0:
            return 0.0
        br = bracket(x, v)
        f = 0.0 if br <= 0 else (br if p.law in ("kelvin-voigt", "hertz-viscous") else p.kI * br)
        if p.law == "two-stage" and state.get("stage"):  # the second stop: k2 (h - h1)^n1 behind h1
            f += p.k2 * max(x - p.xI - p.h1, 0.0) ** p.n1
        return f

    return external, contact, bracket


def _piece_setups(p: ModelParams, omega: float, method: str, max_nfev, forcing=None) -> dict:
    """Right-hand side and events of each piece kind ("free", "contact", "cut") for
    ``solve_ivp``; the right-hand sides count their calls and raise
    :class:`ReferenceBudgetExceeded` past ``max_nfev`` (None: no limit)."""
    state = {"chi": 0.0, "stage": 0}
    external, contact, bracket = model_forces(p, omega, state, forcing)
    vcut = _cut_velocity(p)

    calls = [0]
    limit = math.inf if max_nfev is None else max_nfev

    def counted(t):
        calls[0] += 1
        if calls[0] > limit:
            raise ReferenceBudgetExceeded(f"SciPy {method}: more than {max_nfev} evaluations, stuck at t = {t:.12g} s")

    def rhs_free(t, y):
        counted(t)
        return [y[1], external(t, y[0], y[1]) / p.m]

    def rhs_contact(t, y):
        counted(t)
        return [y[1], (external(t, y[0], y[1]) - contact(y[0], y[1])) / p.m]

    def ev_onset(t, y):
        return y[0] - p.xI

    ev_onset.terminal, ev_onset.direction = True, 1

    def ev_exit(t, y):
        return y[0] - p.xI

    ev_exit.terminal, ev_exit.direction = True, -1

    def ev_cut(t, y):  # the bracket's sign: model BC's at v = -vcut, a law's where its force turns to 0
        if p.law == "bc":
            return y[1] + vcut if p.n2 == p.n1 else bracket(y[0], y[1])
        if p.law in ("kelvin-voigt", "hertz-viscous"):
            return p.kI * max(y[0] - p.xI, 0.0) ** p.n1 + p.cI * y[1]
        return 1 + state["chi"] * y[1]

    ev_cut.terminal, ev_cut.direction = True, 0

    # a law's cut, other than model BC's v = -vcut, is not snapped onto: each side looks for its
    # own crossing only, so the piece that starts on the surface does not find it again at once
    def ev_cut_on(t, y):
        return ev_cut(t, y)

    def ev_cut_off(t, y):
        return ev_cut(t, y)

    ev_cut_on.terminal, ev_cut_on.direction = True, -1
    ev_cut_off.terminal, ev_cut_off.direction = True, 1
    on, off = (ev_cut, ev_cut) if _cut_is_line(p) else (ev_cut_on, ev_cut_off)

    def ev_vzero(t, y):
        return y[1]

    ev_vzero.terminal, ev_vzero.direction = False, -1

    # the two-stage law: its second stop at h = h1 splits the contact as the onset splits the
    # motion (it has no cut); behind it the "stop" piece, whose own exit is h = h1 downwards
    def ev_stop(t, y):
        return y[0] - p.xI - p.h1

    def ev_stop_off(t, y):
        return ev_stop(t, y)

    def ev_never(t, y):
        return 1.0

    ev_stop.terminal, ev_stop.direction = True, 1
    ev_stop_off.terminal, ev_stop_off.direction = True, -1
    ev_never.terminal = True
    if p.law == "two-stage":
        on = ev_stop

    return {
        "free": (rhs_free, (ev_onset,)),
        "contact": (rhs_contact, (ev_exit, on, ev_vzero)),
        "cut": (rhs_free, (ev_exit, off)),
        "stop": (rhs_contact, (ev_stop_off, ev_never, ev_vzero)),
        "state": state,
    }


def _cut_velocity(p: ModelParams) -> float:
    """b^(-1/n3), model BC's cut velocity where its cut is that line (n2 = n1), written here anew."""
    if p.law != "bc" or p.n2 != p.n1 or p.b <= 0 or p.n3 <= 0:
        return math.inf
    try:
        return p.b ** (-1.0 / p.n3)
    except OverflowError:  # b < 1 and a tiny n3: the bracket never turns negative
        return math.inf


def _cut_is_line(p: ModelParams) -> bool:
    """Model BC's cut with n2 = n1 is the line v = -vcut, snapped onto; another cut is a curve."""
    return p.law == "bc" and p.n2 == p.n1


def solve_reference(
    omega,
    t_end,
    *,
    x0=0.0,
    v0=0.0,
    params=None,
    method="DOP853",
    rtol=1e-13,
    atol=1e-15,
    max_pieces=1_000_000,
    poincare=False,
    max_nfev=None,
    t0=0.0,
    contact_v0=None,
    forcing=None,
):
    """Impact onsets (t, v) and penetrations (t, h) of model BC on [t0, t_end] with SciPy.

    Returns a dict with arrays impacts_t, impacts_v, penetrations_t, penetrations_h and the
    counters nfev, n_pieces, wall_time. With ``poincare`` also poincare_t|x|v: SciPy's dense
    output at t_i = 2 pi i / w (``t_eval``, which does not change SciPy's steps).
    With ``max_nfev`` the run raises :class:`ReferenceBudgetExceeded` after that many
    right-hand-side evaluations (an explicit method pinned by a stiff creep never ends).
    A run that starts inside a restitution law's contact takes its onset velocity as
    ``contact_v0``; ``final`` is the end state (x, v, onset velocity of the contact it lies in,
    nan outside one), with ``poincare`` off. ``forcing(t)`` (N) replaces the unbalance's m0e w^2 sin(w t).
    """
    p = params or ModelParams()
    vcut = _cut_velocity(p)
    setups = _piece_setups(p, omega, method, max_nfev, forcing)
    state = setups["state"]
    cut = setups["contact"][1][1]

    t, y = float(t0), np.array([x0, v0], float)
    onset = math.nan
    if p.law in RESTITUTION_CHI and y[0] > p.xI:  # without contact_v0: a contact at rest, undamped
        onset = 0.0 if contact_v0 is None else float(contact_v0)
        if onset > 0:
            state["chi"] = RESTITUTION_CHI[p.law](p.e, onset)
            vcut = 1 / state["chi"]
    mode = "contact" if y[0] >= p.xI and y[1] > -vcut else ("cut" if y[0] >= p.xI else "free")
    if mode == "contact" and p.law == "two-stage" and y[0] - p.xI > p.h1:
        mode, state["stage"] = "stop", 1
    period = 2 * math.pi / omega
    sections = period * np.arange(1, int(math.floor(t_end / period * (1 + 1e-14))) + 1) if poincare else None
    imp_t, imp_v, pen_t, pen_h, pc_t, pc_x, pc_v = [], [], [], [], [], [], []
    nfev = 0
    pieces = 0
    wall = time.perf_counter()
    while t < t_end:
        if pieces >= max_pieces:
            raise RuntimeError(f"SciPy {method}: more than {max_pieces} pieces before t = {t_end} s")
        pieces += 1
        fun, events = setups[mode]
        t_eval = sections[sections > t] if poincare else None
        sol = solve_ivp(fun, (t, t_end), y, method=method, rtol=rtol, atol=atol, events=events, t_eval=t_eval)
        nfev += sol.nfev
        if sol.status == -1:
            raise RuntimeError(f"SciPy {method} failed at t={t}: {sol.message}")
        if poincare and len(sol.t):  # (with an empty t_eval SciPy returns an empty y)
            pc_t.extend(sol.t)
            pc_x.extend(sol.y[0])
            pc_v.extend(sol.y[1])
        if mode in ("contact", "stop"):
            for te, ye in zip(sol.t_events[2], sol.y_events[2]):
                if te <= t:  # SciPy reports v = 0 at the start of a piece that starts at rest
                    continue
                pen_t.append(te)
                pen_h.append(ye[0] - p.xI)
        if sol.status == 0:
            # the end state; with poincare, sol.y holds the sections only (a list when none)
            y = np.full(2, math.nan) if poincare else sol.y[:, -1]
            break
        n_terminal = 2 if mode != "free" else 1
        k = min((k for k in range(n_terminal) if len(sol.t_events[k])), key=lambda k: sol.t_events[k][-1])
        t = float(sol.t_events[k][-1])
        y = np.array(sol.y_events[k][-1], float)
        if mode == "free":  # onset
            y[0] = p.xI
            imp_t.append(t)
            imp_v.append(y[1])
            if p.law in RESTITUTION_CHI:  # this contact's damping, from its onset velocity
                state["chi"] = RESTITUTION_CHI[p.law](p.e, y[1]) if y[1] > 0 else 0.0
                onset = y[1]
            mode = "contact" if (y[1] > -vcut if _cut_is_line(p) else cut(t, y) > 0 or y[1] >= 0) else "cut"
            state["stage"] = 0
        elif mode == "stop":  # back in front of the second stop
            y[0] = p.xI + p.h1
            state["stage"], mode = 0, "contact"
        elif k == 1 and p.law == "two-stage":  # onto the second stop
            y[0] = p.xI + p.h1
            state["stage"], mode = 1, "stop"
        elif k == 0:  # exit
            y[0] = p.xI
            mode = "free"
        else:  # crossing the cut
            if _cut_is_line(p):
                y[1] = -vcut
            mode = "cut" if mode == "contact" else "contact"
    out = {
        "impacts_t": np.array(imp_t),
        "impacts_v": np.array(imp_v),
        "penetrations_t": np.array(pen_t),
        "penetrations_h": np.array(pen_h),
        "nfev": nfev,
        "n_pieces": pieces,
        "wall_time": time.perf_counter() - wall,
        "final": np.array([y[0], y[1], onset if y[0] > p.xI and p.law in RESTITUTION_CHI else math.nan]),
    }
    if poincare:
        out.update(poincare_t=np.array(pc_t), poincare_x=np.array(pc_x), poincare_v=np.array(pc_v))
    return out
