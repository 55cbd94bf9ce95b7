"""Finite mixture models for interval distributions, fitted by maximum likelihood (EM).

The paper finds the chaotic ISI histogram bimodal and leaves its approximation open;
here one- and two-component mixtures of Gaussian, lognormal and gamma densities are
fitted by expectation-maximisation and ranked by BIC, so "bimodal" becomes a model
comparison rather than a visual impression.

Parameterisation (per component j, weight ``w_j``):

* ``gaussian``  -- ``mu`` (mean), ``sigma`` (standard deviation); units of the data.
* ``lognormal`` -- ``mu``, ``sigma`` of ``log x`` (x in the data's units, e.g. s).
* ``gamma``     -- ``shape`` (dimensionless), ``scale`` (units of the data).

Likelihood degeneracies (a component collapsing onto a single point) are prevented by a
floor on each component's spread of 1e-3 times the spread of the whole sample.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy import special

from ._validation import as_finite_1d, as_positive_1d

__all__ = ["FAMILIES", "MixtureFit", "MixtureSelection", "fit_mixture", "select_mixture"]

FAMILIES = ("gaussian", "lognormal", "gamma")
_SPREAD_FLOOR = 1e-3
_SHORT_RUN = 30  # EM iterations every start gets before the ranking
_N_FINISH = 2  # best starts that are run to convergence
_LOG_2PI = np.log(2 * np.pi)
_CODE = {"gaussian": 0, "lognormal": 1, "gamma": 2}  # family as the compiled kernel sees it


@dataclass(frozen=True)
class MixtureFit:
    """Maximum-likelihood mixture fit.

    Attributes
    ----------
    family : str
        One of ``FAMILIES``.
    weights : ndarray, shape (K,)
        Mixing weights, summing to 1; components are ordered by increasing mean.
    params : dict of str -> ndarray, shape (K,)
        Family parameters (see module docstring).
    loglik : float
        Maximised log-likelihood.
    n_obs : int
        Sample size.
    converged : bool
        Whether EM met its tolerance before ``max_iter``.
    n_iter : int
        EM iterations of the best restart.
    """

    family: str
    weights: np.ndarray
    params: dict
    loglik: float
    n_obs: int
    converged: bool
    n_iter: int

    @property
    def n_components(self) -> int:
        return int(self.weights.size)

    @property
    def n_params(self) -> int:
        """Free parameters: 2 per component plus K - 1 weights."""
        return 3 * self.n_components - 1

    @property
    def aic(self) -> float:
        """Akaike information criterion ``2 p - 2 logL``."""
        return 2 * self.n_params - 2 * self.loglik

    @property
    def bic(self) -> float:
        """Bayesian information criterion ``p ln n - 2 logL`` (lower is better)."""
        return self.n_params * np.log(self.n_obs) - 2 * self.loglik

    @property
    def means(self) -> np.ndarray:
        """Component means (units of the data)."""
        return _moments(self.family, self.params)[0]

    @property
    def stds(self) -> np.ndarray:
        """Component standard deviations (units of the data)."""
        return np.sqrt(_moments(self.family, self.params)[1])

    @property
    def modes(self) -> np.ndarray:
        """Component modes (units of the data); 0 for a gamma with shape <= 1."""
        p = self.params
        if self.family == "gaussian":
            return p["mu"].copy()
        if self.family == "lognormal":
            return np.exp(p["mu"] - p["sigma"] ** 2)
        return np.maximum(p["shape"] - 1.0, 0.0) * p["scale"]

    def pdf(self, x) -> np.ndarray:
        """Mixture density at ``x`` (1/units of the data); zero outside the support."""
        x = np.asarray(x, dtype=float)
        out = np.zeros(x.shape)
        ok = np.isfinite(x) & ((x > 0) if self.family != "gaussian" else True)
        if np.any(ok):
            v = x[ok].ravel()
            y = v if self.family == "gaussian" else np.log(v)
            e, top, _ = _shifted_log_joint(self.family, v, y, self.weights, self.params)
            out[ok] = np.exp(top) * (1.0 + np.exp(e[:-1]).sum(axis=0))  # 1: the top component's term
        return out

    def summary(self) -> str:
        """One line: family, K, weights, means, BIC."""
        w = ", ".join(f"{v:.3f}" for v in self.weights)
        m = ", ".join(f"{v:.4g}" for v in self.means)
        return (
            f"{self.family} x{self.n_components}: weights [{w}], means [{m}], "
            f"logL={self.loglik:.2f}, BIC={self.bic:.2f}"
        )


def _moments(family: str, p: dict) -> tuple[np.ndarray, np.ndarray]:
    """Component means and variances."""
    if family == "gaussian":
        return p["mu"].copy(), p["sigma"] ** 2
    if family == "lognormal":
        mu, s2 = p["mu"], p["sigma"] ** 2
        mean = np.exp(mu + s2 / 2)
        return mean, np.expm1(s2) * mean**2
    a, th = p["shape"], p["scale"]
    return a * th, a * th**2


# EM's arithmetic lives in two compiled kernels, with numpy's exp and log between them.  They
# evaluate every expression operation for operation, and add every sum in the order, of the
# numpy code they replaced (over the sample in sample order, over components in component
# order), so log-likelihoods keep every bit.  That matters: restarts that reach the same
# maximum differ only in the last bits of their log-likelihoods, and those bits decide which
# restart, with which parameters, EM returns.  Components are rows of (K, n) arrays; the
# kernels write into arrays passed in (they compile faster than ones that allocate).


def _shifted_log_joint(family: str, x: np.ndarray, y: np.ndarray, w: np.ndarray, p: dict):
    """``log(w_k f_k(x_i)) - top_i`` with ``top_i = max_k log(w_k f_k(x_i))``, for the exp of the E-step.

    ``y`` is ``log x`` (``x`` itself for gaussian).  Returns ``(out, top, arg)``: ``out``
    (K, n) holds in its first K - 1 rows the values of every component but the top one,
    ``arg``; the top one's value, ``top - top`` (0, whose exp is 1, unless top is not
    finite), is left out so that numpy's exp runs on ``out[:-1]`` only.
    :func:`_responsibility_moments` puts the rows back in order.
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
    """Fill ``out``, ``top`` and ``arg`` for :func:`_shifted_log_joint`."""
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


