"""The monodromy matrix of model BC from the variational equations (SciPy, independent of the core).

Why: :func:`shooting.monodromy` differentiates the numba core by finite differences. This module
computes the same M = dP^N/dy another way, as an independent check of it: the state and the
tangent matrix Phi = dy(t)/dy(0) are integrated together with SciPy's DOP853 at a tight
tolerance, Phi' = J(t, x, v) Phi, Phi(0) = I, with J the analytic Jacobian of the vector field
written here (nothing is shared with the core but :class:`ModelParams`). Model BC's law only: the
other laws refuse (a restitution law would need the jump term of chi(v0) at each onset).

The vector field is continuous everywhere (the contact force vanishes at the obstacle, h = x - xI
= 0, and at the Hunt-Crossley cut where its bracket reaches 0; the dry friction is regularised),
so Phi needs no saltation matrix at any switch: it is carried unchanged from one smooth piece to
the next. The traps and how each is handled:

1. Inside contact dF_I/dv = kI b h^n2 n3 |v|^(n3 - 1) is infinite at v = 0 (the deepest
   penetration; n3 = 0.187). Within a window |v| < `v_window` (1 cm/s; half the impact velocity
   after a slower impact) the contact piece is integrated in its own variable u = sgn(v) |v|^n3
   instead of t, with t, x and Phi as functions of u: du/dt = n3 |v|^(n3 - 1) a, so
   dt/du = |v|^(1 - n3) / (n3 a) and the singular entry of J dt/du becomes -kI b h^n2 / (m a):
   the factor |v|^(n3 - 1) cancels exactly, and every entry of the right-hand side in u is
   bounded by |a|^-1 times the model's constants (the friction slope too:
   T eps^2 |v|^(1 - n3) / (v^2 + eps^2)^1.5 <= T eps^-n3). The window is split at u = 0, so each
   half is smooth inside; at u = 0 the terms |u|^((1 - n3)/n3) are C^4, a weak
   endpoint singularity the step control refines geometrically. This needs a != 0 in the window
   (true unless the cart sticks in contact: a is ~ -100 m/s^2 there on the orbits checked); a
   sign change of a there, or a step-size failure in u (dt/du blowing up), raises
   :class:`UnsupportedTrajectory`. The window's border is a choice, not an approximation: borders
   from 0.1 mm/s to 1 m/s give the same M to 2e-10 (the solver's tolerance; tests/test_variational.py).
2. The regularised friction has slope T eps^2 / (v^2 + eps^2)^1.5, T/eps ~ 6e5 N s/m at v = 0:
   free flight is split at every v = 0 (a terminal event), and DOP853 resolves each crossing of
   the band |v| ~ eps. Explicit is right here: a step that resolves the band (length
   ~ eps m / (|F| - T), with F the net force without friction) meets the largest slope T/(m eps)
   with h lambda ~ T / (|F| - T), and at |v| >> eps the resolving step ~ |v|/|a| has h lambda
   ~ (T / m|a|) (eps/v)^2: inside DOP853's stability interval (|h lambda| < ~6) whenever
   |F| > 2 T at the reversal, which is checked (a cart that nearly sticks raises
   :class:`UnsupportedTrajectory`; such creeping orbits need an implicit method).
3. Contact onset and exit (h = 0), the cut (bracket = 0), v = 0 in free flight and the borders of
   the window of 1. are terminal `solve_ivp` events, so no step straddles a kink of J; each piece
   integrates the smooth formula of its own side (h clipped at 0, the bracket not clipped). At
   onset and exit J itself is continuous (its h^(n1 - 1) = h^0.5 term vanishes), only its
   derivative is singular, again a weak endpoint singularity the step control refines.

Tolerances: `rtol` on every component; the absolute tolerance is `rtol` times each component's
scale unless `atol` is given: 1 mm and 0.1 m/s for x and v (shooting.SCALE), their ratios for the
entries of Phi, 1 ms for t in the u pieces.
"""

from __future__ import annotations

import math
import numbers

import numpy as np
from scipy.integrate import solve_ivp

from impactosc.dynamics.shooting import SCALE
from impactosc.model.contact_laws import law_of
from impactosc.model.parameters import ModelParams

__all__ = ["UnsupportedTrajectory", "variational_monodromy"]

