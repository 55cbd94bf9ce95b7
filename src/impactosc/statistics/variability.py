"""Variability of an impact train: running C_V^2 of the intervals and Fano factor of counts.

Three different quantities are in play and are easy to confuse (see DESIGN.md,
"Replication notes"):

* :func:`cv2_paper_running` -- ``var(S)/mean(S)`` of the ISIs, in **seconds**.  This is what
  the paper plots as "C_V^2" in Fig. 8 (limit about 0.03 for the chaotic train); it is not
  dimensionless and its value depends on the time unit.
* :func:`cv2_running` -- the dimensionless squared coefficient of variation
  ``var(S)/mean(S)^2`` (1 for a Poisson train, 0 for a periodic one; about 0.2 chaotic).
* :func:`fano_factor` -- ``var(N)/mean(N)`` of the counts N in windows of fixed length, the
  quantity the paper's definition ``D[N]/M[N]`` actually describes (1 for Poisson; for a
  renewal process it tends to the interval C_V^2 for long windows).

All variances use ``ddof=1`` (unbiased, n - 1 denominator) by default, matching
Mathematica's ``Variance`` which the paper used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics._validation import as_event_times, as_positive_1d, check_positive_scalar, check_time_span
from impactosc.statistics.counts import counts_in_windows

__all__ = [
    "RunningStatistic",
    "FanoCurve",
    "cv2_paper_running",
    "cv2_running",
    "fano_factor",
    "fano_curve",
]


@dataclass(frozen=True)
class RunningStatistic:
    """A statistic evaluated on the growing prefixes ``S[:i]`` of a sequence.

    Attributes
    ----------
    sample_size : ndarray of int
        Prefix length i (starts at ``ddof + 1``, the first size with a defined variance).
    value : ndarray
        Statistic on ``S[:i]``.
    ddof : int
        Delta degrees of freedom used for the variance.
    """

    sample_size: np.ndarray
    value: np.ndarray
    ddof: int

    @property
    def final(self) -> float:
        """Value on the whole sample."""
        return float(self.value[-1])


def _running_mean_var(s: np.ndarray, ddof: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Prefix means and variances of ``s`` for prefix sizes ``ddof+1 .. n``.

    Sums are taken about the overall mean (a shift that leaves the variance unchanged) to
    avoid the cancellation of the naive sum-of-squares formula.
    """
    if ddof < 0:
        raise ValueError(f"ddof must be >= 0, got {ddof}")
    if s.size < ddof + 1:
        raise ValueError(f"S has too few samples: need at least {ddof + 1} for ddof={ddof}, got {s.size}")
    shift = s.mean()
    d = s - shift
    i = np.arange(1, s.size + 1, dtype=float)
    csum = np.cumsum(d)
    csum2 = np.cumsum(d * d)
    mean_d = csum / i
    start = ddof  # first index with i - ddof > 0
    i_v = i[start:]
    var = (csum2[start:] - i_v * mean_d[start:] ** 2) / (i_v - ddof)
    var = np.maximum(var, 0.0)  # rounding can give -1e-20 for constant prefixes
    return i_v.astype(int), mean_d[start:] + shift, var


def cv2_paper_running(S, ddof: int = 1) -> RunningStatistic:
    """The paper's Fig. 8 "C_V^2": ``var(S[:i]) / mean(S[:i])`` versus sample size i.

    Why: reproduces the plotted quantity exactly; it has units of seconds (about 0.03 s
    for the chaotic train at w = 40.86), so report :func:`cv2_running` alongside it.

    Parameters
    ----------
    S : array_like, shape (n,)
        Inter-impact intervals in s, all > 0, n >= ddof + 1.
    ddof : int, default 1
        Variance denominator ``i - ddof`` (1 = Mathematica's ``Variance``).

    Returns
    -------
    RunningStatistic
        ``value`` in seconds, for i = ddof+1 .. n.
    """
    s = as_positive_1d(S, "S")
    n, mean, var = _running_mean_var(s, int(ddof))
    return RunningStatistic(n, var / mean, int(ddof))


