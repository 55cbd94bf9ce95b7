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

from impactosc.statistics._validation import as_finite_1d, as_positive_1d
from impactosc.statistics.mixture_em import EMFamily, best_em_run, e_step
from impactosc.statistics.mixture_kernels import component_moments, shifted_log_joint

__all__ = ["FAMILIES", "MixtureFit", "MixtureSelection", "fit_mixture", "select_mixture"]

FAMILIES = ("gaussian", "lognormal", "gamma")


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
        return component_moments(self.family, self.params)[0]

    @property
    def stds(self) -> np.ndarray:
        """Component standard deviations (units of the data)."""
        return np.sqrt(component_moments(self.family, self.params)[1])

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
            e, top, _ = shifted_log_joint(self.family, v, y, self.weights, self.params)
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
    fam = EMFamily(family, v)
    best = best_em_run(fam, k, n_restarts, seed, tol, max_iter)
    # loglik of the returned parameters (after max_iter the state is one M-step ahead)
    loglik = e_step(fam, best.weights, best.params)[0]
    order = np.argsort(component_moments(family, best.params)[0])
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