V_WINDOW = 1e-2  # m/s: contact with |v| below this is integrated in u = sgn(v) |v|^n3
STICK_MARGIN = 2.0  # a free-flight reversal needs |F| > STICK_MARGIN T (trap 2 in the docstring)
MAX_PIECES = 100_000
_FREE, _CONTACT, _CUT = "free flight", "contact", "contact past the cut"
_WINDOW = "contact, |v| < v_window"  # contact integrated in u (trap 1)


class UnsupportedTrajectory(ValueError):
    """The trajectory does something the variational integration does not handle (sticking)."""


def _sign(z):
    return 1.0 if z > 0 else -1.0


class _Model:
    """The right-hand sides in t and in u, with the analytic Jacobian, for one (params, omega)."""

    def __init__(self, p: ModelParams, omega: float):
        self.p, self.w = p, omega
        self.f0 = p.m0e * omega * omega
        self.inv_n3 = 1.0 / p.n3 if p.n3 > 0 else math.inf
        # the window of trap 1 is needed only where dF_I/dv is singular
        self.windowed = p.b > 0 and 0 < p.n3 < 1

    # --- the vector field (x', v') = (v, a) and J = [[0, 1], [a_x, a_v]] ---------------
    def friction(self, v):
        s = v * v + self.p.eps * self.p.eps
        sq = math.sqrt(s)
        return self.p.T * v / sq, self.p.T * self.p.eps * self.p.eps / (s * sq)

    def outer(self, t, x, v):
        """Net force without friction and contact (forcing - spring - viscous)."""
        p = self.p
        return self.f0 * math.sin(self.w * t) - p.k * x - p.c * v

    def cut_function(self, h, signed_vn):
        """bracket / h^n2 (so it does not vanish at h = 0 as the bracket does): < 0 past the cut."""
        p = self.p
        lead = 1.0 if p.n1 == p.n2 else max(h, 1e-300) ** (p.n1 - p.n2)
        return lead + p.b * signed_vn

    def time_rhs(self, contact):
        p, inv_m = self.p, 1.0 / self.p.m

        def rhs(t, y):
            x, v, p00, p01, p10, p11 = y
            fr, dfr = self.friction(v)
            f = self.outer(t, x, v) - fr
            fx, fv = -p.k, -p.c - dfr
            if contact:
                h = max(x - p.xI, 0.0)
                hn2 = h**p.n2
                if p.b > 0:
                    av = abs(v)
                    vn = math.copysign(av**p.n3, v)
                    f -= p.kI * (h**p.n1 + p.b * hn2 * vn)
                    fx -= p.kI * (p.n1 * h ** (p.n1 - 1) + p.b * p.n2 * h ** (p.n2 - 1) * vn)
                    # finite: the window (trap 1) keeps |v| >= its border on time pieces
                    fv -= p.kI * p.b * hn2 * p.n3 * max(av, 1e-300) ** (p.n3 - 1)
                else:
                    f -= p.kI * h**p.n1
                    fx -= p.kI * p.n1 * h ** (p.n1 - 1)
            ax, av_ = fx * inv_m, fv * inv_m
            return [v, f * inv_m, p10, p11, ax * p00 + av_ * p10, ax * p01 + av_ * p11]

        return rhs

    def u_state(self, u, t, x):
        """v, a, and the pieces of the right-hand side in u at (u, t, x)."""
        p = self.p
        au = abs(u)
        v = math.copysign(au**self.inv_n3, u)
        h = max(x - p.xI, 0.0)
        hn2 = h**p.n2
        fr, dfr = self.friction(v)
        a = (self.outer(t, x, v) - fr - p.kI * (h**p.n1 + p.b * hn2 * u)) / p.m
        return v, h, hn2, dfr, a

    def u_rhs(self):
        """d/du of (t, x, Phi) with u = sgn(v)|v|^n3: bounded while a != 0 (trap 1)."""
        p, inv_m = self.p, 1.0 / self.p.m
        expo = (1.0 - p.n3) / p.n3  # |v|^(1 - n3) = |u|^expo

        def rhs(u, z):
            t, x, p00, p01, p10, p11 = z
            v, h, hn2, dfr, a = self.u_state(u, t, x)
            tu = abs(u) ** expo / (p.n3 * a)  # dt/du
            ax_tu = (-p.k - p.kI * (p.n1 * h ** (p.n1 - 1) + p.b * p.n2 * h ** (p.n2 - 1) * u)) * inv_m * tu
            # a_v dt/du: the contact term -kI b h^n2 n3 |v|^(n3-1) / m times |v|^(1-n3) / (n3 a)
            av_tu = -(p.c + dfr) * inv_m * tu - p.kI * p.b * hn2 * inv_m / a
            return [tu, v * tu, tu * p10, tu * p11, ax_tu * p00 + av_tu * p10, ax_tu * p01 + av_tu * p11]

        return rhs


