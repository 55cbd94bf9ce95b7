"""The friction band of a free-flight reversal, crossed in one go.

Where free flight in closed form (closed_flight.py) reaches the band's edge |v| = U_CLOSED eps
heading for v = 0, the motion through the band to |v| = U_CLOSED eps on the other side is, in
u = asinh(v/eps),

    dt/du = m eps cosh u / (G - c eps sinh u - T tanh u),   dx/du = eps sinh u dt/du,

G = F(t) - k x the net force other than friction. With G frozen at G* (|G*| > T) and c = 0 it
has a closed form: mirrored so that G* > 0 and v rises, G* cosh u - T sinh u = R cosh(u - u*)
(R = sqrt(G*^2 - T^2), tanh u* = T/G*), so dt/du = (m eps / R) cosh^2 u / cosh(u - u*) and

    t(u) = (m eps / R) (sinh(u + u*) - (T/R)^2 atan(sinh(u - u*))),

x(u) elementary too (:func:`_closed`). What the frozen force leaves out (F's change over the
crossing, ~1e-3 of G, the spring's and c v's, smaller) is a smooth remainder of dt/du, integrated
by Gauss-Legendre on each half of the band (from the entry to v = 0, and on to the exit) with
Picard's iteration for its dependence on t and x: each iteration gains the factor |dG/dt| dt / (G
- T) over the crossing (~1e-3). The remainder is analytic in the strip |Im u| < pi/2 (the frozen
form's pole is at u* + i pi/2): 8 nodes a half bring the crossing to the rounding of t and x (6
leave 2e-9 of its duration). About 1 us a crossing, where the band's piece takes ~11 DOP853 steps.

The crossing returns the state at v = 0 (an extremum of x, the core's event) and at the exit;
the caller falls back to the band's own piece (DOP853 steps in s = asinh(v/eps)) where it declines
(:func:`cross` returns ok = False): a net force that comes close to 1.5 T (the implicit solver's
hand-over, transitions.goes_implicit), a crossing slow enough that the force changes by more
than a small fraction of G - T, or an iteration that does not settle.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core.transitions import U_CLOSED
from impactosc.model.parameters import P_C, P_EPS, P_K, P_M, P_M0E, P_OMEGA, P_T


def _nodes(n):
    """Gauss-Legendre nodes y and weights w on [0, 1], and the matrix Q with Q[i, j] the
    integral from 0 to y_i of the j-th Lagrange basis polynomial of the nodes."""
    x, wt = np.polynomial.legendre.leggauss(n)
    y, w = 0.5 * (x + 1.0), 0.5 * wt
    vander = np.vander(y, n, increasing=True)  # basis monomials y^k at the nodes
    coef = np.linalg.inv(vander)  # Lagrange basis j = sum_k coef[k, j] y^k
    powers = np.arange(1, n + 1)
    integ = (y[:, None] ** powers[None, :]) / powers[None, :]  # integral of y^k from 0 to y_i
    return y, w, integ @ coef


@njit(cache=True, inline="always")
def _closed(z, ez, C, S, K, c2, eps):
    """(t, x) of the frozen crossing at u = u* + z (ez = exp(z)), each up to its constant:
    C = cosh u*, S = sinh u*, K = m eps / R, c2 = (T/R)^2."""
    iz = 1.0 / ez
    sz, cz = 0.5 * (ez - iz), 0.5 * (ez + iz)
    t = K * (sz * (C * C + S * S) + cz * 2.0 * C * S - c2 * math.atan(sz))
    # x' = eps sinh u t' = eps K (C^2 S cosh^2 z + (C^3 + 3 C S^2) cosh z sinh z + (2 C^2 S + S^3)
    # sinh^2 z - C S^2 tanh z), integrated in z
    x = (
        -0.5 * S * (C * C + S * S) * z
        + 0.5 * S * (3.0 * C * C + S * S) * sz * cz
        + 0.5 * C * (C * C + 3.0 * S * S) * sz * sz
        - C * S * S * math.log(cz)
    )
    return t, eps * K * x


N_NODES = 8  # Gauss-Legendre nodes a half: the crossing to the rounding of t and x (measured; 6: 2e-9 of it)
Y, W, Q = _nodes(N_NODES)
U_EDGE = math.asinh(U_CLOSED)  # u at the band's edge
E_EDGE = U_CLOSED + math.sqrt(U_CLOSED * U_CLOSED + 1.0)  # exp(U_EDGE)
E2 = np.exp(U_EDGE * Y)  # exp(u) at the second half's nodes (u from 0 to U_EDGE: fixed)
G_MIN = 1.6  # the frozen net force at entry at least G_MIN T: with KAPPA_MAX it stays above
# 1.6 T - KAPPA_MAX (1.6 - 1) T = 1.57 T over the crossing, clear of the implicit hand-over at 1.5 T
KAPPA_MAX = 0.05  # what the frozen force leaves out at most this fraction of G - T: it bounds
# Picard's factor (each iteration ~KAPPA_MAX fewer digits wrong) and keeps the remainder small
WT_MAX = 0.05  # w times the crossing's duration at most this: sin and cos by their Taylor series
PICARD_TOL = 1e-13  # relative change of the nodes' times that ends the iteration (what is left: ~kappa of it)
MAX_PICARD = 8  # iterations a half before declining


@njit(cache=True, inline="always")
def _forcing_change(f0, sa, ca, y):
    """f0 (sin(wt_a + y) - sin(w t_a)) for |y| <= WT_MAX: sin y and cos y - 1 by Taylor (their
    next terms y^9 / 9! and y^10 / 10! are below 1e-17 there)."""
    y2 = y * y
    sn = y * (1.0 - y2 / 6.0 * (1.0 - y2 / 20.0 * (1.0 - y2 / 42.0)))
    cm = -0.5 * y2 * (1.0 - y2 / 12.0 * (1.0 - y2 / 30.0 * (1.0 - y2 / 56.0)))
    return f0 * (sa * cm + ca * sn)


@njit(cache=True)
def _half(p, wk, f0, sa, ca, Gs, us, eus, C, S, K, c2, u0, e0, h, e1, tau0, dx0, tol):
    """One half of the band, u from u0 over h (wk row 0: exp(u) at its nodes; e0, e1: exp(u) at
    its ends; eus = exp(-u*)), from (tau0, dx0) (time and mirrored x since the entry): (tau, dx)
    at its end, or tau = -1 if Picard's iteration did not settle. The remainder of dt/du against
    the frozen closed form at a node is -m eps cosh u delta / (D* (D* + delta)), D* = G* - T tanh u,
    delta = G - c v - G*."""
    eps, m, k, c, T, w = p[P_EPS], p[P_M], p[P_K], p[P_C], p[P_T], p[P_OMEGA]
    n = N_NODES
    phi0, psi0 = _closed(u0 - us, e0 * eus, C, S, K, c2, eps)
    for i in range(n):
        e = wk[0, i]
        bt, bx = _closed(u0 + h * Y[i] - us, e * eus, C, S, K, c2, eps)
        wk[0, i] = 0.5 * (e + 1.0 / e)  # cosh u
        wk[1, i] = 0.5 * (e - 1.0 / e)  # sinh u
        wk[2, i] = tau0 + bt - phi0  # the frozen closed form at the node
        wk[3, i] = dx0 + bx - psi0
        wk[4, i] = Gs - T * wk[1, i] / wk[0, i]  # D*
        wk[5, i] = wk[2, i]  # the iterate: time and x at the node
        wk[6, i] = wk[3, i]
    last = math.inf
    for _ in range(MAX_PICARD):
        for i in range(n):
            delta = _forcing_change(f0, sa, ca, w * wk[5, i]) - k * wk[6, i] - c * eps * wk[1, i]
            r = -h * m * eps * wk[0, i] * delta / (wk[4, i] * (wk[4, i] + delta))
            wk[7, i] = r
            wk[8, i] = r * eps * wk[1, i]
        change = 0.0
        for i in range(n):
            st, sx = 0.0, 0.0
            for j in range(n):
                st += Q[i, j] * wk[7, j]
                sx += Q[i, j] * wk[8, j]
            change = max(change, abs(wk[2, i] + st - wk[5, i]))
            wk[5, i] = wk[2, i] + st
            wk[6, i] = wk[3, i] + sx
        # settled: this change below tol, or the next one (the iteration contracts by the factor
        # change / last, and what is left after this update is about that factor times it)
        if change <= tol or (change < last < math.inf and change * change <= tol * last):
            st, sx = 0.0, 0.0
            for j in range(n):
                st += W[j] * wk[7, j]
                sx += W[j] * wk[8, j]
            bt, bx = _closed(u0 + h - us, e1 * eus, C, S, K, c2, eps)
            return tau0 + bt - phi0 + st, dx0 + bx - psi0 + sx
        last = change
    return -1.0, 0.0


@njit(cache=True)
def cross(p, t_a, x_a, v_a):
    """The band crossed from (t_a, x_a, v_a), |v_a| at the edge U_CLOSED eps heading for 0, to
    |v| = U_CLOSED eps on the other side: (ok, t0, x0, t1, x1, v1), the state at v = 0 and at the
    exit; ok False where it declines (see the module's docstring)."""
    eps, m, k, T, w = p[P_EPS], p[P_M], p[P_K], p[P_T], p[P_OMEGA]
    sg = -1.0 if v_a > 0.0 else 1.0  # mirrored: V = sg v rises through 0, G* > 0
    sa, ca = math.sin(w * t_a), math.cos(w * t_a)
    f0 = sg * p[P_M0E] * w * w
    Gs = f0 * sa - k * sg * x_a
    if not Gs > G_MIN * T:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    R2 = (Gs - T) * (Gs + T)
    span = 2.0 * m * eps * U_CLOSED * Gs / R2  # the crossing's duration, frozen
    # what the frozen force leaves out, at most: the forcing's change (|dF/dt| over the crossing at
    # most, as |F''| <= f0 w^2), the spring's over x's excursion on the slow side, and c v's
    slope = abs(f0) * w * (abs(ca) + w * span)
    ve = U_CLOSED * eps
    left_out = slope * span + k * m * ve * ve / (2.0 * (Gs - T)) + p[P_C] * ve
    if left_out > KAPPA_MAX * (Gs - T) or w * span > WT_MAX:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    R = math.sqrt(R2)
    us = math.atanh(T / Gs)
    eus = (Gs - T) / R  # exp(-u*)
    C, S = Gs / R, T / R
    K = m * eps / R
    c2 = S * S
    ya = sg * v_a / eps  # < 0
    ua = math.asinh(ya)
    ea = 1.0 / (math.sqrt(ya * ya + 1.0) - ya)  # exp(ua), without cancellation
    wk = np.empty((9, N_NODES))
    for i in range(N_NODES):
        wk[0, i] = math.exp(ua * (1.0 - Y[i]))
    tol = PICARD_TOL * span
    tau0, dx0 = _half(p, wk, f0, sa, ca, Gs, us, eus, C, S, K, c2, ua, ea, -ua, 1.0, 0.0, 0.0, tol)
    if tau0 < 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(N_NODES):
        wk[0, i] = E2[i]
    tau1, dx1 = _half(p, wk, f0, sa, ca, Gs, us, eus, C, S, K, c2, 0.0, 1.0, U_EDGE, E_EDGE, tau0, dx0, tol)
    if tau1 < 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, t_a + tau0, x_a + sg * dx0, t_a + tau1, x_a + sg * dx1, sg * U_CLOSED * eps
