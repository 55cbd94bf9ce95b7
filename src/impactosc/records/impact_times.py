"""Impact times from a sampled record: the sub-sample time of each upward crossing of the
obstacle position, its stated uncertainty and its Cramer-Rao bound.

Why a module: the timing step is the part of extraction whose accuracy sets the statistics'
resolution (see :mod:`impactosc.records.extract` for the whole method), and its bound is what
the noise study scores the extraction against.
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.records.sample_fits import quadratic_fits

__all__ = ["crossing_time_crb"]


def crossing_time_crb(sigma, v, u, n):
    """Cramer-Rao bound (std, s) of the crossing time from the quadratic fit of the timing step.

    Model: the n free-flight samples before the crossing, equally spaced by dt, are
    x_k = c0 + c1 s_k + c2 s_k^2 + e_k with white Gaussian noise e_k of std sigma.  The crossing
    time s* solves c0 + c1 s* + c2 s*^2 = x_impact.  The model is linear in c, so its Fisher
    information is A^T A / sigma^2 (A: the design matrix) and, for any unbiased estimator of s*,

        var(s*) >= sigma^2 g^T (A^T A)^-1 g / v^2,   g = (1, s*, s*^2),  v = c1 + 2 c2 s*,

    which is also the delta-method variance of the least-squares root (so the fit attains the
    bound to first order in sigma / (v dt)).  With orthogonal polynomials on n equally spaced
    samples, g^T (A^T A)^-1 g (the fitted curve's variance at s*, in units of sigma^2) is

        L(u, n) = 1/n + 12 u^2 / (n (n^2 - 1)) + 180 (u^2 - (n^2 - 1)/12)^2 / (n (n^2 - 1) (n^2 - 4)),

    u = (t* - mean of the fit's sample times) / dt, so  sigma_t >= sqrt(L(u, n)) sigma / |v|.
    The crossing lies between the last fit sample (u = (n-1)/2) and the next (u = (n+1)/2):
    for the default n = 5, sqrt(L) runs from 0.94 to 2.14 (1.45 at mid-interval).  For a
    fixed n the bound does not depend on the sample rate (a faster card puts the n samples
    closer together); it scales as the noise over the impact velocity.  Arrays broadcast.
    """
    n = np.asarray(n, dtype=float)
    u2 = np.asarray(u, dtype=float) ** 2
    L = 1 / n + 12 * u2 / (n * (n * n - 1)) + 180 * (u2 - (n * n - 1) / 12) ** 2 / (n * (n * n - 1) * (n * n - 4))
    return np.sqrt(L) * np.asarray(sigma, dtype=float) / np.abs(np.asarray(v, dtype=float))


def _crossings(t, x, i, xi, n, sigma):
    """Sub-sample times, velocities, sigma_t and Cramer-Rao bounds of the upward crossings
    between samples i and i+1 (i: the onsets in order; each fit ends at i).

    Fitted root: real roots in (-dt, 2 dt) with positive slope, the one closest to the linear
    interpolation; without such a root (or with fewer than 3 samples) the linear
    interpolation itself.  The bound (:func:`crossing_time_crb`, the fit's delta-method std
    before the dwell-band floor below) is nan where the linear interpolation is used.
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
    # the signal dwells within 3 sigma below x_impact before the crossing (a slow, grazing
    # approach, or a contact sample pushed down by noise): the crossing is only known to
    # within that dwell time, back to the last sample below the band (or the record start)
    below = np.flatnonzero(x <= xi - 3 * sigma)
    last = np.searchsorted(below, fi, side="right") - 1
    k0 = np.where(last >= 0, below[np.maximum(last, 0)], 0)
    stf = np.where(x[fi] > xi - 3 * sigma, np.maximum(stf, t[fi + 1] - t[k0]), stf)
    tc[f], v[f], st[f] = t[fi] + s, vf, stf
    # fitted roots of adjacent crossings can overlap (only without hysteresis): keep the
    # order with the linear interpolation inside [t_i, t_i+1] (sequential: each onset is
    # compared with the previous one's final time)
    overlap = np.zeros(i.size, bool)
    prev = -math.inf
    for k, tk in enumerate(tc.tolist()):
        overlap[k] = tk <= prev
        prev = float(lin[k]) if overlap[k] else tk
    st = np.abs(st)
    return (
        np.where(overlap, lin, tc),
        np.where(overlap, v_lin, v),
        np.where(overlap, np.maximum(st, dt), st),
        np.where(overlap, np.nan, np.abs(crb)),
    )
