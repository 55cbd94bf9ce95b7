"""Free flight in closed form: away from the friction band, an exact piece of the motion.

Away from
the friction band (|v| > U_BAND eps) free flight is a linear oscillator with constant friction
-T sign(v) and harmonic forcing, so

    x(t) = xs + P sin(w t) + Q cos(w t) + exp(-alpha tau) (A cos(wd tau) + B sin(wd tau)),

tau = t - t0, xs = -sign(v) T / k, alpha = c / 2m, wd = sqrt(k/m - alpha^2) (c^2 < 4 k m, as
model BC), (P, Q) the harmonic particular solution and (A, B) fitted to (x0, v0).

Events of a piece (sign(v) fixed): the impact x = xI (only while v > 0: x is monotone on the
piece), the band edge |v| = U_BAND eps heading for 0, and the Poincare times t = 2 pi i / w
(just the state there). The near-miss maximum of x lies at v = 0, inside the band: it is the
band piece's event, not free flight's. Both event functions g (xI - x, and |v| - U_BAND eps)
are located by safe marching: with |g''| <= G2 from the amplitudes (the k-th derivative of
the homogeneous part is at most wn^k R exp(-alpha tau), of the particular part w^k (P^2 +
Q^2)^(1/2)), g(t + h) >= g + g' h - G2 h^2 / 2, and the step to the first zero of that lower
bound can never step over a root, a grazing double root included; near a simple root the step
is Newton's from the safe side (quadratic convergence), and one plain Newton step ends it.
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.core.transitions import U_BAND
from impactosc.model.parameters import P_C, P_EPS, P_K, P_M, P_M0E, P_OMEGA, P_T, P_XI

__all__ = ["EV_BAND", "EV_IMPACT", "EV_NONE", "flight_piece", "flight_state"]

EV_NONE, EV_IMPACT, EV_BAND = 0, 1, 2  # how a closed-form piece ends
MAX_MARCH = 400  # safe-marching iterations per piece before giving up (EV_NONE)
G_TOL = 1e-12  # an event function within G_TOL of its scale is on its root: one Newton step ends it
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
    """Largest h with g + g1 h - g2max h^2 / 2 >= 0 (g >= 0): no root of g before t + h."""
    if g <= 0.0:
        return 0.0
    disc = math.sqrt(g1 * g1 + 2.0 * g2max * g)
    if g1 <= 0.0:
        return 2.0 * g / (disc - g1)
    return (g1 + disc) / g2max


@njit(cache=True)
def flight_piece(p, t0, x0, v0, isec, period, sections):
    """Closed-form free flight from (t0, x0, v0), |v0| >= U_BAND eps, to its first event.

    Returns (kind, t, x, v, isec, n_eval): kind EV_IMPACT (x = xI upwards) or EV_BAND (|v| =
    U_BAND eps heading for 0), EV_NONE if MAX_MARCH iterations found neither; the Poincare
    states t = isec * period passed on the way go to sections[j] = (t, x, v) (isec advances)."""
    w = p[P_OMEGA]
    s = 1.0 if v0 > 0.0 else -1.0
    alpha, wd, wn, P, Q, xs, A, B = _coefficients(p, s, t0, x0, v0)
    R0 = math.sqrt(A * A + B * B)
    pamp = math.sqrt(P * P + Q * Q)
    xI, edge = p[P_XI], U_BAND * p[P_EPS]
    tol_x, tol_v = G_TOL * max(abs(xI), 1e-3), G_TOL * edge
    t = t0
    n_sec = 0
    on_section = False
    for n in range(MAX_MARCH):
        x, v, a, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
        if on_section:
            if n_sec < sections.shape[0]:
                sections[n_sec, 0], sections[n_sec, 1], sections[n_sec, 2] = t, x, v
            n_sec += 1
            on_section = False
        r = R0 * math.exp(-alpha * (t - t0))
        # band edge: g = s v - edge, g' = s a, |g''| <= |x'''|
        gv = s * v - edge
        t_tol = T_TOL * max(1.0, abs(t))
        if s * a < 0.0 and (gv <= tol_v or gv < -s * a * t_tol):
            t = t - gv / (s * a)  # one Newton step onto the root
            x, v, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
            return EV_BAND, t, x, v, isec, n + 2
        h = _safe_step(max(gv, 0.0), s * a, r * wn**3 + pamp * w**3)
        if s > 0.0:  # impact: g = xI - x, g' = -v, |g''| <= |x''|
            gx = xI - x
            if gx <= tol_x or gx < v * t_tol:
                t = t + gx / v
                x, v, _, _ = _eval(w, alpha, wd, P, Q, xs, A, B, t0, t)
                return EV_IMPACT, t, x, v, isec, n + 2
            h = min(h, _safe_step(gx, -v, r * wn * wn + pamp * w * w))
        t_sec = isec * period
        if t + h >= t_sec:
            t = t_sec
            on_section = True  # its state is the next iteration's
            isec += 1
        else:
            t = t + h
    return EV_NONE, t, x, v, isec, MAX_MARCH


@njit(cache=True)
def flight_state(p, t0, x0, v0, t):
    """(x, v) of the closed-form piece from (t0, x0, v0) at t (friction -T sign(v0))."""
    s = 1.0 if v0 > 0.0 else -1.0
    alpha, wd, _, P, Q, xs, A, B = _coefficients(p, s, t0, x0, v0)
    x, v, _, _ = _eval(p[P_OMEGA], alpha, wd, P, Q, xs, A, B, t0, t)
    return x, v