def _event(fun, direction):
    """A terminal solve_ivp event (a new function each time: one g may serve both directions)."""

    def event(s, y):
        return fun(s, y)

    event.terminal, event.direction = True, direction
    return event


def _check_input(y, omega, n_periods, params, rtol, atol, v_window):
    y = np.asarray(y, dtype=float)
    if y.shape != (2,) or not np.all(np.isfinite(y)):
        raise ValueError(f"y must be a finite state (x, v), got {y!r}")
    if not isinstance(omega, numbers.Real) or not math.isfinite(omega) or omega <= 0:
        raise ValueError(f"omega must be a finite number > 0 rad/s, got {omega!r}")
    if isinstance(n_periods, bool) or not isinstance(n_periods, numbers.Integral) or n_periods < 1:
        raise ValueError(f"n_periods must be an integer >= 1, got {n_periods!r}")
    if params is not None and not isinstance(params, ModelParams):
        raise ValueError(f"params must be a ModelParams, got {type(params).__name__}")
    p = params or ModelParams()
    if not law_of(p.law).reads_damping:  # a law that places its own b, n2, n3 (a chi(v0) per contact, ...)
        raise ValueError(f"the variational equations are written for model BC's law only, not the {p.law} law")
    # SciPy raises the smallest rtol to 100 machine epsilons itself (with a warning): refuse instead
    if not isinstance(rtol, numbers.Real) or not 100 * np.finfo(float).eps <= rtol < 1:
        raise ValueError(f"rtol must be in [2.3e-14, 1), got {rtol!r}")
    if atol is not None and (not isinstance(atol, numbers.Real) or not math.isfinite(atol) or atol <= 0):
        raise ValueError(f"atol must be a finite number > 0 (or None for the scaled default), got {atol!r}")
    if not isinstance(v_window, numbers.Real) or not math.isfinite(v_window) or v_window <= 0:
        raise ValueError(f"v_window must be a finite number > 0 m/s, got {v_window!r}")
    if p.n1 < 1 or p.n2 < 1:
        raise ValueError(f"n1 and n2 must be >= 1 (else J is unbounded at contact onset), got {p.n1}, {p.n2}")
    if p.b > 0 and p.n3 == 0:
        raise ValueError("n3 = 0 with b > 0 makes the contact force jump at v = 0: no variational equations")
    return y, p


def variational_monodromy(
    y,
    omega: float,
    n_periods: int = 1,
    params: ModelParams | None = None,
    *,
    rtol: float = 1e-12,
    atol: float | None = None,
    v_window: float = V_WINDOW,
):
    """(P^N(y), M): the state after `n_periods` forcing periods from y = (x, v) at phase 0, and
    M = dP^N/dy from the variational equations (see the module docstring), like
    :func:`shooting.monodromy`.

    `rtol` applies to every integrated component; `atol` (a number, the same for all) defaults
    to `rtol` times each component's scale. `v_window` is the |v| below which contact is
    integrated in u = sgn(v)|v|^n3. Raises ValueError for bad input and
    :class:`UnsupportedTrajectory` (a ValueError) for a trajectory that (nearly) sticks."""
    image, M, _ = _integrate(y, omega, n_periods, params, rtol=rtol, atol=atol, v_window=v_window)
    return image, M


