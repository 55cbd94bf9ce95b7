"""Obstacle position from a sampled record: the contact law fitted to the samples around each turning point.

Why not the curvature of the turning points alone (:func:`impactosc.measured.obstacle_estimate.estimate_x_impact`
with ``method="curvature"``): a quadratic fitted over +-2.5 ms of a contact does not see the
curvature at the vertex.  The contact force grows like h^1.5 and its Hunt-Crossley damping
b h^1.5 |v|^n3 (n3 = 0.19 in model BC) switches sign at the vertex, so the acceleration is
sharply peaked and lopsided there; the fitted curvature is 9 % (shallow contacts) to 25 %
(deep ones) too small, and the free-flight acceleration (forcing, up to +-3.4 m/s^2 against
contact curvatures of 1-80 m/s^2) is ignored.  Extrapolated to zero curvature, that puts x_impact
8-16 um low on the chaotic attractor even without noise.  A quartic over +-1.5 ms still
misses by 1-5 % (the damping's non-polynomial |v|^n3); shorter windows trade that for noise.

How (this module):

1. **Free-flight law.**  On samples whose +-10 ms neighbourhood stays ``margin`` + 5 sigma below a
   first guess of x_impact, the Savitzky-Golay acceleration (quartic over +-10 ms) is regressed
   on ``1, sin(w t), cos(w t), x, v, sign(v)``: a = a0 + F sin + G cos - w0^2 x - gamma v - mu sign(v),
   linear least squares over tens of thousands of samples (free flight is most of a record).
   w is the record's forcing frequency (estimated from the free-flight acceleration's
   periodogram when the record has none).
2. **Windows.**  Every turning point (maximum of the signal smoothed over +-``smooth``; a wide
   smoother so that the noise of the samples near the top hardly moves the window: centring
   on the raw or lightly smoothed maximum biases x_impact by -2 um at 5 um noise and -6 um at
   10 um) whose height is within ``band`` of the guess gives a window of +-``window`` s.
3. **Local model.**  In each window the motion is the solution of
   x'' = a_ff - gamma v - mu sign(v) - K max(0, h^1.5 (1 + b sign(v) |v|^n3)),  h = x - x_impact,
   with the turning point (H, v = 0) at time tau (a_ff: the free-flight law at the window's
   centre, H and tau: per-window unknowns; K = kI/m, b, n3, x_impact: shared).  It is integrated
   outward from the vertex (RK4, geometrically graded steps on the first two legs, where
   |v|^n3 is not smooth; 6 nm from the converged trajectory at 2 kHz).  This is the contact law
   of model BC with its constants free; a rig with another law (another exponent) would bias it.
4. **Fit.**  Least squares over all window samples (variable projection: for each trial of the
   shared constants, every window's H and tau are fitted by Levenberg-Marquardt, its Jacobian
   integrated with the trajectory: the tangent in H, -v in tau), the shared constants by
   ``scipy.optimize.least_squares`` with Kaufman's Jacobian of the projected residuals (each
   constant's forward difference at the windows' fitted H and tau, less what their own fit
   takes up: one integration per window and constant, where differences of the whole fit
   refit every window; 3x faster, and the same or a lower sum of squares).
5. **Uncertainty.**  sigma(x_impact) from the Jacobian of the projected residuals (the fit
   covariance, scaled by the residual variance).  Checked against the spread over noise seeds
   and record segments (tests/test_obstacle.py, docs/measured.md).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["fit_contact_law", "forcing_frequency", "free_flight_law", "model_window"]

# graded first legs: NGRADE steps growing by RATIO (first step span / 54)
_NGRADE = 8
_H0 = 1e-4  # m, reference penetration of the contact law with a fitted exponent
_H0_15 = _H0 * math.sqrt(_H0)
_RATIO = 1.6
#: difference step of the shared constants in the fit's variables (1e-11 m in x_impact, 1e-6
#: relative in K, 1e-6 in b, n3, n1): the window's integration is a smooth function of them
_JAC_STEP = 1e-6


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
def _window(H, tau, a, gam, mu, K, xi, b, n1, n3, half, dt, nsub, out, dH, dtau):
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
def _project(Y, a, gam, mu, K, xi, b, n1, n3, half, dt, nsub, H, tau, tau_max, max_iter, out):
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
        _window(h_, t_, a[j], gam, mu, K, xi, b, n1, n3, half, dt, nsub, f, fH, ft)
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
                _window(hc, tc, a[j], gam, mu, K, xi, b, n1, n3, half, dt, nsub, fc, cH, ct)
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
def _projected_jacobian(Y, a, gam, mu, consts, steps, half, dt, nsub, H, tau, tau_max, J):
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
        _window(H[j], tau[j], a[j], gam, mu, K, xi, b, n1, n3, half, dt, nsub, f, fH, ft)
        for i in range(P):
            Ki, xii, bi, n1i, n3i = consts[i + 1]
            _window(H[j], tau[j], a[j], gam, mu, Ki, xii, bi, n1i, n3i, half, dt, nsub, fi, scratch, scratch)
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
    _window(float(H), float(tau), *args, half, dt, nsub, out, d_h, d_tau)
    return out


def _savgol(x, dt, half_t, deg, deriv):
    from scipy.signal import savgol_filter

    hw = max(deg // 2 + 1, int(round(half_t / dt)))
    return savgol_filter(x, 2 * hw + 1, deg, deriv=deriv, delta=dt), hw


def forcing_frequency(t, a, mask, *, f_min=0.5, f_max=None) -> float:
    """Forcing frequency (rad/s) as the largest line of the free-flight acceleration a[mask].

    Periodogram of the acceleration with the masked-out samples (contacts) set to zero,
    zero-padded 4 times, between f_min and f_max Hz (default: a tenth of the sample rate),
    refined by least squares of a0 + F sin(w t) + G cos(w t) on the masked samples.
    """
    from scipy.optimize import minimize_scalar

    dt = float(t[1] - t[0])
    f_max = f_max or 0.1 / dt
    filled = np.where(mask, a - np.mean(a[mask]), 0.0)
    n = 4 * filled.size
    p = np.abs(np.fft.rfft(filled, n)) ** 2
    f = np.fft.rfftfreq(n, dt)
    band = (f >= f_min) & (f <= f_max)
    f0 = f[band][int(np.argmax(p[band]))]
    step = f[1] - f[0]
    tt, aa = t[mask], a[mask]

    def rss(w):
        B = np.column_stack([np.ones_like(tt), np.sin(w * tt), np.cos(w * tt)])
        return float(np.sum((aa - B @ np.linalg.lstsq(B, aa, rcond=None)[0]) ** 2))

    lo, hi = 2 * np.pi * (f0 - 2 * step), 2 * np.pi * (f0 + 2 * step)
    return float(minimize_scalar(rss, bounds=(lo, hi), method="bounded", options={"xatol": 1e-7}).x)


def free_flight_law(t, x, level, omega=None, *, window=10e-3, min_samples=200) -> dict:
    """Step 1: the free-flight acceleration law from samples staying below ``level`` (m).

    Returns a dict with ``omega`` (given or estimated), ``coef`` (a0, F, G, -w0^2, -gamma,
    -mu for the columns 1, sin w t, cos w t, x, v, sign v), ``n`` (samples used) and ``rms``
    (residual acceleration, m/s^2: noise of the Savitzky-Golay estimate plus unmodelled terms).
    """
    from scipy.ndimage import maximum_filter1d

    dt = float(t[1] - t[0])
    a, hw = _savgol(x, dt, window, 4, 2)
    v, _ = _savgol(x, dt, window, 4, 1)
    ok = maximum_filter1d(x, 2 * hw + 1, mode="nearest") < level
    ok[:hw] = False
    ok[x.size - hw :] = False
    if ok.sum() < min_samples:
        raise ValueError(
            f"only {int(ok.sum())} free-flight samples below {level:.6g} m; cannot fit the free-flight law"
        )
    estimated = omega is None
    if estimated:
        omega = forcing_frequency(t, a, ok)
    tt = t[ok]
    B = np.column_stack([np.ones_like(tt), np.sin(omega * tt), np.cos(omega * tt), x[ok], v[ok], np.sign(v[ok])])
    coef = np.linalg.lstsq(B, a[ok], rcond=None)[0]
    return {
        "omega": float(omega),
        "omega_estimated": estimated,
        "coef": coef,
        "n": int(ok.sum()),
        "rms": float(np.std(a[ok] - B @ coef)),
    }


def _windows(t, x, half, smooth, separation):
    """Indices of turning points (maxima of the signal smoothed over +-smooth) and their windows."""
    from scipy.ndimage import maximum_filter1d

    dt = float(t[1] - t[0])
    xs, _ = _savgol(x, dt, smooth, 2, 0)
    sep = max(1, int(round(separation / dt)))
    m = maximum_filter1d(xs, size=2 * sep + 1, mode="nearest")
    i = np.arange(x.size)
    idx = np.flatnonzero((xs == m) & (i >= max(sep, half)) & (i < x.size - max(sep, half)))
    return idx, x[idx[:, None] + np.arange(-half, half + 1)]


def fit_contact_law(
    t,
    x,
    guess,
    sigma,
    *,
    omega=None,
    K0=None,
    window=2.5e-3,
    smooth=5e-3,
    separation=5e-3,
    band=150e-6,
    margin=30e-6,
    n3=None,
    exponent=1.5,
    step=0.25e-3,
) -> dict:
    """Steps 1-5 of the module docstring.  Returns x_impact (m), its 1-sigma uncertainty and the fit.

    guess : first estimate of x_impact (m), e.g. the curvature estimator's; it sets the
        free-flight level (guess - margin - 5 sigma) and the windows kept (vertex above guess - band).
    sigma : sensor-noise std (m), the scale of the residuals.
    K0 : starting value of kI/m (m^-1/2 s^-2); None: 2.7e7 (model BC).
    n3 : damping exponent; None fits it (the default), a number fixes it.
    exponent : contact-force exponent n1 (1.5: Hertz, model BC's, the default); None fits it too
        (for a rig whose contact law is not known: the estimate then carries that uncertainty).
    step : longest RK4 step of the local model between samples, s (0.25 ms: 6 nm from the
        converged trajectory on model BC's contacts).
    """
    from scipy.optimize import least_squares

    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    dt = float(t[1] - t[0])
    half = max(3, int(round(window / dt)))
    nsub = max(1, math.ceil(dt / step - 1e-9))
    sigma = max(float(sigma), 1e-9)
    ff = free_flight_law(t, x, guess - margin - 5 * sigma, omega)
    a0, F, G, cx, gam, mu = ff["coef"]
    w = ff["omega"]
    idx, Y = _windows(t, x, half, smooth, separation)
    s = np.arange(-half, half + 1) * dt
    c = Y @ np.linalg.pinv(s[:, None] ** np.arange(3)).T
    # the vertex may lie up to tau_max from the smoothed maximum (the contact is lopsided: up to
    # about 0.5 ms here; a limit of +-2 samples at 5 kHz clipped a sixth of the windows and
    # biased x_impact by -2 um)
    tau_max = max(2 * dt, 0.4 * window)
    tau0 = np.clip(-c[:, 1] / (2 * np.where(c[:, 2] < 0, c[:, 2], -1e-12)), -tau_max, tau_max)
    H0 = c[:, 0] + c[:, 1] * tau0 + c[:, 2] * tau0**2
    keep = (H0 - guess) > -band
    idx, Y, H0, tau0 = idx[keep], Y[keep], H0[keep], tau0[keep]
    if idx.size < 10:
        raise ValueError(f"only {idx.size} turning points near the obstacle; cannot fit the contact law")
    tj = t[idx]
    # free-flight acceleration at each vertex (v = 0; the odd terms are in the local model)
    a = a0 + F * np.sin(w * tj) + G * np.cos(w * tj) + cx * H0
    gam, mu = -gam, -mu
    K0 = float(K0 or 2.7e7)
    lk0 = math.log(K0)
    fit_n3, fit_n1 = n3 is None, exponent is None
    out = np.empty_like(Y)
    H, tau = H0.copy(), tau0.copy()

    def unpack(u):
        rest = list(u[3:])
        nn = rest.pop(0) if fit_n3 else float(n3)
        e = rest.pop(0) if fit_n1 else float(exponent)
        return guess + 1e-5 * u[0], math.exp(lk0 + u[1]), u[2], e, nn

    fitted = {}  # the windows' H and tau of the last evaluation, for the Jacobian at the same u

    def residuals(u):
        xi, K, b, e, nn = unpack(u)
        Hj, tj_ = H.copy(), tau.copy()
        _project(Y, a, gam, mu, K, xi, b, e, nn, half, dt, nsub, Hj, tj_, tau_max, 50, out)
        fitted.update(u=u.copy(), H=Hj, tau=tj_)
        return out.ravel() / sigma

    def jacobian(u):
        if "u" not in fitted or not np.array_equal(fitted["u"], u):
            residuals(u)
        points = [u] + [u + _JAC_STEP * np.eye(u.size)[i] for i in range(u.size)]
        consts = np.array([(K, xi, b, e, nn) for xi, K, b, e, nn in map(unpack, points)])
        J = np.empty((Y.size, u.size))
        steps = np.full(u.size, _JAC_STEP)
        _projected_jacobian(Y, a, gam, mu, consts, steps, half, dt, nsub, fitted["H"], fitted["tau"], tau_max, J)
        return J / sigma

    u0 = np.array([0.0, 0.0, 0.5] + ([0.3] if fit_n3 else []) + ([1.5] if fit_n1 else []))
    # the exponent's box is extract.CONTACT_EXPONENT_RANGE (not imported: extract imports
    # obstacle_estimate, which loads this module lazily)
    lo = [-np.inf, -np.inf, 0.0] + ([0.02] if fit_n3 else []) + ([1.0] if fit_n1 else [])
    hi = [np.inf, np.inf, 20.0] + ([3.0] if fit_n3 else []) + ([2.5] if fit_n1 else [])
    # warm start of the per-window unknowns at the starting constants (every evaluation
    # starts from these, so the objective is a deterministic, smooth function of u)
    xi, K, b, e, nn = unpack(u0)
    _project(Y, a, gam, mu, K, xi, b, e, nn, half, dt, nsub, H, tau, tau_max, 50, out)
    r = least_squares(residuals, u0, jac=jacobian, bounds=(lo, hi), xtol=1e-10, ftol=1e-10, gtol=1e-10)
    xi, K, b, e, nn = unpack(r.x)
    n_par = r.x.size
    dof = max(r.fun.size - n_par - 2 * Y.shape[0], 1)
    s2 = float(r.fun @ r.fun) / dof
    cov = np.linalg.pinv(r.jac.T @ r.jac) * s2
    Hf, tf = H.copy(), tau.copy()
    _project(Y, a, gam, mu, K, xi, b, e, nn, half, dt, nsub, Hf, tf, tau_max, 50, out)
    return {
        "x_impact": float(xi),
        "sigma": float(1e-5 * math.sqrt(cov[0, 0])),
        "K": float(K),
        "K_rel_sigma": float(math.sqrt(cov[1, 1])),
        "b": float(b),
        "n3": float(nn),
        "n3_fitted": fit_n3,
        "exponent": float(e),
        "exponent_fitted": fit_n1,
        "exponent_sigma": float(math.sqrt(cov[-1, -1])) if fit_n1 else 0.0,
        "n_windows": int(Y.shape[0]),
        "n_contacts": int(np.sum(Hf > xi)),
        "window_samples": int(2 * half + 1),
        "at_tau_limit": int(np.sum(np.abs(tf) >= tau_max * (1 - 1e-9))),
        "chi2_dof": s2,
        "nfev": int(r.nfev),
        "free_flight": ff,
    }
