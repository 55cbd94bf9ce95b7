"""Impact counts in time windows and the test that the impact rate is the same in each.

The paper checks stationarity by splitting 400 s into five 80 s windows and comparing the
counts {572, 571, 579, 579, 574}; :func:`equal_rate_test` turns "almost equal" into a
chi-square test.  :func:`counts_in_windows` is also what the Fano factor is built on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics._validation import as_event_times, as_finite_1d, check_time_span

__all__ = ["EqualRateTest", "counts_in_windows", "window_counts", "equal_rate_test"]


def counts_in_windows(times, edges) -> np.ndarray:
    """Number of events in each window ``[edges[i], edges[i+1])``.

    Windows are half-open on the right except the last, which is closed (numpy.histogram
    convention); events outside ``[edges[0], edges[-1]]`` are ignored.

    Parameters
    ----------
    times : array_like, shape (n,)
        Event times in s, non-empty, finite and strictly increasing.
    edges : array_like, shape (m + 1,)
        Window edges in s, strictly increasing, m >= 1.

    Returns
    -------
    ndarray of int, shape (m,)
    """
    t = as_event_times(times, "times")
    e = as_event_times(edges, "edges", min_size=2)
    counts, _ = np.histogram(t, bins=e)
    return counts.astype(int)


def window_counts(times, t_start: float, t_stop: float, n_windows: int) -> np.ndarray:
    """Impact counts in ``n_windows`` equal windows tiling ``[t_start, t_stop]``.

    Why: equal counts in equal windows is the paper's stationarity check (5 x 80 s).

    Parameters
    ----------
    times : array_like
        Impact onset times in s, strictly increasing.
    t_start, t_stop : float
        Observation window in s (e.g. the recorded span 100 s .. 500 s, not the first and
        last impact).
    n_windows : int
        Number of equal windows, >= 1.  Edges are ``np.linspace(t_start, t_stop, n_windows+1)``.

    Returns
    -------
    ndarray of int, shape (n_windows,)
    """
    a, b = check_time_span(t_start, t_stop)
    n_windows = int(n_windows)
    if n_windows < 1:
        raise ValueError(f"n_windows must be >= 1, got {n_windows}")
    return counts_in_windows(times, np.linspace(a, b, n_windows + 1))


@dataclass(frozen=True)
class EqualRateTest:
    """Result of :func:`equal_rate_test`.

    Attributes
    ----------
    statistic : float
        Chi-square statistic ``sum (n_i - nbar)^2 / nbar`` (dimensionless).
    dof : int
        Degrees of freedom, number of windows - 1.
    pvalue : float
        Upper-tail chi-square probability.
    alpha : float
        Significance level used for the conclusion.
    conclusion : str
        One-line verdict.
    """

    statistic: float
    dof: int
    pvalue: float
    alpha: float
    conclusion: str

    @property
    def rejected(self) -> bool:
        """True if equal rates are rejected at level ``alpha``."""
        return self.pvalue < self.alpha


def equal_rate_test(counts, alpha: float = 0.05) -> EqualRateTest:
    """Chi-square test that event counts in equal-length windows share one rate.

    Why: the paper calls the train stationary because the 5 window counts are "almost
    equal"; this quantifies it.  The statistic ``sum (n_i - nbar)^2 / nbar`` is both
    Pearson's goodness-of-fit statistic for equal expected counts and the Poisson
    dispersion (index-of-dispersion) statistic; under Poisson counts with a common rate it
    is approximately chi-square with ``k - 1`` dof (``scipy.stats.chisquare``).  Impact
    trains more regular than Poisson (Fano < 1) make the test conservative, so a p-value
    close to 1 means "the counts are even more uniform than Poisson scatter" rather than a
    problem.

    Parameters
    ----------
    counts : array_like of int, shape (k,)
        Non-negative counts in k >= 2 windows of equal length, total > 0.
    alpha : float, default 0.05
        Significance level for the conclusion string.

    Returns
    -------
    EqualRateTest
    """
    c = as_finite_1d(counts, "counts", min_size=2)
    if np.any(c < 0) or np.any(c != np.round(c)):
        raise ValueError("counts must be non-negative integers")
    if c.sum() <= 0:
        raise ValueError("counts are all zero; the rate cannot be tested")
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must be in (0, 1), got {alpha}")
    # expected counts default to the mean; ddof=0 gives k - 1 dof (nbar uses only the total)
    from scipy import stats

    res = stats.chisquare(c)
    statistic, pvalue = float(res.statistic), float(res.pvalue)
    dof = c.size - 1
    detail = f"chi2={statistic:.3g}, dof={dof}, p={pvalue:.3g}"
    if pvalue < alpha:
        conclusion = (
            f"equal rates rejected ({detail} < {alpha}): counts vary more than Poisson "
            f"scatter, the train is not stationary over these windows"
        )
    else:
        conclusion = f"consistent with equal rates ({detail} >= {alpha}): no evidence against stationarity"
    return EqualRateTest(statistic, dof, pvalue, float(alpha), conclusion)