def _responsibility_moments(
    e: np.ndarray, top: np.ndarray, arg: np.ndarray, x: np.ndarray, y: np.ndarray, with_var: bool
):
    """Responsibilities from the exp of :func:`_shifted_log_joint`'s ``out[:-1]``, and their moments.

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
    """Fill ``e``, ``tot`` and ``m`` for :func:`_responsibility_moments`."""
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


def _gamma_shape(log_mean: np.ndarray, mean_log: np.ndarray, shape_max: float) -> np.ndarray:
    """Solve ``log a - digamma(a) = log_mean - mean_log`` for the gamma shape a.

    Minka's (2002) closed-form start and generalised Newton iterations; converges in a
    handful of steps for any s > 0.  Between the ufunc calls (log, digamma, trigamma) the K
    shapes are Python floats, whose arithmetic rounds as numpy's does: on arrays of one to
    three elements numpy's per-call overhead cost more than the arithmetic.  For large
    shapes rounding can make the iterates alternate between two neighbouring values that
    never meet the tolerance; the remaining iterations are then skipped, ending on the value
    the 20th would give.
    """
    s = np.maximum(log_mean - mean_log, 1.0 / (2 * shape_max))
    a = (3 - s + np.sqrt((s - 3) ** 2 + 24 * s)) / (12 * s)
    s, a, a_old = s.tolist(), a.tolist(), None
    for it in range(20):
        arr = np.array(a)
        # zeta(2, a) is the trigamma function: what polygamma(1, a) returns, without its overhead
        funcs = zip(np.log(arr).tolist(), special.digamma(arr).tolist(), special.zeta(2.0, arr).tolist())
        a_new = []
        for ak, sk, (log_a, psi, trigamma) in zip(a, s, funcs):
            inv = 1.0 / ak
            v = 1.0 / (inv + (log_a - psi - sk) / (ak * ak * (inv - trigamma)))
            a_new.append(v if v > 0 else ak / 2)
        if all(abs(v - ak) <= 1e-12 * ak for v, ak in zip(a_new, a)):
            a = a_new
            break
        if a_old is not None and all(v == v_old for v, v_old in zip(a_new, a_old)):
            # a 2-cycle: the tolerance tests repeat too, so the 20th iterate is known
            a = a_new if (19 - it) % 2 == 0 else a
            break
        a_old, a = a, a_new
    return np.minimum(np.array(a), shape_max)


class _Family:
    """M-step and starting values for one family, with spread floors from the whole sample."""

    def __init__(self, family: str, x: np.ndarray):
        self.family = family
        self.x = np.array(x, dtype=float)  # C-contiguous and writable: the kernels' one compiled signature
        self.y = np.log(self.x) if family != "gaussian" else self.x  # scale the floors live on
        spread = max(float(np.std(self.y)), 1e-12 * max(float(np.abs(self.y).max()), 1.0))
        self.sigma_min = _SPREAD_FLOOR * spread
        cv = float(np.std(x) / np.mean(x)) if family == "gamma" else 1.0
        self.shape_max = 1.0 / max(_SPREAD_FLOOR * cv, 1e-6) ** 2

    def shifted_log_joint(self, w: np.ndarray, p: dict):
        """:func:`_shifted_log_joint` of the sample."""
        return _shifted_log_joint(self.family, self.x, self.y, w, p)

    def mstep(self, moments: np.ndarray) -> tuple[np.ndarray, dict]:
        """Weighted ML parameters from the :func:`_responsibility_moments` of the responsibilities."""
        nk, mean_x, mean_y, var_y = moments
        w = nk / nk.sum()
        if self.family == "gamma":
            a = _gamma_shape(np.log(mean_x), mean_y, self.shape_max)
            return w, {"shape": a, "scale": mean_x / a}
        return w, {"mu": mean_y, "sigma": np.maximum(np.sqrt(var_y), self.sigma_min)}

    def hard_start(self, labels: np.ndarray, k: int) -> np.ndarray:
        """Responsibility moments of a hard partition (every component non-empty)."""
        n = self.x.size  # all the weight on the labelled component: it is the top one, the rest 0
        return _responsibility_moments(np.zeros((k, n)), np.zeros(n), labels, self.x, self.y, self.family != "gamma")[1]


def _kmeans_1d(y: np.ndarray, centers: np.ndarray, n_iter: int = 100) -> np.ndarray:
    """Lloyd's algorithm in 1-D; returns labels."""
    labels = np.full(y.size, -1)
    for _ in range(n_iter):
        new = np.argmin(np.abs(y[:, None] - centers[None, :]), axis=1)
        if np.array_equal(new, labels):
            break
        labels = new
        for j in range(centers.size):
            if np.any(labels == j):
                centers[j] = y[labels == j].mean()
    return labels