def _integrate(y, omega, n_periods=1, params=None, *, rtol=1e-12, atol=None, v_window=V_WINDOW, **solver):
    """variational_monodromy plus a log of the pieces: (mode, variable, start, end, nfev).

    `solver` overrides solve_ivp's options (method, max_step) for the checks of the tests."""
    y, p = _check_input(y, omega, n_periods, params, rtol, atol, v_window)
    omega = float(omega)
    mdl = _Model(p, omega)
    t_end = n_periods * 2 * math.pi / omega
    scale_phi = (SCALE[:, None] / SCALE[None, :]).ravel()
    if atol is None:
        atol_t = rtol * np.concatenate([SCALE, scale_phi])
        atol_u = rtol * np.concatenate([[1e-3], SCALE[:1], scale_phi])
    else:
        atol_t = atol_u = float(atol)
    opts = dict(method="DOP853", rtol=rtol) | solver

    def window_of(v):
        """Border of the window (trap 1) for a contact entered at velocity v: v_window, or |v|/2
        after a slow impact (so that the piece starts in t and enters u only while |v| falls)."""
        return min(v_window, abs(v) / 2) if v != 0 else v_window

    x, v = float(y[0]), float(y[1])
    phi = np.eye(2)
    t = 0.0
    v_w = window_of(v)
    h0 = x - p.xI
    if h0 > 0 or (h0 == 0 and v > 0):
        vn = math.copysign(abs(v) ** p.n3, v) if p.n3 > 0 else 0.0
        mode = _CONTACT if mdl.cut_function(h0, vn) > 0 else _CUT
        if mode == _CONTACT and mdl.windowed and abs(v) < v_window:
            a = mdl.time_rhs(True)(t, [x, v, 1, 0, 0, 1])[1]
            if v == 0 or _sign(a) != _sign(v):  # inside the window, |v| falling: start in u
                v_w, mode = v_window, _WINDOW
    else:
        mode = _FREE
    log = []

    # event functions (time pieces: y = (x, v, Phi); u pieces: z = (t, x, Phi))
    def h_of(t, y):
        return y[0] - p.xI

    onset, exit_ = _event(h_of, 1), _event(h_of, -1)

    def cut_t(t, y):
        return mdl.cut_function(max(y[0] - p.xI, 0.0), math.copysign(abs(y[1]) ** p.n3, y[1]))

    cut_leave, cut_enter = _event(cut_t, -1), _event(cut_t, 1)

    def run_time(contact, y0, events):
        sol = solve_ivp(mdl.time_rhs(contact), (t, t_end), y0, events=events, atol=atol_t, **opts)
        if sol.status == -1:
            raise RuntimeError(f"{opts['method']} failed at t = {t:.12g} s in {mode}: {sol.message}")
        log.append((mode, "t", t, float(sol.t[-1]), sol.nfev))
        if sol.status == 0:
            return None, sol.y[:, -1]
        k = min((k for k in range(len(events)) if len(sol.t_events[k])), key=lambda k: sol.t_events[k][0])
        return (k, float(sol.t_events[k][0])), np.array(sol.y_events[k][0], float)

    for _ in range(MAX_PIECES):
        if t >= t_end:
            break
        y0 = np.concatenate([[x, v], phi.ravel()])
        if mode == _FREE:
            if v == 0:  # at a reversal (or a start at rest): which way v leaves 0
                _check_reversal(mdl, t, x)
                force = mdl.outer(t, x, 0.0)
                moving = force if force != 0 else math.cos(omega * t)  # at F = 0 the forcing's slope decides
            else:
                moving = v
            vzero = _event(lambda t, y: y[1], -_sign(moving))
            hit, yy = run_time(False, y0, [onset, vzero])
        elif mode == _CUT:
            hit, yy = run_time(False, y0, [exit_, cut_enter])
        elif mode == _WINDOW:
            hit, t, x, v, phi = _u_pieces(mdl, t, x, v, phi, t_end, v_w**p.n3, atol_u, opts, log)
            mode = _CONTACT
            if hit is None:  # on the window's far border (exactly, so the next piece is in t)
                v = math.copysign(v_w, v)
            elif hit == "exit":
                x, mode = p.xI, _FREE
            elif hit == "cut":
                mode = _CUT
            continue
        else:
            if mdl.windowed:
                window = _event(lambda t, y, v_w=v_w: abs(y[1]) - v_w, -1)
            else:  # no singularity at v = 0 in contact, but the friction band: split there too
                moving = v if v != 0 else mdl.time_rhs(True)(t, y0)[1]
                window = _event(lambda t, y: y[1], -_sign(moving))
            hit, yy = run_time(True, y0, [exit_, cut_leave, window])
        x, v, phi = float(yy[0]), float(yy[1]), yy[2:].reshape(2, 2)
        if hit is None:
            t = t_end
            break
        k, t = hit
        if mode == _FREE:
            if k == 0:  # onset: v > 0 here, so the bracket is positive
                x, mode, v_w = p.xI, _CONTACT, window_of(v)
            else:  # a reversal in free flight: the friction band (trap 2), checked at the next piece
                v = 0.0
        elif mode == _CUT:
            if k == 0:
                x, mode = p.xI, _FREE
            else:
                mode, v_w = _CONTACT, window_of(v)
        elif k == 0:
            x, mode = p.xI, _FREE
        elif k == 1:
            mode = _CUT
        elif mdl.windowed:
            v, mode = math.copysign(v_w, v), _WINDOW  # on the window's border: the next piece is in u
        else:
            v = 0.0
    else:
        raise RuntimeError(f"more than {MAX_PIECES} pieces before t = {t_end:.6g} s (stopped at t = {t:.9g} s)")
    return np.array([x, v]), np.array(phi, float), log


