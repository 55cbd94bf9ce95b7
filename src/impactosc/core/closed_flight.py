"""Free flight in closed form: away from the friction band, an exact piece of the motion.

Away from
the friction band (|v| > U_CLOSED eps) free flight is a linear oscillator with constant friction
-T sign(v) and harmonic forcing, so

    x(t) = xs + P sin(w t) + Q cos(w t) + exp(-alpha tau) (A cos(wd tau) + B sin(wd tau)),

tau = t - t0, xs = -sign(v) T / k, alpha = c / 2m, wd = sqrt(k/m - alpha^2) (c^2 < 4 k m, as
model BC), (P, Q) the harmonic particular solution and (A, B) fitted to (x0, v0).

Events of a piece (sign(v) fixed): the impact x = xI (only while v > 0: x is monotone on the
piece), the band edge |v| = U_CLOSED eps heading for 0, and the Poincare times t = 2 pi i / w
(just the state there). The near-miss maximum of x lies at v = 0, inside the band: it is the
band's event (crossed in one go by band_crossing.py, or by the band piece), not free flight's. Both event functions g (xI - x, and |v| - U_CLOSED eps)
are located by safe marching: with |g''| <= G2 from the amplitudes (the k-th derivative of
the homogeneous part is at most wn^k R exp(-alpha tau), of the particular part w^k (P^2 +
Q^2)^(1/2)), g(t + h) >= g + g' h - G2 h^2 / 2, and the step to the first zero of that lower
bound can never step over a root, a grazing double root included; near a simple root the step
is Newton's from the safe side (quadratic convergence), and one plain Newton step ends it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core import band_crossing
from impactosc.core.events import EV_X_UP, sign
from impactosc.core.layout import (
    C_BY_MODE,
    C_STEPS,
    CLOSED,
    EXPLICIT,
    R_WIN_DT,
    R_WIN_T0,
    S_T,
    S_V,
    S_WIN,
    S_X,
    TIME,
)
from impactosc.core.pieces import start_piece, store
from impactosc.core.sampling import window_due
from impactosc.core.transitions import U_CLOSED, apply_event, band_crossed, enter_band, set_piece
from impactosc.model.equations import FREE
from impactosc.model.parameters import P_C, P_EPS, P_K, P_M, P_M0E, P_OMEGA, P_T, P_XI

__all__ = [
    "EV_BAND",
    "EV_END",
    "EV_IMPACT",
    "EV_NONE",
    "closed_step",
    "corrected_state",
    "flight_piece",
    "flight_state",
    "march",
]

EV_NONE, EV_IMPACT, EV_BAND, EV_END = 0, 1, 2, 3  # how a closed-form march ends
MAX_MARCH = 400  # safe-marching iterations per piece before giving up (EV_NONE)
G_TOL = 1e-12  # an event function within G_TOL of its scale is on its root: one Newton step ends it
MAX_TURN = 30  # Newton iterations for the minimum of |v| inside a piece
T_TOL = 1e-14  # ... as is one whose root is closer than T_TOL max(1, t) in time (the safe step cannot resolve less)


# --- the closed form ------------------------------------------------------------------------
@njit(cache=True)
def _coefficients(p, s, t0, x0, v0):
    """(alpha, wd, wn, P, Q, xs, A, B) of the piece from (t0, x0, v0) with friction -s T."""
    m, k, c, w = p[P_M], p[P_K], p[P_C], p[P_OMEGA]
    f = p[P_M0E] * w * w
    alpha = c / (2.0 * m)
    wn = math.sqrt(k / m)
    wd = math.sqrt(wn * wn - alpha * alpha)
    kd = k - m * w * w
    den = kd * kd + (c * w) ** 2
    P = f * kd / den
    Q = -f * c * w / den
    xs = -s * p[P_T] / k
    sw, cw = math.sin(w * t0), math.cos(w * t0)
    A = x0 - xs - (P * sw + Q * cw)
    B = (v0 - w * (P * cw - Q * sw) + alpha * A) / wd
    return alpha, wd, wn, P, Q, xs, A, B


@njit(cache=True, inline="always")
def _eval(w, alpha, wd, P, Q, xs, A, B, t0, t):
    """(x, v, a, jerk) at t: particular part by derivatives of sin, homogeneous by the map
    (A, B) -> (-alpha A + wd B, -alpha B - wd A) (multiplication by -alpha + i wd)."""
    tau = t - t0
    e = math.exp(-alpha * tau)
    cd, sd = math.cos(wd * tau), math.sin(wd * tau)
    sw, cw = math.sin(w * t), math.cos(w * t)
    a0, b0 = A, B
    a1, b1 = -alpha * a0 + wd * b0, -alpha * b0 - wd * a0
    a2, b2 = -alpha * a1 + wd * b1, -alpha * b1 - wd * a1
    a3, b3 = -alpha * a2 + wd * b2, -alpha * b2 - wd * a2
    ps = P * sw + Q * cw
    pc = P * cw - Q * sw
    x = xs + ps + e * (a0 * cd + b0 * sd)
    v = w * pc + e * (a1 * cd + b1 * sd)
    a = -w * w * ps + e * (a2 * cd + b2 * sd)
    j = -w * w * w * pc + e * (a3 * cd + b3 * sd)
    return x, v, a, j


@njit(cache=True, inline="always")
def _safe_step(g, g1, g2max):
    """Largest h with g + g1 h - g2max h^2 / 2 >= 0 (g >= 0): no root of g before t + h. On the
    root (g = 0) and leaving it (g1 > 0, the band's far edge where a crossing ends), up to the
    bound's next root."""
    if g < 0.0 or (g == 0.0 and g1 <= 0.0):
        return 0.0
    disc = math.sqrt(g1 * g1 + 2.0 * g2max * g)
    if g1 <= 0.0:
        return 2.0 * g / (disc - g1)
    return (g1 + disc) / g2max


# --- the friction residual -------------------------------------------------------------------
RESIDUAL_POINTS = 5  # Gauss-Legendre points per half segment
_GL_X, _GL_W = np.polynomial.legendre.leggauss(RESIDUAL_POINTS)
GL_Y, GL_W = 0.5 * (_GL_X + 1.0), 0.5 * _GL_W  # on [0, 1]
RESIDUAL_FLOOR = 1e-17  # m/s: a segment whose residual impulse per unit mass is below this is left as it is


@njit(cache=True, inline="always")
def _residual_force(p, s, v):
    """The regularised friction minus the closed form's: T s (1 - |v| / sqrt(v^2 + eps^2)) >= 0
    along s (the true friction is weaker), ~ T eps^2 / (2 v^2) outside the band."""
    eps = p[P_EPS]
    av = abs(v)
    return s * p[P_T] * (eps * eps / (math.sqrt(av * av + eps * eps) * (math.sqrt(av * av + eps * eps) + av)))


@njit(cache=True)
def _half(p, s, w, alpha, wd, P, Q, A, B, t0, t_from, direction, span, ec, es):
    """One half of the residual's Duhamel integral to the segment's end t1: from t_from over
    `span` towards the other end (direction +1 forwards, -1 backwards), in z with tau = tau_c
    (exp(z) - 1). tau_c is the time |v| takes to double from t_from: |v|/|a| where v is near
    linear (a band's edge), sqrt(2 |v| / |jerk|) at a minimum of |v|; there the residual ~
    1 / |v|^2 decays like exp(-z) or faster and the integrand is smooth in z (Gauss-Legendre,
    RESIDUAL_POINTS). The impulse response exp((-alpha + i wd)(t1 - t)) is (ec + i es), that of
    the whole segment, times the inverse of the piece's own rotation at t: no transcendental of
    its own."""
    m = p[P_M]
    _, v, a, j = _eval(w, alpha, wd, P, Q, 0.0, A, B, t0, t_from)
    tau_c = span
    if abs(a) * span > abs(v):
        tau_c = abs(v) / abs(a)
    if abs(j) * span * span > 2.0 * abs(v):
        tau_c = min(tau_c, math.sqrt(2.0 * abs(v) / abs(j)))
    tau_c = max(tau_c, 1e-9 * span)
    z_max = math.log1p(span / tau_c)
    dx, dv = 0.0, 0.0
    for i in range(GL_Y.shape[0]):
        ez = math.exp(z_max * GL_Y[i])
        t = t_from + direction * tau_c * (ez - 1.0)
        tau = t - t0
        e = math.exp(-alpha * tau)
        cd, sd = math.cos(wd * tau), math.sin(wd * tau)
        vt = w * (P * math.cos(w * t) - Q * math.sin(w * t)) + e * (
            (-alpha * A + wd * B) * cd + (-alpha * B - wd * A) * sd
        )
        f = _residual_force(p, s, vt) * z_max * GL_W[i] * tau_c * ez / (m * e)
        kc, ks = ec * cd + es * sd, es * cd - ec * sd  # exp(alpha (t1 - t)) (cos, sin)(wd (t1 - t)) * exp(-alpha tau)
        dx += f * ks / wd
        dv += f * (kc - alpha / wd * ks)
    return dx, dv


@njit(cache=True)
def _turn(w, alpha, wd, P, Q, A, B, t0, tl, tr):
    """The minimum of |v| bracketed by [tl, tr] (a changes sign there): safeguarded Newton on a."""
    _, _, al, _ = _eval(w, alpha, wd, P, Q, 0.0, A, B, t0, tl)
    t = 0.5 * (tl + tr)
    for _ in range(MAX_TURN):
        _, _, a, j = _eval(w, alpha, wd, P, Q, 0.0, A, B, t0, t)
        if (a > 0.0) == (al > 0.0):
            tl = t
        else:
            tr = t
        step = -a / j if j != 0.0 else 0.0
        t_new = t + step
        if not tl < t_new < tr:
            t_new = 0.5 * (tl + tr)
        if abs(t_new - t) <= T_TOL * max(1.0, abs(t)):
            return t_new
        t = t_new
    return t


@njit(cache=True)
def residual_correction(p, s, w, alpha, wd, P, Q, xs, A, B, t0, t1, tl, tr):
    """(dx, dv) at t1 of the regularised friction's residual over the segment [t0, t1] of the
    closed form (Duhamel's integral against the oscillator's impulse response, to first order: the
    residual is ~1e-7 of T at the band's edge and the state it moves is moved by ~1e-10 of itself).
    The residual peaks where |v| is smallest: at the segment's ends next to a friction band, and
    at a minimum of |v| inside it (a near miss of the band, bracketed by [tl, tr], tl < tr; none
    if tl >= tr). Each stretch between them is integrated in two halves, each graded at its end."""
    if t1 <= t0:
        return 0.0, 0.0
    m = p[P_M]
    _, va, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t0)
    _, vb, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t1)
    peak = max(abs(_residual_force(p, s, va)), abs(_residual_force(p, s, vb)))
    tm = t1
    if tl < tr:
        tm = _turn(w, alpha, wd, P, Q, A, B, t0, max(tl, t0), min(tr, t1))
        _, vm, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, tm)
        peak = max(peak, abs(_residual_force(p, s, vm)))
    if peak * (t1 - t0) / m < RESIDUAL_FLOOR:
        return 0.0, 0.0
    d = t1 - t0
    ed = math.exp(-alpha * d)
    ec, es = ed * math.cos(wd * d), ed * math.sin(wd * d)
    dx, dv = 0.0, 0.0
    a, b = t0, tm
    for _ in range(2):  # [t0, tm] and [tm, t1] (tm = t1 without a minimum inside)
        if b > a:
            half = 0.5 * (b - a)
            dx1, dv1 = _half(p, s, w, alpha, wd, P, Q, A, B, t0, a, 1.0, half, ec, es)
            dx2, dv2 = _half(p, s, w, alpha, wd, P, Q, A, B, t0, b, -1.0, half, ec, es)
            dx += dx1 + dx2
            dv += dv1 + dv2
        a, b = tm, t1
    return dx, dv


