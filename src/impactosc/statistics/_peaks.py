"""Sub-sample peak refinement shared by the spectrum, ACF-spectrum and density maxima code."""

from __future__ import annotations

import numpy as np

__all__ = ["parabolic_refine"]


def parabolic_refine(y: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Refine local maxima of a sampled curve by fitting a parabola through 3 points.

    A peak of a smooth curve sampled on a grid generally lies between samples; the vertex
    of the parabola through ``y[i-1], y[i], y[i+1]`` estimates its position to a fraction
    of the grid step.

    Parameters
    ----------
    y : ndarray
        Sampled curve (any units; pass a log-magnitude for spectral peaks).
    idx : ndarray of int
        Indices of local maxima in ``y``.  Peaks at the first/last sample are not refined.

    Returns
    -------
    offset : ndarray
        Fractional position offset in samples, in [-0.5, 0.5] (0 at the array ends).
    value : ndarray
        Curve value at the parabola vertex (``y[idx]`` where not refined).
    """
    idx = np.asarray(idx, dtype=int)
    offset = np.zeros(idx.shape, dtype=float)
    value = y[idx].astype(float)
    inner = (idx > 0) & (idx < y.size - 1)
    if inner.any():
        i = idx[inner]
        ym, y0, yp = y[i - 1], y[i], y[i + 1]
        denom = ym - 2.0 * y0 + yp
        with np.errstate(divide="ignore", invalid="ignore"):
            p = np.where(denom < 0, 0.5 * (ym - yp) / denom, 0.0)
        p = np.clip(p, -0.5, 0.5)
        offset[inner] = p
        value[inner] = y0 - 0.25 * (ym - yp) * p
    return offset, value
