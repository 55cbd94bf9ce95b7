"""Impact times from a sampled record: the sub-sample time of each upward crossing of the
obstacle position, its stated uncertainty and its Cramer-Rao bound.

Why a module: the timing step sets the resolution of every statistic of a measured train, and its
bound is what the noise study scores extraction against.

Why a window in time, not a number of samples: a fit over a fixed number of samples has a bound
that does not fall with the sample rate (a faster card puts them closer together).  The bound of
a fit over a window of duration W falls like 1 / sqrt(W rate).  The window is limited by

* the approach: only the samples after the last turning point before the crossing (where the
  dry friction switches and the acceleration jumps), from where the signal has covered a quarter
  of its rise from that turning point to the obstacle (:func:`_approach_start`), and after the
  previous contact;
* the model error: a polynomial of degree d over W misses the motion's next derivative by a bias
  at the window's end of about x^(3) W^3 / 120 (quadratic) or x^(4) W^4 / 1680 (cubic).  W is the
  longest window whose bias is at most a quarter of the fit's noise, (d + 1) sigma / sqrt(W rate)
  (:func:`window_lengths`), with the record's derivative scales x^(3), x^(4) measured on its own
  approaches (:func:`derivative_scales`).

Per impact the degree (2 or 3) whose window gives the smaller variance at the crossing is fitted
by least squares to the samples ending at the crossing (found by iteration, the window moving
with it) and solved for x = x_impact by Newton's method.  sigma_t is the fit's delta-method std at
the crossing: the Cramer-Rao bound of the crossing time from those samples under the polynomial
model (:func:`crossing_time_crb`).  Only the free flight before the crossing enters: a rig's
contact law is not known when its impacts are timed.  Where the approach has too few samples (a
grazing contact, a chatter of impacts a few ms apart) or the fit has no crossing, the short
five-sample quadratic of :func:`short_crossings` times the impact, with a stated sigma_t that
covers its dwell near the obstacle.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.records.sample_fits import quadratic_fits

__all__ = [
    "crossing_time_crb",
    "derivative_scales",
    "window_lengths",
    "window_samples",
    "fit_crossings",
    "short_crossings",
    "time_impacts",
]

#: The bias allowed at the window's end, as a share of the fit's noise there.
BIAS_SHARE = 0.25
#: Fewest samples in a fit of degree 2 and of degree 3 (below: a lower degree or the short fit).
MIN_SAMPLES_QUADRATIC, MIN_SAMPLES_CUBIC = 4, 8
#: Longest window of any fit, and the one in which the derivative scales are measured (s).
PROBE_WINDOW = 0.05
#: A contact is grazing when its largest sample stays below x_impact + this many noise std
#: (a penetration of a few um: its force bends the motion by a fraction of the noise).
GRAZE_SIGMAS = 6.0
#: A turning point is passed (scanning back from a crossing) when the signal rises this many
#: noise std above its running minimum.
TURN_SIGMAS = 6.0
#: Share of the rise from the last turning point to the obstacle that the approach window leaves out.
APPROACH_SKIP = 0.25


def crossing_time_crb(sigma, v, u, n, degree=2):
    """Cramer-Rao bound (std, s) of a crossing time from a polynomial fit over n equally spaced samples.

    Model: the n free-flight samples before the crossing, equally spaced by dt, are a polynomial
    of degree d (2 or 3) in time plus white Gaussian noise of std sigma; the crossing time s*
    solves p(s*) = x_impact.  The model is linear in the coefficients, so its Fisher information
    is A^T A / sigma^2 (A: the design matrix) and, for any unbiased estimator of s*,

        var(s*) >= sigma^2 g^T (A^T A)^-1 g / v^2,   g = (1, s*, ..., s*^d),  v = p'(s*),

    which is also the delta-method variance of the least-squares root (so the fit attains the
    bound to first order in sigma / (v dt)).  In the discrete orthogonal (Gram) polynomials of
    n equally spaced samples, g^T (A^T A)^-1 g (the fitted curve's variance at s*, in units of
    sigma^2) is

        L(u, n) = 1/n + 12 u^2 / (n (n^2 - 1)) + 180 (u^2 - (n^2 - 1)/12)^2 / (n (n^2 - 1) (n^2 - 4))
                  [ + 2800 (u^3 - u (3 n^2 - 7)/20)^2 / (n (n^2 - 1) (n^2 - 4) (n^2 - 9))  for d = 3 ],

    u = (t* - mean of the fit's sample times) / dt, so  sigma_t >= sqrt(L(u, n)) sigma / |v|.  At
    the end of a long window L is about (d + 1)^2 / n: 9 / n for the quadratic, 16 / n for the
    cubic.  For the quadratic on n = 5 samples sqrt(L) runs from 0.94 to 2.14 as the crossing moves
    from the last sample (u = 2) to the next (u = 3).  Arrays broadcast.
    """
    L = _variance_factor(np.asarray(u, dtype=float), np.asarray(n, dtype=float), np.asarray(degree))
    return np.sqrt(L) * np.asarray(sigma, dtype=float) / np.abs(np.asarray(v, dtype=float))


def _variance_factor(u, n, degree):
    """L(u, n) of :func:`crossing_time_crb` (arrays broadcast)."""
    u2, n2 = u * u, n * n
    with np.errstate(divide="ignore", invalid="ignore"):
        L = 1 / n + 12 * u2 / (n * (n2 - 1)) + 180 * (u2 - (n2 - 1) / 12) ** 2 / (n * (n2 - 1) * (n2 - 4))
        cubic = 2800 * (u * u2 - u * (3 * n2 - 7) / 20) ** 2 / (n * (n2 - 1) * (n2 - 4) * (n2 - 9))
    return np.where(degree >= 3, L + np.where(degree >= 3, cubic, 0.0), L)


def window_lengths(sigma, rate, jerk, snap):
    """Longest windows (s) of the quadratic and the cubic fit whose bias at the crossing stays
    within :data:`BIAS_SHARE` of their noise (module docstring), from

        jerk W^3 / 120 = BIAS_SHARE 3 sigma / sqrt(W rate),   snap W^4 / 1680 = BIAS_SHARE 4 sigma / sqrt(W rate).

    jerk, snap: the record's third and fourth derivative scales (m/s^3, m/s^4); sigma (m),
    rate (Hz).  A scale that is not positive (or nan: not measured) gives no limit.
    """
    root = math.sqrt(rate)
    w2 = (120 * BIAS_SHARE * 3 * sigma / (jerk * root)) ** (1 / 3.5) if jerk > 0 else math.inf
    w3 = (1680 * BIAS_SHARE * 4 * sigma / (snap * root)) ** (1 / 4.5) if snap > 0 else math.inf
    return w2, w3


@njit(cache=True)
def _approach_start(x, i, floor, xi, rise):
    """First sample of the approach to the crossing after sample i: scanning back from i (not
    before ``floor``) past the last turning point (the signal rises ``rise`` above its running
    minimum), the first sample after the last one below a quarter of the rise to xi."""
    low, k_low, k = x[i], i, i
    while k > floor:
        k -= 1
        if x[k] < low:
            low, k_low = x[k], k
        elif x[k] > low + rise:
            break
    level = low + APPROACH_SKIP * (xi - low)
    k = i
    while k > k_low and x[k - 1] > level:
        k -= 1
    return max(k, floor)


@njit(cache=True)
def _solve(M, r):
    """Solution of the small symmetric positive-definite system M c = r (Gaussian elimination)."""
    n = r.size
    A, b = M.copy(), r.copy()
    for c in range(n):
        for row in range(c + 1, n):
            f = A[row, c] / A[c, c]
            for k in range(c, n):
                A[row, k] -= f * A[c, k]
            b[row] -= f * b[c]
    out = np.zeros(n)
    for c in range(n - 1, -1, -1):
        acc = b[c]
        for k in range(c + 1, n):
            acc -= A[c, k] * out[k]
        out[c] = acc / A[c, c]
    return out


@njit(cache=True)
def _poly_fit(t, x, k0, k1, d):
    """Least-squares polynomial of degree d through samples k0..k1 in s = (t - mid) / half.

    Returns (coefficients, normal matrix, mid, half)."""
    mid, half = 0.5 * (t[k0] + t[k1]), max(0.5 * (t[k1] - t[k0]), 1e-300)
    M, r, pw = np.zeros((d + 1, d + 1)), np.zeros(d + 1), np.empty(2 * d + 1)
    for k in range(k0, k1 + 1):
        s = (t[k] - mid) / half
        pw[0] = 1.0
        for j in range(1, 2 * d + 1):
            pw[j] = pw[j - 1] * s
        for a in range(d + 1):
            r[a] += pw[a] * x[k]
            for b in range(d + 1):
                M[a, b] += pw[a + b]
    return _solve(M, r), M, mid, half


@njit(cache=True)
def _poly(c, s):
    """p(s) and p'(s) of the coefficients c (lowest first)."""
    p, dp = 0.0, 0.0
    for j in range(c.size - 1, -1, -1):
        dp = dp * s + p
        p = p * s + c[j]
    return p, dp


@njit(cache=True)
def _root(c, xi, s0):
    """The upward root of p(s) = xi nearest s0 in [s0 - 0.5, s0 + 0.5] and p' there, or (nan, nan).

    Newton's method from s0 while p' > 0 along its path; else (a grazing crossing, where the
    path meets the vertex) the first upward sign change on a grid, refined by bisection."""
    s = s0
    for _ in range(40):
        p, dp = _poly(c, s)
        if not dp > 0:
            break
        step = (p - xi) / dp
        s -= step
        if abs(step) < 1e-13 * max(1.0, abs(s)):
            if abs(s - s0) <= 0.5:
                return s, dp
            break
    lo, f_lo = s0 - 0.5, _poly(c, s0 - 0.5)[0] - xi
    for k in range(1, 201):
        hi = s0 - 0.5 + k / 200.0
        f_hi = _poly(c, hi)[0] - xi
        if f_lo < 0 <= f_hi:
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                if _poly(c, mid)[0] - xi < 0:
                    lo = mid
                else:
                    hi = mid
            dp = _poly(c, hi)[1]
            return (hi, dp) if dp > 0 else (math.nan, math.nan)
        lo, f_lo = hi, f_hi
    return math.nan, math.nan


@njit(cache=True)
def _end_factor(n, d):
    """L of :func:`crossing_time_crb` half a sample after the last of n samples (the njit twin of
    :func:`_variance_factor`; a test checks that they agree)."""
    u = n / 2.0
    u2, n2 = u * u, float(n) * n
    L = 1 / n + 12 * u2 / (n * (n2 - 1)) + 180 * (u2 - (n2 - 1) / 12) ** 2 / (n * (n2 - 1) * (n2 - 4))
    if d >= 3:
        L += 2800 * (u * u2 - u * (3 * n2 - 7) / 20) ** 2 / (n * (n2 - 1) * (n2 - 4) * (n2 - 9))
    return L


@njit(cache=True)
def _last_at_or_before(t, k, tp):
    """Index of the last sample at or before time tp, searched from index k."""
    while k + 1 < t.size and t[k + 1] <= tp:
        k += 1
    while k > 0 and t[k] > tp:
        k -= 1
    return k


@njit(cache=True)
def _fit_one(t, x, i, ks, tp, xi, sigma, n_max2, n_max3):
    """The windowed fit of one crossing from the first estimate tp (the iteration of
    :func:`fit_crossings`): (t, v, sigma_t, first sample, samples, degree), degree 0 if none."""
    out = (math.nan, math.nan, math.nan, 0, 0, 0)
    for _ in range(4):
        ke = _last_at_or_before(t, i, tp)
        avail = ke - ks + 1
        n2, n3 = min(avail, n_max2), min(avail, n_max3)
        d, n = 0, 0
        if n2 >= MIN_SAMPLES_QUADRATIC:
            d, n = 2, n2
        if n3 >= MIN_SAMPLES_CUBIC and (d == 0 or _end_factor(n3, 3) < _end_factor(n2, 2)):
            d, n = 3, n3
        if d == 0:
            break
        k0 = ke - n + 1
        c, M, mid, half = _poly_fit(t, x, k0, ke, d)
        s, dp = _root(c, xi, (tp - mid) / half)
        if not abs(s - 1.0) < 0.5:  # no crossing near the window's end
            break
        g = np.empty(d + 1)
        g[0] = 1.0
        for j in range(1, d + 1):
            g[j] = g[j - 1] * s
        var = max(g @ _solve(M, g), 0.0)
        tp = mid + s * half
        out = (tp, dp / half, sigma * math.sqrt(var) * half / dp, k0, n, d)
    return out


@njit(cache=True)
def _fit_through(t, x, ks, ke, tp, xi, sigma, n_max2, n_max3):
    """One fit over samples ks..ke (at most the longest window, ending at ke) solved for the
    upward crossing of xi nearest tp inside it: the refit of a grazing contact."""
    avail = ke - ks + 1
    n2, n3 = min(avail, n_max2), min(avail, n_max3)
    d, n = 0, 0
    if n2 >= MIN_SAMPLES_QUADRATIC:
        d, n = 2, n2
    if n3 >= MIN_SAMPLES_CUBIC and (d == 0 or _end_factor(n3, 3) < _end_factor(n2, 2)):
        d, n = 3, n3
    if d == 0:
        return math.nan, math.nan, math.nan, 0, 0, 0
    k0 = ke - n + 1
    c, M, mid, half = _poly_fit(t, x, k0, ke, d)
    s, dp = _root(c, xi, (tp - mid) / half)
    if not abs(s) <= 1.0:
        return math.nan, math.nan, math.nan, 0, 0, 0
    g = np.empty(d + 1)
    g[0] = 1.0
    for j in range(1, d + 1):
        g[j] = g[j - 1] * s
    var = max(g @ _solve(M, g), 0.0)
    return mid + s * half, dp / half, sigma * math.sqrt(var) * half / dp, k0, n, d


@njit(cache=True)
def fit_crossings(t, x, onsets, floors, xi, sigma, n_max2, n_max3, peaks, ends, graze_level):
    """Crossing time, velocity and std of each onset (the last sample below xi before a crossing).

    floors: first sample each fit may use (after the previous contact).  n_max2, n_max3: most
    samples in the quadratic's and the cubic's window (:func:`window_lengths` times the rate).
    peaks, ends: each contact's largest sample and its end (the re-arming sample).  A grazing
    contact (its largest sample below ``graze_level``) whose crossing the approach alone does not
    reach (the fitted curve stays below xi: noise triggered the onset well before the slow
    crossing) is fitted again over the approach and the whole contact (:func:`_fit_through`):
    so shallow a contact barely bends the motion.
    Returns (t, v, sigma_t, first sample, samples, degree); degree 0 where no fit was found (the
    caller times those impacts otherwise).
    """
    m = onsets.size
    tc, vc, sc = np.full(m, np.nan), np.full(m, np.nan), np.full(m, np.nan)
    first, count, degree = np.zeros(m, np.int64), np.zeros(m, np.int64), np.zeros(m, np.int64)
    rise = TURN_SIGMAS * sigma
    for q in range(m):
        i = onsets[q]
        ks = _approach_start(x, i, floors[q], xi, rise)
        tp = t[i] + (t[i + 1] - t[i]) * (xi - x[i]) / (x[i + 1] - x[i])
        r = _fit_one(t, x, i, ks, tp, xi, sigma, n_max2, n_max3)
        if r[5] == 0 and ends[q] > i + 1 and x[peaks[q]] < graze_level:
            r = _fit_through(t, x, ks, ends[q] - 1, tp, xi, sigma, n_max2, n_max3)
        tc[q], vc[q], sc[q], first[q], count[q], degree[q] = r
    return tc, vc, sc, first, count, degree


@njit(cache=True)
def _last_below(x, ends, floors, level):
    """Index of the last sample at or below level up to each of ends (its floor if none)."""
    out = np.zeros(ends.size, np.int64)
    for q in range(ends.size):
        k = ends[q]
        while k > floors[q] and x[k] > level:
            k -= 1
        out[q] = k
    return out


@njit(cache=True)
def _top_coefficients(t, x, onsets, floors, xi, sigma, d, n_max):
    """The degree-d coefficient (in time units) of a fit over each approach, or nan."""
    out = np.full(onsets.size, np.nan)
    rise = TURN_SIGMAS * sigma
    for q in range(onsets.size):
        i = onsets[q]
        k0 = max(_approach_start(x, i, floors[q], xi, rise), i - n_max + 1)
        if i - k0 + 1 >= 3 * (d + 1):
            c, _M, _mid, half = _poly_fit(t, x, k0, i, d)
            out[q] = c[d] / half**d
    return out


def derivative_scales(t, x, onsets, floors, xi, sigma):
    """The record's third and fourth derivative scales on its approaches (m/s^3, m/s^4).

    The median magnitude of the top coefficient (times 3! and 4!) of cubic and quartic fits over
    each approach (at most :data:`PROBE_WINDOW`).  Noise inflates them, which only shortens the
    windows; nan with fewer than 5 usable approaches.
    """
    n_max = max(int(PROBE_WINDOW / (t[1] - t[0])), 1)
    out = []
    for d, factorial in ((3, 6.0), (4, 24.0)):
        c = _top_coefficients(t, x, onsets, floors, xi, sigma, d, n_max)
        c = np.abs(c[np.isfinite(c)])
        out.append(float(factorial * np.median(c)) if c.size >= 5 else math.nan)
    return tuple(out)


def short_crossings(t, x, i, xi, n, sigma, floors=None):
    """Sub-sample times, velocities, sigma_t and Cramer-Rao bounds of the upward crossings
    between samples i and i+1 (i: the onsets in order; each fit ends at i).

    Fitted root: real roots in (-dt, 2 dt) with positive slope, the one closest to the linear
    interpolation; without such a root (or with fewer than 3 samples) the linear
    interpolation itself.  The bound (:func:`crossing_time_crb`, the fit's delta-method std
    before the dwell-band floor below) is nan where the linear interpolation is used.  floors:
    the first sample the dwell may reach back to (default: the record's start).
    """
    dt = t[i + 1] - t[i]
    lin = t[i] + dt * (xi - x[i]) / (x[i + 1] - x[i])
    v_lin = (x[i + 1] - x[i]) / dt
    st = np.divide(sigma, np.abs(v_lin), out=dt.copy(), where=v_lin != 0)
    tc, v = lin.copy(), v_lin.copy()
    f = np.flatnonzero(i >= 2)  # at least 3 samples in the fit window
    fi = i[f]
    c, cov = quadratic_fits(t, x, np.maximum(0, fi - n + 1), fi + 1, t[fi])
    a, b, cc = c[:, 2], c[:, 1], c[:, 0] - xi
    # both roots in the numerically stable form (no cancellation in b +- sqrt(disc); q = 0
    # only for the double root 0); a == 0 leaves the linear root
    disc = b * b - 4 * a * cc
    real = (disc >= 0) | (a == 0)
    q = -0.5 * (b + np.copysign(np.sqrt(np.where(real, disc, 0.0)), b))
    with np.errstate(divide="ignore", invalid="ignore"):
        roots = np.where(
            (a == 0)[:, None],
            (-cc / b)[:, None],
            np.stack([q / a, np.where(q != 0, cc / q, 0.0)], axis=1),
        )
    slope = b[:, None] + 2 * a[:, None] * roots
    ok = real[:, None] & (roots > -dt[f, None]) & (roots < 2 * dt[f, None]) & (slope > 0)
    dist = np.where(ok, np.abs(roots - (lin[f] - t[fi])[:, None]), np.inf)
    pick = np.argmin(dist, axis=1)
    has = ok.any(axis=1)
    f, fi, s, vf = f[has], fi[has], roots[has, pick[has]], slope[has, pick[has]]
    g = np.stack([np.ones_like(s), s, s * s], axis=1)
    var = np.einsum("mj,mj->m", np.einsum("mi,mij->mj", g, cov[has]), g)
    stf = sigma * np.sqrt(np.maximum(var, 0.0)) / vf
    crb = np.full(i.size, np.nan)
    crb[f] = stf
    tc[f], v[f], st[f] = t[fi] + s, vf, stf
    # the crossing is only known to within the time the signal dwelt within 3 sigma below
    # x_impact before it (a slow, grazing approach, or a contact sample pushed down by noise):
    # back to the last sample below that band (or the record start)
    floors = np.zeros(i.size, np.int64) if floors is None else np.asarray(floors, dtype=np.int64)
    st = np.maximum(np.abs(st), t[i + 1] - t[_last_below(x, i, floors, xi - 3 * sigma)])
    return tc, v, st, np.abs(crb)


def _keep_order(tc, v, st, crb, t, x, i, xi, after=-math.inf):
    """Times of adjacent crossings can overlap (only without hysteresis, where every noise
    crossing is one, and fits of neighbouring onsets find the same crossing): both of an
    overlapping pair take the linear interpolation inside their own [t_i, t_i+1], until the
    times increase (they do once all are interpolated: the onsets are distinct samples).
    ``after``: the time of the impact before the first (of the previous chunk), which stays."""
    dt = t[i + 1] - t[i]
    lin = np.concatenate([[after], t[i] + dt * (xi - x[i]) / (x[i + 1] - x[i])])
    out = np.concatenate([[after], tc])
    overlap = np.zeros(i.size + 1, bool)
    while True:
        bad = np.flatnonzero(out[1:] <= out[:-1])
        if not bad.size:
            break
        overlap[bad] = overlap[bad + 1] = True
        overlap[0] = False
        out[overlap] = lin[overlap]
    out, overlap = out[1:], overlap[1:]
    return (
        out,
        np.where(overlap, (x[i + 1] - x[i]) / dt, v),
        np.where(overlap, np.maximum(st, dt), st),
        np.where(overlap, np.nan, crb),
        overlap,
    )


def window_samples(sigma, rate, scales, window=None):
    """Most samples in the quadratic's and the cubic's window: :func:`window_lengths` (or the
    fixed ``window``, s), at most :data:`PROBE_WINDOW`, times the rate."""
    w2, w3 = (window, window) if window is not None else window_lengths(sigma, rate, *scales)
    return tuple(max(int(min(w, PROBE_WINDOW) * rate), 1) for w in (w2, w3))


def time_impacts(t, x, onsets, floors, xi, sigma, *, windows, peaks=None, ends=None, short_points=5, after=-math.inf):
    """Times of the impacts at ``onsets``: the windowed fits of :func:`fit_crossings`, the short
    fit where those find none.

    floors: the first sample each impact's fits may use (after the previous contact, and at
    most the longest window back: what makes a record cut in chunks give the same times).
    windows: (n_max2, n_max3) from :func:`window_samples`.  peaks, ends: each contact's largest
    sample and its end (for the refit of grazing contacts, :func:`fit_crossings`; None: no
    refit).  Returns a dict of arrays: ``t``,
    ``v``, ``sigma_t``, ``crb_t`` (the fit's std at the crossing, before the short fit's dwell
    floor), ``fit_start`` (time of the fit's first sample), ``fit_samples`` and ``fit_degree``;
    the times increase, and follow ``after`` (the last impact timed before these).
    """
    onsets, floors = np.asarray(onsets, dtype=np.int64), np.asarray(floors, dtype=np.int64)
    if peaks is None or ends is None:
        peaks, ends = onsets, onsets  # no refit
    peaks, ends = np.asarray(peaks, dtype=np.int64), np.asarray(ends, dtype=np.int64)
    graze = xi + GRAZE_SIGMAS * sigma
    tc, vc, sc, first, count, degree = fit_crossings(t, x, onsets, floors, xi, sigma, *windows, peaks, ends, graze)
    crb = sc.copy()
    short = np.flatnonzero(degree == 0)
    if short.size:
        i = onsets[short]
        tc[short], vc[short], sc[short], crb[short] = short_crossings(t, x, i, xi, short_points, sigma, floors[short])
        first[short] = np.maximum(i - short_points + 1, 0)
        count[short] = i - first[short] + 1
        degree[short] = 2
    tc, vc, sc, crb, overlap = _keep_order(tc, vc, sc, crb, t, x, onsets, xi, after)
    count[overlap], degree[overlap], first[overlap] = 2, 1, onsets[overlap]
    return {
        "t": tc,
        "v": vc,
        "sigma_t": sc,
        "crb_t": crb,
        "fit_start": t[first] if t.size else np.empty(0),
        "fit_samples": count,
        "fit_degree": degree,
    }