@njit(cache=True)
def march(p, t0, x0, v0, t_end):
    """Closed-form free flight from (t0, x0, v0), |v0| >= U_CLOSED eps, to its first event or t_end.

    Returns (kind, t, x, v, n_eval, tl, tr): kind EV_IMPACT (x = xI upwards), EV_BAND (|v| =
    U_CLOSED eps heading for 0), EV_END (t_end reached first), or EV_NONE if MAX_MARCH iterations
    found none of them (the state reached is returned: time steps go on from there). The state
    returned includes the friction residual's correction; for it, the march notes where |v|
    passed through its lowest minimum inside the piece (s a from < 0 to > 0 between two of its
    points): [tl, tr] (tl >= tr: none)."""
    w = p[P_OMEGA]
    s = 1.0 if v0 > 0.0 else -1.0
    alpha, wd, wn, P, Q, xs, A, B = _coefficients(p, s, t0, x0, v0)
    R0 = math.sqrt(A * A + B * B)
    pamp = math.sqrt(P * P + Q * Q)
    xI, edge = p[P_XI], U_CLOSED * p[P_EPS]
    tol_x, tol_v = G_TOL * max(abs(xI), 1e-3), G_TOL * edge
    t = t0
    x, v = x0, v0
    t_prev, a_prev = t0, 0.0
    tl, tr, v_low = 0.0, 0.0, math.inf  # the bracket of the lowest minimum of |v| seen
    for n in range(MAX_MARCH):
        x, v, a, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
        if n > 0 and s * a_prev < 0.0 <= s * a and s * v < v_low:
            tl, tr, v_low = t_prev, t, s * v
        t_prev, a_prev = t, a
        if t >= t_end:
            dx, dv = residual_correction(p, s, w, alpha, wd, P, Q, xs, A, B, t0, t, tl, tr)
            return EV_END, t, x + dx, v + dv, n + 1, tl, tr
        r = R0 * math.exp(-alpha * (t - t0))
        # band edge: g = s v - edge, g' = s a, |g''| <= |x'''|
        gv = s * v - edge
        t_tol = T_TOL * max(1.0, abs(t))
        if s * a < 0.0 and (gv <= tol_v or gv < -s * a * t_tol):
            t = t - gv / (s * a)  # one Newton step onto the root
            x, v, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
            dx, dv = residual_correction(p, s, w, alpha, wd, P, Q, xs, A, B, t0, t, tl, tr)
            return EV_BAND, t, x + dx, v + dv, n + 2, tl, tr
        h = _safe_step(max(gv, 0.0), s * a, r * wn**3 + pamp * w**3)
        if s > 0.0:  # impact: g = xI - x, g' = -v, |g''| <= |x''|
            gx = xI - x
            if gx <= tol_x or gx < v * t_tol:
                t = t + gx / v
                x, v, a, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
                dx, dv = residual_correction(p, s, w, alpha, wd, P, Q, xs, A, B, t0, t, tl, tr)
                dt = -dx / v  # the corrected trajectory reaches xI this much earlier
                return EV_IMPACT, t + dt, x + dx + v * dt, v + dv + a * dt, n + 2, tl, tr
            h = min(h, _safe_step(gx, -v, r * wn * wn + pamp * w * w))
        t = min(t + h, t_end)
    dx, dv = residual_correction(p, s, w, alpha, wd, P, Q, xs, A, B, t0, t, tl, tr)
    return EV_NONE, t, x + dx, v + dv, MAX_MARCH, tl, tr