def _check_reversal(mdl, t, x):
    """A reversal in free flight must cross the friction band briskly (trap 2): |F| > 2 T."""
    force, T = mdl.outer(t, x, 0.0), mdl.p.T
    if T > 0 and abs(force) <= STICK_MARGIN * T:
        raise UnsupportedTrajectory(
            f"the cart (nearly) sticks at t = {t:.9g} s, x = {x:.6e} m: net force {force:.3g} N "
            f"against friction T = {T:.3g} N at v = 0 (needs |F| > {STICK_MARGIN:g} T)"
        )


def _u_pieces(mdl, t, x, v, phi, t_end, u_window, atol, opts, log):
    """Contact inside the window |u| < u_window, in u = sgn(v)|v|^n3 (trap 1), split at u = 0.

    Returns (what stopped it: None at the window's far border, "end", "exit" or "cut"; t, x, v, Phi)."""
    p = mdl.p
    u = math.copysign(abs(v) ** p.n3, v) if v != 0 else 0.0
    _, _, _, _, a = mdl.u_state(u, t, x)
    if a == 0:
        raise UnsupportedTrajectory(f"a = 0 at v = {v:.3g} m/s in contact at t = {t:.9g} s: the cart sticks there")
    sigma = _sign(a)  # u moves with a
    target = sigma * u_window
    stops = [0.0, target] if u != 0 and _sign(u) != sigma else [target]

    t_stop = _event(lambda u, z: z[0] - t_end, 1)
    exit_ = _event(lambda u, z: z[1] - p.xI, -1)
    cut = _event(lambda u, z: mdl.cut_function(max(z[1] - p.xI, 0.0), u), -1)
    a_zero = _event(lambda u, z: mdl.u_state(u, z[0], z[1])[4], 0)
    names = ("end", "exit", "cut", "a = 0")
    z = np.concatenate([[t, x], phi.ravel()])
    for stop in stops:
        if stop == u:
            continue
        sol = solve_ivp(mdl.u_rhs(), (u, stop), z, events=[t_stop, exit_, cut, a_zero], atol=atol, **opts)
        if sol.status == -1:  # dt/du = 1 / (du/dt) blew up: a -> 0 inside the window
            raise UnsupportedTrajectory(
                f"{opts['method']} failed in u = sgn(v)|v|^n3 after t = {z[0]:.12g} s ({sol.message}): "
                "the acceleration vanishes inside the window of contact around v = 0 (sticking in contact, "
                "or v_window too large)"
            )
        log.append((_WINDOW, "u", u, float(sol.t[-1]), sol.nfev))
        if sol.status == 1:
            k = min((k for k in range(4) if len(sol.t_events[k])), key=lambda k: abs(sol.t_events[k][0] - u))
            u, z = float(sol.t_events[k][0]), sol.y_events[k][0]
            if names[k] == "a = 0":
                raise UnsupportedTrajectory(
                    f"a changes sign at |v| = {abs(u) ** mdl.inv_n3:.3g} m/s in contact at t = {z[0]:.9g} s "
                    "(the cart sticks there, or v_window is too large)"
                )
            vv = math.copysign(abs(u) ** mdl.inv_n3, u)
            tt = t_end if names[k] == "end" else float(z[0])
            return names[k], tt, float(z[1]), vv, z[2:].reshape(2, 2)
        u, z = stop, sol.y[:, -1]
    return None, float(z[0]), float(z[1]), math.copysign(abs(u) ** mdl.inv_n3, u), z[2:].reshape(2, 2)
