"""The local contact model of the obstacle fit (:mod:`.obstacle`) and its fits, compiled.

Why a module of its own: these are the numba kernels the fit spends its time in, apart from the
estimator that calls them.  In a window around a turning point the motion is
x'' = a - gamma v - mu sign(v) - K max(0, h^n1 (1 + b sign(v) |v|^n3)), h = x - x_impact, with the
vertex (H, v = 0) at time tau; :func:`integrate_window` samples it (RK4 outward from the vertex,
with its tangent in H), :func:`fit_vertices` fits each window's H and tau to its samples, and
:func:`projected_jacobian` gives the outer fit's Jacobian in the shared constants.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["integrate_window", "fit_vertices", "projected_jacobian", "model_window"]

# graded first legs: NGRADE steps growing by RATIO (first step span / 54)
_NGRADE = 8
_H0 = 1e-4  # m, reference penetration of the contact law with a fitted exponent
_H0_15 = _H0 * math.sqrt(_H0)
_RATIO = 1.6


@njit(cache=True, inline="always")
def _acc(x, v, a, gam, mu, K, xi, b, n1, n3):
    """The local model's acceleration and its partial derivatives in x and v.

    The contact's partials are 0 where it is off; the damping's d|v|^n3/dv, infinite at v = 0,
    is taken as 0 there (only the vertex has v = 0, where the tangent's dv is 0).
    """
    acc = a - gam * v
    if v > 0.0:
        acc -= mu
    elif v < 0.0:
        acc += mu
    ax = 0.0
    av = -gam
    h = x - xi
    if h <= 0.0:
        return acc, ax, av
    # K h^n1 written K h0^1.5 (h / h0)^n1, h0 = 100 um: K keeps its meaning (kI/m of the Hertz
    # law at 100 um) whatever n1, so the fitted K and n1 are not tied by units
    if n1 == 1.5:
        sq = math.sqrt(h)
        br = h * sq
        dbr = 1.5 * sq
    else:
        br = _H0_15 * (h / _H0) ** n1
        dbr = n1 * br / h
    fac = 1.0
    dfac = 0.0
    if v != 0.0 and b != 0.0:
        av_n3 = abs(v) ** n3
        fac = 1.0 + b * av_n3 if v > 0.0 else 1.0 - b * av_n3
        dfac = b * n3 * av_n3 / abs(v)
    f = br * fac
    if f <= 0.0:
        return acc, ax, av
    return acc - K * f, -K * dbr * fac, av - K * br * dfac


@njit(cache=True, inline="always")
def _rk4(x, v, p, q, hh, a, gam, mu, K, xi, b, n1, n3):
    """One RK4 step of the state (x, v) and of its tangent (p, q) = d(x, v)/dH."""
    k1v, ax, av = _acc(x, v, a, gam, mu, K, xi, b, n1, n3)
    k1x, k1p, k1q = v, q, ax * p + av * q
    x2, v2, p2, q2 = x + 0.5 * hh * k1x, v + 0.5 * hh * k1v, p + 0.5 * hh * k1p, q + 0.5 * hh * k1q
    k2v, ax, av = _acc(x2, v2, a, gam, mu, K, xi, b, n1, n3)
    k2x, k2p, k2q = v2, q2, ax * p2 + av * q2
    x3, v3, p3, q3 = x + 0.5 * hh * k2x, v + 0.5 * hh * k2v, p + 0.5 * hh * k2p, q + 0.5 * hh * k2q
    k3v, ax, av = _acc(x3, v3, a, gam, mu, K, xi, b, n1, n3)
    k3x, k3p, k3q = v3, q3, ax * p3 + av * q3
    x4, v4, p4, q4 = x + hh * k3x, v + hh * k3v, p + hh * k3p, q + hh * k3q
    k4v, ax, av = _acc(x4, v4, a, gam, mu, K, xi, b, n1, n3)
    k4x, k4p, k4q = v4, q4, ax * p4 + av * q4
    c = hh / 6.0
    return (
        x + c * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
        v + c * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        p + c * (k1p + 2.0 * k2p + 2.0 * k3p + k4p),
        q + c * (k1q + 2.0 * k2q + 2.0 * k3q + k4q),
    )


@njit(cache=True)
def integrate_window(H, tau, a, gam, mu, K, xi, b, n1, n3, half, dt, nsub, out, dH, dtau):
    """Samples at k dt (k = -half..half) of the local model with its vertex (H, v = 0) at tau,
    to out, and their derivatives in H (dH, the tangent) and in tau (dtau = -v).

    Integrated outward from the vertex in both directions, so no RK4 step straddles v = 0
    (where |v|^n3 has an infinite derivative); the first two legs of each side, which start at
    or near the vertex, use geometrically growing steps.
    """
    k0 = int(math.ceil(tau / dt))
    tot = 0.0
    w = 1.0
    for _ in range(_NGRADE):
        tot += w
        w *= _RATIO
    for sign in (1, -1):
        x = H
        v = 0.0
        p = 1.0
        q = 0.0
        pos = 0.0
        k = k0 if sign > 0 else k0 - 1
        graded = 2
        while -half <= k <= half:
            target = k * dt - tau
            span = target - pos
            if graded > 0:
                w = span / tot
                for _ in range(_NGRADE):
                    x, v, p, q = _rk4(x, v, p, q, w, a, gam, mu, K, xi, b, n1, n3)
                    w *= _RATIO
                graded -= 1
            else:
                hh = span / nsub
                for _ in range(nsub):
                    x, v, p, q = _rk4(x, v, p, q, hh, a, gam, mu, K, xi, b, n1, n3)
            pos = target
            out[k + half] = x
            dH[k + half] = p
            dtau[k + half] = -v
            k += sign


@njit(cache=True)
def _ssr(Y, j, f):
    s = 0.0
    for k in range(f.size):
        r = Y[j, k] - f[k]
        s += r * r
    return s


@njit(cache=True)
def fit_vertices(Y, a, gam, mu, K, xi, b, n1, n3, half, dt, nsub, H, tau, tau_max, max_iter, out):
    """Per window, fit H and tau (Levenberg-Marquardt); residuals to out.

    The Jacobian comes with each trajectory (its tangent in H, and -v in tau), so a trial
    costs one integration, and the fit stops when the Gauss-Newton step predicts less than
    1e-12 of the sum of squares (a trial would only confirm it). H and tau hold the starting
    values on entry and the fitted ones on return; tau is kept within +-tau_max of the
    window's centre.
    """
    M, L = Y.shape
    f = np.empty(L)
    fH = np.empty(L)
    ft = np.empty(L)
    fc = np.empty(L)
    cH = np.empty(L)
    ct = np.empty(L)
    for j in range(M):
        h_ = H[j]
        t_ = tau[j]
        integrate_window(h_, t_, a[j], gam, mu, K, xi, b, n1, n3, half, dt, nsub, f, fH, ft)
        s0 = _ssr(Y, j, f)
        lam = 1e-3
        for _ in range(max_iter):
            a11 = a12 = a22 = g1 = g2 = 0.0
            for k in range(L):
                jh = fH[k]
                jt = ft[k]
                r = Y[j, k] - f[k]
                a11 += jh * jh
                a12 += jh * jt
                a22 += jt * jt
                g1 += jh * r
                g2 += jt * r
            # tau held at its bound when the Gauss-Newton step would leave it: a fit in H alone
            det0 = a11 * a22 - a12 * a12
            pinned = det0 > 0.0 and abs(t_) >= tau_max and (a11 * g2 - a12 * g1) * t_ > 0.0
            if pinned or det0 <= 0.0:
                decrement = g1 * g1 / a11 if a11 > 0.0 else 0.0
            else:
                decrement = (a22 * g1 * g1 - 2.0 * a12 * g1 * g2 + a11 * g2 * g2) / det0
            # converged: the Gauss-Newton step would lower the sum of squares by less than this
            # (no trial integrated to find that out)
            if decrement <= 1e-12 * s0:
                break
            done = True
            for _try in range(30):
                b11 = a11 * (1.0 + lam)
                b22 = a22 * (1.0 + lam)
                if pinned:
                    hc = h_ + g1 / b11
                    tc = t_
                else:
                    det = b11 * b22 - a12 * a12
                    if det <= 0.0:
                        lam *= 4.0
                        continue
                    hc = h_ + (b22 * g1 - a12 * g2) / det
                    tc = min(max(t_ + (b11 * g2 - a12 * g1) / det, -tau_max), tau_max)
                integrate_window(hc, tc, a[j], gam, mu, K, xi, b, n1, n3, half, dt, nsub, fc, cH, ct)
                s1 = _ssr(Y, j, fc)
                if s1 <= s0:
                    done = s0 - s1 <= 1e-12 * s0 + 1e-300
                    lam = max(lam / 3.0, 1e-9)
                    h_, t_, s0 = hc, tc, s1
                    f[:] = fc
                    fH[:] = cH
                    ft[:] = ct
                    break
                lam *= 4.0
            if done:
                break
        H[j] = h_
        tau[j] = t_
        for k in range(L):
            out[j, k] = Y[j, k] - f[k]


@njit(cache=True)
def projected_jacobian(Y, a, gam, mu, consts, steps, half, dt, nsub, H, tau, tau_max, J):
    """Jacobian of the residuals Y - f in the shared constants, by variable projection (Kaufman).

    Why not differences of the whole fit: each of those refits every window's H and tau (several
    integrations per window); here a constant's column is its forward difference at the fitted
    H and tau (one integration per window), less its projection on the window's own directions
    (the tangent in H, and -v in tau unless tau is at its bound), which that window's fit takes
    up. Its J^T J is the Gauss-Newton information of the constants with every window's H and
    tau eliminated: the covariance of the fit. consts: rows (K, xi, b, n1, n3), the first at
    the point, row i + 1 with entry i of the fitted constants stepped by steps[i]; J: rows
    window by window like Y.ravel(), one column per step.
    """
    M, L = Y.shape
    P = steps.size
    f = np.empty(L)
    fH = np.empty(L)
    ft = np.empty(L)
    fi = np.empty(L)
    scratch = np.empty(L)
    D = np.empty((L, P))
    K, xi, b, n1, n3 = consts[0]
    for j in range(M):
        integrate_window(H[j], tau[j], a[j], gam, mu, K, xi, b, n1, n3, half, dt, nsub, f, fH, ft)
        for i in range(P):
            Ki, xii, bi, n1i, n3i = consts[i + 1]
            integrate_window(H[j], tau[j], a[j], gam, mu, Ki, xii, bi, n1i, n3i, half, dt, nsub, fi, scratch, scratch)
            for k in range(L):
                D[k, i] = (fi[k] - f[k]) / steps[i]
        a11 = a12 = a22 = 0.0
        for k in range(L):
            a11 += fH[k] * fH[k]
            a12 += fH[k] * ft[k]
            a22 += ft[k] * ft[k]
        det = a11 * a22 - a12 * a12
        with_tau = abs(tau[j]) < tau_max * (1.0 - 1e-9) and det > 1e-12 * a11 * a22
        for i in range(P):
            g1 = g2 = 0.0
            for k in range(L):
                g1 += fH[k] * D[k, i]
                g2 += ft[k] * D[k, i]
            if with_tau:
                c1 = (a22 * g1 - a12 * g2) / det
                c2 = (a11 * g2 - a12 * g1) / det
            else:
                c1 = g1 / a11 if a11 > 0.0 else 0.0
                c2 = 0.0
            for k in range(L):
                J[j * L + k, i] = -(D[k, i] - c1 * fH[k] - c2 * ft[k])


def model_window(H, tau, a, K, x_impact, b, n3, half, dt, *, gamma=0.0, mu=0.0, nsub=2, n1=1.5):
    """The local model's samples at k dt, k = -half..half (vertex (H, v = 0) at tau); for tests."""
    out, d_h, d_tau = np.empty((3, 2 * half + 1))
    args = (float(a), gamma, mu, float(K), float(x_impact), float(b), float(n1), float(n3))
    integrate_window(float(H), float(tau), *args, half, dt, nsub, out, d_h, d_tau)
    return out
