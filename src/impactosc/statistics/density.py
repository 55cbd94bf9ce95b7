"""Relative-frequency histograms, a smooth density estimate and its maxima (paper Figs 9, 11).

The paper bins the 2875 chaotic ISIs into 10 bars of relative frequency and draws a smooth
curve through them whose two maxima (about 0.05 s and 0.2 s) are the reported time scales.
Here the smooth curve is a Gaussian kernel density estimate, and its maxima are located
automatically with a prominence threshold so sampling noise does not add spurious modes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from impactosc.statistics._peaks import parabolic_refine
from impactosc.statistics._validation import as_finite_1d

__all__ = [
    "Histogram",
    "KernelDensity",
    "DensityMaxima",
    "relative_frequency_histogram",
    "kernel_density",
    "density_maxima",
]


@dataclass(frozen=True)
class Histogram:
    """Relative-frequency histogram.

    Attributes
    ----------
    edges : ndarray, shape (bins + 1,)
        Bin edges (units of the data).
    counts : ndarray of int, shape (bins,)
        Samples per bin.
    relative_frequency : ndarray, shape (bins,)
        ``counts / n``; sums to 1 (the paper's bar heights).
    """

    edges: np.ndarray
    counts: np.ndarray
    relative_frequency: np.ndarray

    @property
    def centers(self) -> np.ndarray:
        """Bin centres (units of the data)."""
        return 0.5 * (self.edges[:-1] + self.edges[1:])

    @property
    def widths(self) -> np.ndarray:
        """Bin widths (units of the data)."""
        return np.diff(self.edges)

    @property
    def density(self) -> np.ndarray:
        """Probability density ``counts / (n * width)`` (1/units), comparable with a KDE."""
        return self.relative_frequency / self.widths


def relative_frequency_histogram(values, bins: int = 10, range=None) -> Histogram:
    """Histogram whose bar heights are relative frequencies (fractions of the sample).

    Why: the paper's Figs 9 and 11 plot relative frequencies over 10 equal bins spanning
    the data.  To overlay a density curve on these bars multiply the density by the bin
    width (or plot ``Histogram.density``).

    Parameters
    ----------
    values : array_like, shape (n,)
        Finite samples (e.g. ISIs in s, penetrations in m).
    bins : int, default 10
        Number of equal-width bins, >= 1.
    range : (float, float), optional
        Histogram span; default ``(min, max)`` of the data.  Samples outside are dropped
        but still counted in n, so the bars then sum to less than 1.

    Returns
    -------
    Histogram
    """
    v = as_finite_1d(values, "values")
    bins = int(bins)
    if bins < 1:
        raise ValueError(f"bins must be >= 1, got {bins}")
    counts, edges = np.histogram(v, bins=bins, range=range)
    return Histogram(edges, counts.astype(int), counts / v.size)


@dataclass(frozen=True)
class KernelDensity:
    """Gaussian kernel density estimate evaluated on a grid.

    Attributes
    ----------
    grid : ndarray
        Evaluation points (units of the data).
    density : ndarray
        Estimated probability density (1/units).
    bandwidth : float
        Kernel standard deviation (units of the data).
    """

    grid: np.ndarray
    density: np.ndarray
    bandwidth: float


def kernel_density(values, bw_method="scott", grid=None, n_grid: int = 1024) -> KernelDensity:
    """Gaussian kernel density estimate (``scipy.stats.gaussian_kde``) on a grid.

    Why: a smooth estimate of the ISI density whose maxima define the time scales, without
    the arbitrariness of bin placement.

    The kernel standard deviation is ``factor * std(values, ddof=1)``; Scott's rule gives
    ``factor = n**(-1/5)`` (0.20 for n = 2875).  Scott's and Silverman's rules are optimal
    for a Gaussian and tend to over-smooth well-separated multimodal data; pass a smaller
    scalar ``bw_method`` (the factor) if modes merge.

    Parameters
    ----------
    values : array_like, shape (n,)
        Finite samples, n >= 2, not all equal.
    bw_method : {"scott", "silverman"} or float, default "scott"
        Passed to ``gaussian_kde``.
    grid : array_like, optional
        Evaluation points; default ``n_grid`` points spanning ``min - 3 bw .. max + 3 bw``.
    n_grid : int, default 1024

    Returns
    -------
    KernelDensity
    """
    v = as_finite_1d(values, "values", min_size=2)
    if np.ptp(v) == 0:
        raise ValueError("values are all equal; a kernel density estimate is undefined")
    from scipy import stats

    kde = stats.gaussian_kde(v, bw_method=bw_method)
    bw = float(np.sqrt(kde.covariance[0, 0]))
    if grid is None:
        if int(n_grid) < 3:
            raise ValueError(f"n_grid must be >= 3, got {n_grid}")
        g = np.linspace(v.min() - 3 * bw, v.max() + 3 * bw, int(n_grid))
    else:
        g = as_finite_1d(grid, "grid", min_size=3)
    return KernelDensity(g, kde(g), bw)


@dataclass(frozen=True)
class DensityMaxima:
    """Local maxima of a smooth density.

    Attributes
    ----------
    positions : ndarray
        Locations of the maxima, ascending (units of the grid).
    heights : ndarray
        Density at the maxima.
    prominences : ndarray
        Prominence of each maximum (same units as the density).
    """

    positions: np.ndarray
    heights: np.ndarray
    prominences: np.ndarray

    @property
    def n_modes(self) -> int:
        """Number of maxima found."""
        return int(self.positions.size)


def density_maxima(grid, density, min_prominence: float = 0.05) -> DensityMaxima:
    """Locate the local maxima of a smooth curve, ignoring insignificant wiggles.

    Why: turns the paper's "two distinct maxima at 0.05 s and 0.2 s" read off a plot into
    a reproducible number.  A maximum counts only if its prominence (height above the
    higher of the two surrounding minima) is at least ``min_prominence`` times the global
    maximum; positions are refined by a parabola through the three highest samples.

    Parameters
    ----------
    grid : array_like, shape (m,)
        Strictly increasing, evenly spaced abscissae (e.g. ``KernelDensity.grid``).
    density : array_like, shape (m,)
        Curve values on the grid (e.g. ``KernelDensity.density``), finite.
    min_prominence : float, default 0.05
        Relative prominence threshold in [0, 1).

    Returns
    -------
    DensityMaxima
    """
    g = as_finite_1d(grid, "grid", min_size=3)
    y = as_finite_1d(density, "density", min_size=3)
    if g.size != y.size:
        raise ValueError(f"grid and density must have the same length, got {g.size} and {y.size}")
    step = np.diff(g)
    if np.any(step <= 0):
        raise ValueError("grid must be strictly increasing")
    if not np.allclose(step, step[0], rtol=1e-6, atol=0):
        raise ValueError("grid must be evenly spaced")
    if not 0 <= min_prominence < 1:
        raise ValueError(f"min_prominence must be in [0, 1), got {min_prominence}")
    ymax = float(np.max(y))
    if ymax <= 0:
        raise ValueError("density has no positive values")
    # pad with the curve minimum so maxima at the grid ends are not lost
    floor = float(np.min(y))
    padded = np.concatenate([[floor], y, [floor]])
    from scipy import signal

    idx, props = signal.find_peaks(padded, prominence=min_prominence * ymax)
    idx = idx - 1
    off, val = parabolic_refine(y, idx)
    return DensityMaxima(g[idx] + off * step[0], val, props["prominences"])
