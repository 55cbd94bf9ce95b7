"""Obstacle position from a sampled record: the contact law fitted to the samples around each turning point.

Why not the curvature of the turning points alone (:func:`impactosc.records.obstacle_estimate.estimate_x_impact`
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

from impactosc.records.contact_window import fit_vertices, projected_jacobian

__all__ = ["fit_contact_law", "forcing_frequency", "free_flight_law"]

#: difference step of the shared constants in the fit's variables (1e-11 m in x_impact, 1e-6
#: relative in K, 1e-6 in b, n3, n1): the window's integration is a smooth function of them
_JAC_STEP = 1e-6


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


class _Projected:
    """The residuals (Y - f) / sigma as a function of the shared constants' variables u, every
    window's H and tau fitted at each u from the same warm start (H, tau), and their Jacobian
    (:func:`projected_jacobian`, at the H and tau of the last evaluation at that u)."""

    def __init__(self, Y, a, gam, mu, grid, tau_max, sigma, unpack, H, tau):
        self.Y, self.a, self.gam, self.mu = Y, a, gam, mu
        self.grid, self.tau_max, self.sigma, self.unpack = grid, tau_max, sigma, unpack
        self.H, self.tau = H.copy(), tau.copy()
        self.last = None

    def vertices(self, u):
        """(Y - f, H, tau) with every window's vertex fitted at the constants of u."""
        xi, K, b, e, nn = self.unpack(u)
        H, tau, out = self.H.copy(), self.tau.copy(), np.empty_like(self.Y)
        fit_vertices(self.Y, self.a, self.gam, self.mu, K, xi, b, e, nn, *self.grid, H, tau, self.tau_max, 50, out)
        return out, H, tau

    def residuals(self, u):
        out, H, tau = self.vertices(u)
        self.last = (u.copy(), H, tau)
        return out.ravel() / self.sigma

    def jacobian(self, u):
        if self.last is None or not np.array_equal(self.last[0], u):
            self.residuals(u)
        _, H, tau = self.last
        points = [u] + [u + _JAC_STEP * np.eye(u.size)[i] for i in range(u.size)]
        consts = np.array([(K, xi, b, e, nn) for xi, K, b, e, nn in map(self.unpack, points)])
        J = np.empty((self.Y.size, u.size))
        steps = np.full(u.size, _JAC_STEP)
        projected_jacobian(self.Y, self.a, self.gam, self.mu, consts, steps, *self.grid, H, tau, self.tau_max, J)
        return J / self.sigma


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
    K0 = float(K0 or 2.7e7)
    lk0 = math.log(K0)
    fit_n3, fit_n1 = n3 is None, exponent is None

    def unpack(u):  # the fit's variables -> (x_impact, K, b, n1, n3)
        rest = list(u[3:])
        nn = rest.pop(0) if fit_n3 else float(n3)
        e = rest.pop(0) if fit_n1 else float(exponent)
        return guess + 1e-5 * u[0], math.exp(lk0 + u[1]), u[2], e, nn

    u0 = np.array([0.0, 0.0, 0.5] + ([0.3] if fit_n3 else []) + ([1.5] if fit_n1 else []))
    # the exponent's box is extract.CONTACT_EXPONENT_RANGE (not imported: extract imports
    # obstacle_estimate, which loads this module lazily)
    lo = [-np.inf, -np.inf, 0.0] + ([0.02] if fit_n3 else []) + ([1.0] if fit_n1 else [])
    hi = [np.inf, np.inf, 20.0] + ([3.0] if fit_n3 else []) + ([2.5] if fit_n1 else [])
    obj = _Projected(Y, a, -gam, -mu, (half, dt, nsub), tau_max, sigma, unpack, H0, tau0)
    # warm start of the per-window unknowns at the starting constants (every evaluation
    # starts from these, so the objective is a deterministic, smooth function of u)
    _, obj.H, obj.tau = obj.vertices(u0)
    r = least_squares(obj.residuals, u0, jac=obj.jacobian, bounds=(lo, hi), xtol=1e-10, ftol=1e-10, gtol=1e-10)
    xi, K, b, e, nn = unpack(r.x)
    n_par = r.x.size
    dof = max(r.fun.size - n_par - 2 * Y.shape[0], 1)
    s2 = float(r.fun @ r.fun) / dof
    cov = np.linalg.pinv(r.jac.T @ r.jac) * s2
    _, Hf, tf = obj.vertices(r.x)
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