def _starts(y: np.ndarray, k: int, n_restarts: int, rng: np.random.Generator):
    """Hard partitions to start EM from: quantile split, 1-D k-means, random thresholds."""
    if k == 1:
        yield np.zeros(y.size, dtype=int)
        return
    order = np.argsort(y)
    q = np.empty(y.size, dtype=int)
    q[order] = np.minimum(np.arange(y.size) * k // y.size, k - 1)
    yield q
    yield _kmeans_1d(y, np.quantile(y, (np.arange(k) + 0.5) / k))
    for _ in range(n_restarts):
        cuts = np.sort(rng.uniform(0.1, 0.9, size=k - 1))
        yield np.searchsorted(np.quantile(y, cuts), y)


@dataclass
class _EMState:
    """Mutable state of one EM run (private)."""

    loglik: float
    weights: np.ndarray
    params: dict
    converged: bool
    n_iter: int


def _estep(fam: _Family, w: np.ndarray, p: dict) -> tuple[float, np.ndarray]:
    """Log-likelihood of the sample and responsibility moments for weights ``w``, params ``p``."""
    e, top, arg = fam.shifted_log_joint(w, p)
    np.exp(e[:-1], out=e[:-1])
    tot, moments = _responsibility_moments(e, top, arg, fam.x, fam.y, fam.family != "gamma")
    return float(top.sum() + np.log(tot).sum()), moments


def _em(fam: _Family, st: _EMState, tol: float, n_steps: int) -> _EMState:
    """Advance EM by up to ``n_steps`` iterations from ``st`` (which it updates and returns).

    Stops when the log-likelihood gain per sample drops below ``tol``; a component whose
    total responsibility vanishes marks the run as failed (loglik = -inf).
    """
    n = fam.x.size
    w, p = st.weights, st.params
    prev = st.loglik
    for _ in range(n_steps):
        ll, moments = _estep(fam, w, p)
        st.n_iter += 1
        if (moments[0] < 1e-8 * n).any():  # a component died
            st.loglik, st.converged = -np.inf, False
            return st
        st.loglik = ll
        if ll - prev < tol * n:
            st.converged = True
            return st
        prev = ll
        w, p = fam.mstep(moments)
        st.weights, st.params = w, p
    return st


def fit_mixture(
    x,
    family: str = "gamma",
    n_components: int = 2,
    n_restarts: int = 8,
    seed: int = 0,
    tol: float = 1e-9,
    max_iter: int = 2000,
) -> MixtureFit:
    """Maximum-likelihood K-component mixture of one family, by EM with restarts.

    Why: a parametric description of the bimodal ISI distribution (paper Fig. 9) whose
    components give the two time scales with uncertainties and whose BIC tells whether two
    components are needed at all.

    EM is started from a quantile split, a 1-D k-means partition (on log x for lognormal
    and gamma) and ``n_restarts`` random quantile thresholds.  Every start gets 30 EM
    iterations, the two best are iterated to convergence, and the higher likelihood wins.
    Gamma M-steps solve the weighted shape equation by Newton iteration (Minka 2002).

    Parameters
    ----------
    x : array_like, shape (n,)
        Samples (e.g. ISIs in s); strictly positive for lognormal and gamma.
        n must be at least 3 * n_components.
    family : {"gaussian", "lognormal", "gamma"}, default "gamma"
    n_components : int, default 2
    n_restarts : int, default 8
        Random starts in addition to the two deterministic ones (K > 1 only).
    seed : int, default 0
        Seed of the random starts (results are deterministic).
    tol : float, default 1e-9
        Stop when the log-likelihood gain per sample falls below ``tol``.
    max_iter : int, default 2000

    Returns
    -------
    MixtureFit
    """
    if family not in FAMILIES:
        raise ValueError(f"family must be one of {FAMILIES}, got {family!r}")
    k = int(n_components)
    if k < 1:
        raise ValueError(f"n_components must be >= 1, got {n_components}")
    if family == "gaussian":
        v = as_finite_1d(x, "x", min_size=3 * k)
    else:
        v = as_positive_1d(x, "x", min_size=3 * k)
    if np.ptp(v) == 0:
        raise ValueError("x is constant; a mixture density cannot be fitted")
    fam = _Family(family, v)
    rng = np.random.default_rng(seed)
    # Short runs from every start, then run the most promising ones to convergence:
    # restarts that head for a poor local maximum are abandoned early.
    runs = []
    for labels in _starts(fam.y, k, int(n_restarts), rng):
        if np.unique(labels).size < k:
            continue
        w0, p0 = fam.mstep(fam.hard_start(labels, k))
        runs.append(_em(fam, _EMState(-np.inf, w0, p0, False, 0), tol, _SHORT_RUN))
    runs = [r for r in runs if np.isfinite(r.loglik)]
    runs.sort(key=lambda r: r.loglik, reverse=True)
    for r in runs[:_N_FINISH]:
        if not r.converged:
            _em(fam, r, tol, int(max_iter) - r.n_iter)
    runs = [r for r in runs[:_N_FINISH] if np.isfinite(r.loglik)]
    if not runs:
        raise ValueError(f"EM failed for {k} {family} components: a component always collapsed")
    best = max(runs, key=lambda r: r.loglik)
    # loglik of the returned parameters (after max_iter the state is one M-step ahead)
    loglik = _estep(fam, best.weights, best.params)[0]
    order = np.argsort(_moments(family, best.params)[0])
    p = {name: val[order] for name, val in best.params.items()}
    return MixtureFit(family, best.weights[order], p, loglik, int(v.size), best.converged, best.n_iter)


@dataclass(frozen=True)
class MixtureSelection:
    """Candidate mixture fits ranked by BIC (best first).

    Attributes
    ----------
    fits : tuple of MixtureFit
        Sorted by increasing BIC.
    """

    fits: tuple

    @property
    def best(self) -> MixtureFit:
        """The fit with the lowest BIC."""
        return self.fits[0]

    @property
    def delta_bic(self) -> np.ndarray:
        """BIC of each fit minus the best BIC (>10 is "very strong" evidence against it)."""
        b = np.array([f.bic for f in self.fits])
        return b - b[0]

    def table(self) -> str:
        """Multi-line ranking, one fit per line, with delta BIC."""
        return "\n".join(f"dBIC={d:8.2f}  {f.summary()}" for d, f in zip(self.delta_bic, self.fits))


def select_mixture(
    x,
    families=FAMILIES,
    n_components=(1, 2),
    n_restarts: int = 8,
    seed: int = 0,
) -> MixtureSelection:
    """Fit every (family, K) candidate and rank by BIC.

    Why: answers "is the ISI distribution bimodal, and which shape fits?" by a criterion
    that penalises the extra parameters of a second component.

    Parameters
    ----------
    x : array_like
        Samples (e.g. ISIs in s); must be positive if lognormal or gamma is included.
    families : sequence of str, default all of ``FAMILIES``
    n_components : sequence of int, default (1, 2)
    n_restarts, seed : see :func:`fit_mixture`

    Returns
    -------
    MixtureSelection
    """
    fams = tuple(families)
    ks = tuple(int(k) for k in n_components)
    if not fams or not ks:
        raise ValueError("families and n_components must not be empty")
    fits = [fit_mixture(x, f, k, n_restarts=n_restarts, seed=seed) for f in fams for k in ks]
    return MixtureSelection(tuple(sorted(fits, key=lambda f: f.bic)))