@njit(cache=True)
def flight_piece(p, t0, x0, v0, isec, period, sections):
    """Closed-form free flight from (t0, x0, v0), |v0| >= U_CLOSED eps, to its first event.

    Returns (kind, t, x, v, isec, n_eval): kind EV_IMPACT (x = xI upwards) or EV_BAND (|v| =
    U_CLOSED eps heading for 0), EV_NONE if MAX_MARCH iterations found neither; the Poincare
    states t = isec * period passed on the way go to sections[j] = (t, x, v) (isec advances),
    each the start of the next march, as in the core."""
    t, x, v = t0, x0, v0
    n_eval = 0
    n_sec = 0
    while True:
        kind, t, x, v, n, _, _ = march(p, t, x, v, isec * period)
        n_eval += n
        if kind != EV_END:
            return kind, t, x, v, isec, n_eval
        if n_sec < sections.shape[0]:
            sections[n_sec, 0], sections[n_sec, 1], sections[n_sec, 2] = t, x, v
        n_sec += 1
        isec += 1


@njit(cache=True)
def closed_step(p, st, cnt, rs, ws, ev, n_ev, win_x, win_v, t_target):
    """One step of a free-flight piece in closed form: from the state to its first event, or to
    t_target (the next Poincare time or the run's end), where the driver takes over. An impact
    starts the contact as time steps would; the band edge hands over to the band's variable; a
    march that gave up (a long grazing approach) goes on in time steps."""
    t0, x0, v0 = st[S_T], st[S_X], st[S_V]
    kind, t, x, v, _, tl, tr = march(p, t0, x0, v0, t_target)
    cnt[C_BY_MODE + CLOSED] += 1
    cnt[C_STEPS] += 1
    if window_due(st, rs, win_x, t):
        _sample_window(p, t0, x0, v0, t, tl, tr, st, rs, win_x, win_v)
    d0 = ws[3]
    if kind == EV_END:
        store(st, t, x, v, t, 0.0)
    elif kind == EV_IMPACT:
        ev, n_ev, x, v = apply_event(p, st, cnt, rs, ev, n_ev, EV_X_UP, t, x, v, 1.0, 0.0)
        start_piece(p, st, cnt, d0, t, x, v, 0.0)
    elif kind == EV_BAND:
        ev, n_ev = _band(p, st, cnt, rs, ev, n_ev, win_x, d0, t, x, v, t_target)
    else:
        set_piece(st, FREE, EXPLICIT, TIME)
        start_piece(p, st, cnt, d0, t, x, v, 0.0)
    return ev, n_ev