def cv2_running(S, ddof: int = 1) -> RunningStatistic:
    """Dimensionless squared coefficient of variation ``var(S[:i]) / mean(S[:i])^2``.

    Why: the standard, unit-free regularity measure of a spike/impact train
    (1 = Poisson, 0 = periodic); the running form shows whether the estimate has settled.

    Parameters
    ----------
    S : array_like, shape (n,)
        Inter-impact intervals in s, all > 0, n >= ddof + 1.
    ddof : int, default 1
        Variance denominator ``i - ddof``.

    Returns
    -------
    RunningStatistic
        Dimensionless ``value`` for i = ddof+1 .. n.
    """
    s = as_positive_1d(S, "S")
    n, mean, var = _running_mean_var(s, int(ddof))
    return RunningStatistic(n, var / mean**2, int(ddof))


def _window_edges(window: float, t_start: float, t_stop: float) -> np.ndarray:
    """Edges of the consecutive windows of length ``window`` that fit in [t_start, t_stop]."""
    n = int(np.floor((t_stop - t_start) / window * (1 + 1e-12)))
    return t_start + window * np.arange(n + 1)


def fano_factor(times, window: float, t_start: float, t_stop: float, ddof: int = 1) -> float:
    """Fano factor ``var(N)/mean(N)`` of impact counts N in consecutive windows.

    Why: this is the quantity ``D[N]/M[N]`` the paper defines (Poisson: 1, periodic: ~0),
    estimated from counts rather than from intervals.

    The span ``[t_start, t_stop]`` is tiled by ``floor((t_stop - t_start)/window)``
    non-overlapping windows starting at ``t_start``; a remainder shorter than ``window`` at
    the end is discarded.  Pass the recording span, not the first/last impact (starting a
    window on an impact biases its count).

    Parameters
    ----------
    times : array_like
        Impact onset times in s, strictly increasing.
    window : float
        Window length in s, > 0; at least 2 windows must fit in the span.
    t_start, t_stop : float
        Observation span in s.
    ddof : int, default 1
        Variance denominator ``m - ddof`` over the m window counts.

    Returns
    -------
    float
        Dimensionless Fano factor.
    """
    t = as_event_times(times, "times")
    w = check_positive_scalar(window, "window")
    a, b = check_time_span(t_start, t_stop)
    edges = _window_edges(w, a, b)
    if edges.size - 1 < 2:
        raise ValueError(f"window={w} s is too long: fewer than 2 windows fit in [{a}, {b}] s")
    if edges.size - 1 <= ddof:
        raise ValueError(f"too few windows ({edges.size - 1}) for ddof={ddof}")
    counts = counts_in_windows(t, edges)
    mean = counts.mean()
    if mean == 0:
        raise ValueError("no events fall in the windows; the Fano factor is undefined")
    return float(counts.var(ddof=ddof) / mean)


@dataclass(frozen=True)
class FanoCurve:
    """Fano factor versus counting-window length.

    Attributes
    ----------
    windows : ndarray
        Window lengths in s.
    fano : ndarray
        Fano factor for each window length (dimensionless).
    n_windows : ndarray of int
        Number of windows the estimate used (its standard error for Poisson counts is
        about ``sqrt(2 / (n_windows - 1))``).
    """

    windows: np.ndarray
    fano: np.ndarray
    n_windows: np.ndarray


def fano_curve(times, windows, t_start: float, t_stop: float, ddof: int = 1) -> FanoCurve:
    """Fano factor for several window lengths (see :func:`fano_factor`).

    Why: for a Poisson train the curve is flat at 1; a regular (periodic-like) train drops
    towards 0 at long windows, and a clustered one rises above 1.

    Parameters
    ----------
    times : array_like
        Impact onset times in s.
    windows : array_like
        Window lengths in s, each > 0 and short enough for 2 windows to fit.
    t_start, t_stop : float
        Observation span in s.
    ddof : int, default 1

    Returns
    -------
    FanoCurve
    """
    w = as_positive_1d(windows, "windows")
    a, b = check_time_span(t_start, t_stop)
    fano = np.array([fano_factor(times, wi, a, b, ddof) for wi in w])
    n_win = np.array([_window_edges(wi, a, b).size - 1 for wi in w], dtype=int)
    return FanoCurve(w, fano, n_win)
