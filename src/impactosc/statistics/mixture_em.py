"""Expectation-maximisation for a mixture of one family: starting partitions, M-steps, and the
restarts that pick the best run.

Why a module: EM finds a local maximum of the likelihood from each start, and which start
wins is decided in the last bits of the log-likelihoods, so the algorithm (starts, short
runs, the best ones run to convergence) is kept apart from what a fit reports
(:mod:`impactosc.statistics.mixture`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import special

from impactosc.statistics.mixture_kernels import responsibility_moments, shifted_log_joint

__all__ = ["EMFamily", "EMState", "e_step", "best_em_run"]

_SPREAD_FLOOR = 1e-3
_SHORT_RUN = 30  # EM iterations every start gets before the ranking
_N_FINISH = 2  # best starts that are run to convergence


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


class EMFamily:
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
        """:func:`impactosc.statistics.mixture_kernels.shifted_log_joint` of the sample."""
        return shifted_log_joint(self.family, self.x, self.y, w, p)

    def mstep(self, moments: np.ndarray) -> tuple[np.ndarray, dict]:
        """Weighted ML parameters from the moments of the responsibilities (mixture_kernels.responsibility_moments)."""
        nk, mean_x, mean_y, var_y = moments
        w = nk / nk.sum()
        if self.family == "gamma":
            a = _gamma_shape(np.log(mean_x), mean_y, self.shape_max)
            return w, {"shape": a, "scale": mean_x / a}
        return w, {"mu": mean_y, "sigma": np.maximum(np.sqrt(var_y), self.sigma_min)}

    def hard_start(self, labels: np.ndarray, k: int) -> np.ndarray:
        """Responsibility moments of a hard partition (every component non-empty)."""
        n = self.x.size  # all the weight on the labelled component: it is the top one, the rest 0
        return responsibility_moments(np.zeros((k, n)), np.zeros(n), labels, self.x, self.y, self.family != "gamma")[1]


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
class EMState:
    """Mutable state of one EM run."""

    loglik: float
    weights: np.ndarray
    params: dict
    converged: bool
    n_iter: int


def e_step(fam: EMFamily, w: np.ndarray, p: dict) -> tuple[float, np.ndarray]:
    """Log-likelihood of the sample and responsibility moments for weights ``w``, params ``p``."""
    e, top, arg = fam.shifted_log_joint(w, p)
    np.exp(e[:-1], out=e[:-1])
    tot, moments = responsibility_moments(e, top, arg, fam.x, fam.y, fam.family != "gamma")
    return float(top.sum() + np.log(tot).sum()), moments


def _em(fam: EMFamily, st: EMState, tol: float, n_steps: int) -> EMState:
    """Advance EM by up to ``n_steps`` iterations from ``st`` (which it updates and returns).

    Stops when the log-likelihood gain per sample drops below ``tol``; a component whose
    total responsibility vanishes marks the run as failed (loglik = -inf).
    """
    n = fam.x.size
    w, p = st.weights, st.params
    prev = st.loglik
    for _ in range(n_steps):
        ll, moments = e_step(fam, w, p)
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


def best_em_run(fam: EMFamily, k: int, n_restarts: int, seed: int, tol: float, max_iter: int) -> EMState:
    """The run of highest likelihood among EM's runs of ``k`` components from every start.

    Short runs from every start, then run the most promising ones to convergence: restarts
    that head for a poor local maximum are abandoned early.
    """
    rng = np.random.default_rng(seed)
    runs = []
    for labels in _starts(fam.y, k, int(n_restarts), rng):
        if np.unique(labels).size < k:
            continue
        w0, p0 = fam.mstep(fam.hard_start(labels, k))
        runs.append(_em(fam, EMState(-np.inf, w0, p0, False, 0), tol, _SHORT_RUN))
    runs = [r for r in runs if np.isfinite(r.loglik)]
    runs.sort(key=lambda r: r.loglik, reverse=True)
    for r in runs[:_N_FINISH]:
        if not r.converged:
            _em(fam, r, tol, int(max_iter) - r.n_iter)
    runs = [r for r in runs[:_N_FINISH] if np.isfinite(r.loglik)]
    if not runs:
        raise ValueError(f"EM failed for {k} {fam.family} components: a component always collapsed")
    return max(runs, key=lambda r: r.loglik)
