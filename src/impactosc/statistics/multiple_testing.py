"""Verdicts from many z-scores at once: two-sided p-values and Holm's step-down correction.

Why: a verdict that checks N numbers each at "within 3 sd" fails by chance with probability
about N x 0.27 % when nothing is wrong (one |z| > 3 among 60 comes up in 15 % of clean runs).
Holm's step-down procedure (Holm 1979) keeps the chance of any false alarm among the N tests
at the family-wise level alpha, whatever their dependence, and rejects at least what Bonferroni
rejects. The default level is that of one 3-sd test, so a verdict on a single number is unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactosc.statistics._validation import as_finite_1d

__all__ = ["THREE_SD_LEVEL", "HolmVerdict", "two_sided_p", "holm", "largest_z_bound"]

#: Two-sided normal tail beyond 3 sd, 0.0027: the level of the single 3-sd checks, used as the family-wise level.
THREE_SD_LEVEL = math.erfc(3.0 / math.sqrt(2.0))


def two_sided_p(z) -> np.ndarray:
    """Two-sided normal p-values ``P(|Z| >= |z|)`` of z-scores (erfc, exact far in the tails)."""
    zz = as_finite_1d(np.atleast_1d(z), "z-scores")
    from scipy import special

    return special.erfc(np.abs(zz) / math.sqrt(2.0))


@dataclass(frozen=True)
class HolmVerdict:
    """Holm's step-down procedure on N p-values at family-wise level ``alpha``.

    Attributes
    ----------
    pvalues : ndarray
        The raw p-values, in the order given.
    adjusted : ndarray
        Holm-adjusted p-values (a test is rejected when its adjusted p-value < alpha).
    rejected : ndarray of bool
    alpha : float
    """

    pvalues: np.ndarray
    adjusted: np.ndarray
    rejected: np.ndarray
    alpha: float

    @property
    def n_tests(self) -> int:
        """Number of tests in the family."""
        return int(self.pvalues.size)

    @property
    def any_rejected(self) -> bool:
        """True if at least one test of the family is rejected."""
        return bool(self.rejected.any())


def holm(pvalues, alpha: float = THREE_SD_LEVEL) -> HolmVerdict:
    """Holm's step-down: sort the N p-values, reject while ``p_(i) < alpha / (N - i + 1)``.

    The adjusted p-value of the i-th smallest is ``max_{j <= i} min(1, (N - j + 1) p_(j))``.
    """
    p = as_finite_1d(np.atleast_1d(pvalues), "p-values")
    if np.any((p < 0) | (p > 1)):
        raise ValueError("p-values must lie in [0, 1]")
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha}")
    order = np.argsort(p, kind="stable")
    factor = p.size - np.arange(p.size)
    adjusted_sorted = np.maximum.accumulate(np.minimum(1.0, factor * p[order]))
    adjusted = np.empty_like(p)
    adjusted[order] = adjusted_sorted
    return HolmVerdict(p, adjusted, adjusted < alpha, float(alpha))


def largest_z_bound(n_tests: int, alpha: float = THREE_SD_LEVEL, reference_size: int | None = None) -> float:
    """The |z| the largest of ``n_tests`` z-scores must exceed for Holm (whose first step is
    Bonferroni's) to reject anything: the two-sided normal quantile at ``alpha / n_tests``.

    Why: a check that reports only its worst |z| (a hard case's row) bounds it by this instead of
    3, and so decides as Holm's procedure on all its tests does (3.0 for one test, 3.6 for ten).

    ``reference_size`` n: each z is a new value against the mean and sample standard deviation of
    n reference values (not a known sd), so it follows sqrt(1 + 1/n) times Student's t with n - 1
    degrees of freedom (a prediction interval): the quantile is that one's. With 5 references
    the normal quantile would reject a true null far more often than alpha.
    """
    n = int(n_tests)
    if n < 1:
        raise ValueError(f"n_tests must be >= 1, got {n_tests}")
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha}")
    from scipy import special, stats

    if reference_size is None:
        return float(math.sqrt(2.0) * special.erfcinv(alpha / n))
    size = int(reference_size)
    if size < 2:
        raise ValueError(f"reference_size must be >= 2 (a sample standard deviation), got {reference_size}")
    return float(math.sqrt(1.0 + 1.0 / size) * stats.t.isf(alpha / (2.0 * n), size - 1))
