"""The arithmetic of a mixture's components: their moments, and the log-densities and
responsibilities of EM's E-step, in two compiled kernels.

EM's arithmetic lives in two compiled kernels, with numpy's exp and log between them.  They
evaluate every expression operation for operation, and add every sum in the order, of the
numpy code they replaced (over the sample in sample order, over components in component
order), so log-likelihoods keep every bit.  That matters: restarts that reach the same
maximum differ only in the last bits of their log-likelihoods, and those bits decide which
restart, with which parameters, EM returns.  Components are rows of (K, n) arrays; the
kernels write into arrays passed in (they compile faster than ones that allocate).

Why a module: a fitted mixture's density (:class:`impactosc.statistics.mixture.MixtureFit`)
and the EM iterations (:mod:`impactosc.statistics.mixture_em`) evaluate the same
components; the parameterisation is in :mod:`impactosc.statistics.mixture`.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy import special

__all__ = ["component_moments", "shifted_log_joint", "responsibility_moments"]

_LOG_2PI = np.log(2 * np.pi)
_CODE = {"gaussian": 0, "lognormal": 1, "gamma": 2}  # family as the compiled kernel sees it


def component_moments(family: str, p: dict) -> tuple[np.ndarray, np.ndarray]:
    """Component means and variances."""
    if family == "gaussian":
        return p["mu"].copy(), p["sigma"] ** 2
    if family == "lognormal":
        mu, s2 = p["mu"], p["sigma"] ** 2
        mean = np.exp(mu + s2 / 2)
        return mean, np.expm1(s2) * mean**2
    a, th = p["shape"], p["scale"]
    return a * th, a * th**2


def shifted_log_joint(family: str, x: np.ndarray, y: np.ndarray, w: np.ndarray, p: dict):
    """``log(w_k f_k(x_i)) - top_i`` with ``top_i = max_k log(w_k f_k(x_i))``, for the exp of the E-step.

    ``y`` is ``log x`` (``x`` itself for gaussian).  Returns ``(out, top, arg)``: ``out``
    (K, n) holds in its first K - 1 rows the values of every component but the top one,
    ``arg``; the top one's value, ``top - top`` (0, whose exp is 1, unless top is not
    finite), is left out so that numpy's exp runs on ``out[:-1]`` only.
    :func:`responsibility_moments` puts the rows back in order.
    """
    if family == "gamma":
        a, th = p["shape"], p["scale"]
        c = (a - 1, th, special.gammaln(a), a * np.log(th))
    else:
        s = p["sigma"]
        c = (-0.5 * _LOG_2PI - np.log(s), p["mu"], s, s)  # the last is unused
    out, top, arg = np.empty((w.size, x.size)), np.empty(x.size), np.empty(x.size, dtype=np.int64)
    _shifted_log_joint_kernel(_CODE[family], x, y, *c, np.log(w), out, top, arg)
    return out, top, arg


@njit(cache=True, error_model="numpy")
def _shifted_log_joint_kernel(code, x, y, c0, c1, c2, c3, log_w, out, top, arg):
    """Fill ``out``, ``top`` and ``arg`` for :func:`shifted_log_joint`."""
    k_count, n = out.shape
    for k in range(k_count):
        row = out[k]
        # scalars, not array loads, inside the loops: lets LLVM vectorise them
        u0, u1, u2, u3, lw = c0[k], c1[k], c2[k], c3[k], log_w[k]
        if code == 2:  # gamma: (a - 1) log x - x / scale - gammaln(a) - a log(scale)
            for i in range(n):
                row[i] = u0 * y[i] - x[i] / u1 - u2 - u3 + lw
        elif code == 1:  # lognormal: -log(2 pi)/2 - log(sigma) - log x - ((log x - mu) / sigma)^2 / 2
            for i in range(n):
                z = (y[i] - u1) / u2
                row[i] = u0 - y[i] - 0.5 * (z * z) + lw
        else:  # gaussian: -log(2 pi)/2 - log(sigma) - ((x - mu) / sigma)^2 / 2
            for i in range(n):
                z = (y[i] - u1) / u2
                row[i] = u0 - 0.5 * (z * z) + lw
    for i in range(n):
        top[i], arg[i] = out[0, i], 0
    for k in range(1, k_count):
        for i in range(n):
            if out[k, i] > top[i] or out[k, i] != out[k, i]:  # nan wins, as in numpy's max
                top[i], arg[i] = out[k, i], k
    for k in range(k_count):
        for i in range(n):
            out[k, i] -= top[i]
    last = k_count - 1
    for i in range(n):  # the last row's value takes the top one's place
        out[arg[i], i] = out[last, i]


def responsibility_moments(
    e: np.ndarray, top: np.ndarray, arg: np.ndarray, x: np.ndarray, y: np.ndarray, with_var: bool
):
    """Responsibilities from the exp of :func:`shifted_log_joint`'s ``out[:-1]``, and their moments.

    Puts the rows of ``e`` (K, n) back in order (``top - top`` for the top component,
    whose exp is 1, or nan) and normalises its columns to responsibilities ``r``, in
    place.  Returns the column sums and a (4, K) array of what the M-step needs: the total
    responsibility ``nk`` of each component, the ``r``-weighted means of x and y and, if
    ``with_var``, the variance of y (nk = 0 gives inf or nan, not an exception).
    """
    tot, m = np.empty(x.size), np.empty((4, e.shape[0]))
    _responsibility_moments_kernel(e, top, arg, x, y, with_var, tot, m)
    return tot, m


@njit(cache=True, error_model="numpy")
def _responsibility_moments_kernel(e, top, arg, x, y, with_var, tot, m):
    """Fill ``e``, ``tot`` and ``m`` for :func:`responsibility_moments`."""
    k_count, n = e.shape
    last = k_count - 1
    for i in range(n):
        e[last, i] = e[arg[i], i]
        e[arg[i], i] = 1.0 + (top[i] - top[i])
    for i in range(n):
        tot[i] = e[0, i]
    for k in range(1, k_count):
        for i in range(n):
            tot[i] += e[k, i]
    for k in range(k_count):
        r = e[k]
        for i in range(n):
            r[i] /= tot[i]
        nk, sx, sy = r[0], r[0] * x[0], r[0] * y[0]
        for i in range(1, n):
            nk += r[i]
            sx += r[i] * x[i]
            sy += r[i] * y[i]
        mean_y = sy / nk
        m[0, k], m[1, k], m[2, k] = nk, sx / nk, mean_y
        m[3, k] = np.nan
        if with_var:
            d = y[0] - mean_y
            sv = r[0] * (d * d)
            for i in range(1, n):
                d = y[i] - mean_y
                sv += r[i] * (d * d)
            m[3, k] = sv / nk