@njit(cache=True)
def _band(p, st, cnt, rs, ev, n_ev, win_x, d0, t, x, v, t_target):
    """Free flight reached the friction band at (t, x, v): crossed in one go (band_crossing.cross)
    where it applies and nothing the core records falls inside the crossing but its v = 0 (a
    Poincare time, a window sample, the run's end, an impact before the maximum of x), else
    stepped through in asinh(v/eps). The crossing is part of this closed-form step (counted as one)."""
    ok, t0, x0, t1, x1, v1 = band_crossing.cross(p, t, x, v)
    if not (ok and t1 < t_target and not window_due(st, rs, win_x, t1) and (v < 0.0 or x0 < p[P_XI])):
        enter_band(p, st, cnt, d0, t, x, v)
        return ev, n_ev
    return band_crossed(p, st, cnt, rs, ev, n_ev, d0, sign(v), t0, x0, t1, x1, v1)


@njit(cache=True)
def _sample_window(p, t0, x0, v0, t1, tl, tr, st, rs, win_x, win_v):
    """The trajectory-window samples due up to t1, from the closed form of the piece with the
    friction residual's correction to each (its minimum of |v| bracketed by [tl, tr])."""
    j = int(st[S_WIN])
    while j < win_x.shape[0]:
        ts = rs[R_WIN_T0] + j * rs[R_WIN_DT]
        if ts > t1:
            break
        win_x[j], win_v[j] = corrected_state(p, t0, x0, v0, ts, tl, tr)
        j += 1
    st[S_WIN] = j


@njit(cache=True)
def corrected_state(p, t0, x0, v0, t, tl, tr):
    """(x, v) at t of the closed-form piece from (t0, x0, v0) with the friction residual's
    correction over [t0, t] (the piece's minimum of |v| bracketed by [tl, tr], if before t)."""
    s = 1.0 if v0 > 0.0 else -1.0
    w = p[P_OMEGA]
    alpha, wd, _, P, Q, xs, A, B = _coefficients(p, s, t0, x0, v0)
    x, v, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
    if not tl < t:
        tl, tr = 0.0, 0.0
    dx, dv = residual_correction(p, s, w, alpha, wd, P, Q, xs, A, B, t0, t, tl, min(tr, t))
    return x + dx, v + dv


@njit(cache=True)
def flight_state(p, t0, x0, v0, t):
    """(x, v) of the closed-form piece from (t0, x0, v0) at t (friction -T sign(v0))."""
    s = 1.0 if v0 > 0.0 else -1.0
    alpha, wd, _, P, Q, xs, A, B = _coefficients(p, s, t0, x0, v0)
    x, v, _, _ = _eval(p[P_OMEGA], alpha, wd, P, Q, xs, A, B, t0, t)
    return x, v
