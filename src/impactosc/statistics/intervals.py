"""Inter-impact intervals, return maps and the distinct interval levels of a periodic train.

The impact map of the paper is the sequence of impact onsets ``T_j``; its intervals
``S_j = T_{j+1} - T_j`` (ISIs) and the pairs ``(S_j, S_{j+1})`` are the raw material of every
other statistic.  For a periodic orbit the ISIs take a few distinct values with equal
counts whose sum is the orbit period (paper Fig. 5: 4 levels summing to 0.8184 s).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics._validation import as_event_times, as_finite_1d

__all__ = ["DistinctLevels", "inter_impact_intervals", "return_map", "distinct_levels"]


def inter_impact_intervals(times) -> np.ndarray:
    """Inter-impact intervals ``S_j = T_{j+1} - T_j``.

    Parameters
    ----------
    times : array_like, shape (n,)
        Impact onset times ``T_j`` in seconds, finite and strictly increasing, n >= 2.

    Returns
    -------
    ndarray, shape (n - 1,)
        Intervals in seconds (all > 0).
    """
    t = as_event_times(times, "times", min_size=2)
    return np.diff(t)


def return_map(seq, lag: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Successive-iteration pairs ``(s_j, s_{j+lag})`` of a sequence (paper Figs 5a, 7b).

    A plot of ``s_{j+1}`` against ``s_j`` shows the dynamics of the impact map: a few points
    for a periodic orbit, separated fractal branches for the chaotic one.

    Parameters
    ----------
    seq : array_like, shape (n,)
        Any finite sequence (ISIs in s, penetrations in m, Poincare-section values, ...).
    lag : int, default 1
        Index shift, 1 <= lag < n.

    Returns
    -------
    (x, y) : tuple of ndarray, each shape (n - lag,)
        ``x = seq[:-lag]`` and ``y = seq[lag:]``, in the units of ``seq``.
    """
    lag = int(lag)
    if lag < 1:
        raise ValueError(f"lag must be >= 1, got {lag}")
    s = as_finite_1d(seq, "seq", min_size=lag + 1)
    return s[:-lag].copy(), s[lag:].copy()


@dataclass(frozen=True)
class DistinctLevels:
    """Clusters of (nearly) equal values, e.g. the distinct ISIs of a periodic train.

    Attributes
    ----------
    levels : ndarray
        Mean value of each cluster, ascending (units of the input).
    counts : ndarray of int
        Number of samples in each cluster.
    spreads : ndarray
        Max - min of the samples inside each cluster (how tight the level is).
    """

    levels: np.ndarray
    counts: np.ndarray
    spreads: np.ndarray

    @property
    def n_levels(self) -> int:
        """Number of distinct levels."""
        return int(self.levels.size)

    @property
    def total(self) -> float:
        """Sum of the distinct levels; for the ISIs of a period-p train, the period (s)."""
        return float(self.levels.sum())

    @property
    def counts_equal(self) -> bool:
        """True if the counts differ by at most 1 (a truncated periodic sequence)."""
        return bool(self.counts.max() - self.counts.min() <= 1)


def distinct_levels(values, rel_tol: float = 1e-3, abs_tol: float = 0.0) -> DistinctLevels:
    """Group values that are equal up to a tolerance and count each group.

    Why: a periodic impact train has only a few distinct intervals (paper Fig. 5b: the
    histogram has 4 bars of equal height); numerical ISIs agree only to the event-location
    accuracy, so exact ``np.unique`` is not enough.

    Values are sorted and split wherever two neighbours differ by more than
    ``tol = max(abs_tol, rel_tol * max|values|)`` (single-linkage clustering in 1-D).  On a
    chaotic train this returns many levels, which is the intended diagnostic.

    Parameters
    ----------
    values : array_like, shape (n,)
        Finite values, e.g. ISIs in seconds.
    rel_tol : float, default 1e-3
        Gap threshold relative to the largest magnitude.
    abs_tol : float, default 0
        Absolute gap threshold in the units of ``values``.

    Returns
    -------
    DistinctLevels
    """
    v = np.sort(as_finite_1d(values, "values"))
    if not (np.isfinite(rel_tol) and rel_tol >= 0 and np.isfinite(abs_tol) and abs_tol >= 0):
        raise ValueError(f"rel_tol and abs_tol must be finite and >= 0, got {rel_tol}, {abs_tol}")
    tol = max(abs_tol, rel_tol * float(np.max(np.abs(v))))
    breaks = np.flatnonzero(np.diff(v) > tol) + 1
    groups = np.split(v, breaks)
    return DistinctLevels(
        levels=np.array([g.mean() for g in groups]),
        counts=np.array([g.size for g in groups], dtype=int),
        spreads=np.array([g[-1] - g[0] for g in groups]),
    )
