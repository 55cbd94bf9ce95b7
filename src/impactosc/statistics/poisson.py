"""Is the impact train Poissonian?  KS test of the intervals against an exponential law.

A Poisson train has independent, exponentially distributed intervals.  The paper argues
the chaotic train is "non-Poissonian" from C_V^2 < 1; this module gives the direct
goodness-of-fit test of the interval distribution.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics._validation import as_positive_1d

__all__ = ["ExponentialKSTest", "exponential_ks_test"]

_CHUNK_ELEMENTS = 2_000_000  # bootstrap memory bound (floats per batch)


@dataclass(frozen=True)
class ExponentialKSTest:
    """Result of :func:`exponential_ks_test`.

    Attributes
    ----------
    statistic : float
        KS distance D between the empirical CDF and ``1 - exp(-s/mean)``.
    pvalue : float
        p-value used for the conclusion: the bootstrap (Lilliefors) one if computed,
        otherwise the classical KS one.
    pvalue_ks : float
        Classical KS p-value, which assumes a fully specified null; with the mean
        estimated from the same data it is too large (the test is conservative).
    pvalue_bootstrap : float or None
        Parametric-bootstrap p-value accounting for the estimated mean; None if
        ``n_bootstrap == 0``.
    mean : float
        Estimated mean interval (s); the rate is ``1/mean`` impacts per s.
    alpha : float
    conclusion : str
        One-line verdict.
    """

    statistic: float
    pvalue: float
    pvalue_ks: float
    pvalue_bootstrap: float | None
    mean: float
    alpha: float
    conclusion: str

    @property
    def rejected(self) -> bool:
        """True if the exponential (Poisson-train) hypothesis is rejected at ``alpha``."""
        return self.pvalue < self.alpha


def exponential_ks_test(S, alpha: float = 0.05, n_bootstrap: int = 999, seed: int = 0) -> ExponentialKSTest:
    """Kolmogorov-Smirnov test of intervals against the exponential with the same mean.

    Why: exponential ISIs are necessary for a Poisson train; rejection means the train is
    non-Poissonian in its interval distribution (independent of C_V^2).

    The mean is estimated from ``S`` itself, so the textbook KS p-value
    (``scipy.stats.kstest``) is conservative.  The Lilliefors-type correction is
    ``scipy.stats.goodness_of_fit`` (exponential with loc 0 known, scale fitted, KS
    statistic): ``n_bootstrap`` simulated samples, the mean re-fitted in each,
    ``p = (1 + #{D_b >= D}) / (n_bootstrap + 1)``.  It runs in batches of at most
    ``_CHUNK_ELEMENTS`` simulated values to bound memory; the batches draw from one
    generator, so the p-value does not depend on the batch size.  Successive intervals are
    assumed independent (true for a Poisson train).

    Parameters
    ----------
    S : array_like, shape (n,)
        Inter-impact intervals in s, all > 0, n >= 5.
    alpha : float, default 0.05
        Significance level for the conclusion.
    n_bootstrap : int, default 999
        Bootstrap replicates; 0 to skip (then the conclusion uses the classical p-value).
    seed : int, default 0
        Seed of the bootstrap generator (results are reproducible).

    Returns
    -------
    ExponentialKSTest
    """
    s = as_positive_1d(S, "S", min_size=5)
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha}")
    n_bootstrap = int(n_bootstrap)
    if n_bootstrap < 0:
        raise ValueError(f"n_bootstrap must be >= 0, got {n_bootstrap}")
    mean = float(s.mean())
    from scipy import stats

    ks = stats.kstest(s, "expon", args=(0.0, mean))
    d = float(ks.statistic)
    p_boot = None
    if n_bootstrap:
        rng = np.random.default_rng(seed)
        rows = max(1, _CHUNK_ELEMENTS // s.size)
        exceed = 0
        for done in range(0, n_bootstrap, rows):
            gof = stats.goodness_of_fit(
                stats.expon,
                s,
                known_params={"loc": 0.0},
                statistic="ks",
                n_mc_samples=min(rows, n_bootstrap - done),
                rng=rng,
            )
            exceed += int(np.sum(gof.null_distribution >= d))
        p_boot = (1 + exceed) / (n_bootstrap + 1)
    p = p_boot if p_boot is not None else float(ks.pvalue)
    kind = "bootstrap" if p_boot is not None else "classical KS, conservative"
    detail = f"D={d:.3g}, p={p:.3g} ({kind}), n={s.size}"
    if p < alpha:
        conclusion = f"exponential intervals rejected ({detail} < {alpha}): the train is not Poisson"
    else:
        conclusion = f"consistent with exponential intervals ({detail} >= {alpha}): no evidence against a Poisson train"
    return ExponentialKSTest(d, p, float(ks.pvalue), p_boot, mean, float(alpha), conclusion)
