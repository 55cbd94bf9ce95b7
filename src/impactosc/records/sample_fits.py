"""What extraction and the obstacle estimate both read off a record's samples: the sensor-noise
level, and batched local quadratic fits.

Why a module: event extraction (:mod:`impactosc.records.extract`) and the estimate of the
obstacle position (:mod:`impactosc.records.obstacle_estimate`) fit the same local quadratics
to the same noisy samples, and scale their thresholds by the same noise estimate.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["estimate_noise", "quadratic_fits"]


def estimate_noise(x) -> float:
    """Sensor-noise std (m) from the MAD of the second difference (see :mod:`impactosc.records.extract`).

    The MAD over Phi^-1(3/4) = 0.674489... is a Gaussian std (scipy.stats.median_abs_deviation
    with scale="normal"; written out here: importing scipy.stats costs a second per process).
    """
    d2 = np.diff(np.asarray(x, dtype=float), 2)
    return float(np.median(np.abs(d2 - np.median(d2))) / _PHI_INV_3_4 / math.sqrt(6.0))


#: Phi^-1(3/4), the MAD of a standard normal variable.
_PHI_INV_3_4 = 0.6744897501960817


def quadratic_fits(t, x, lo, hi, t0):
    """Quadratic LS fits of x over samples lo..hi-1 in s = t - t0, one per entry of lo, hi, t0.

    Why batched: extraction fits two quadratics per impact (tens of thousands per record);
    one stacked solve avoids numpy's per-call overhead.  Windows shorter than the longest
    are padded with zero rows, which add nothing to the normal equations.  Returns the
    coefficients (c0, c1, c2), shape (m, 3), and their covariance / sigma^2, shape (m, 3, 3).
    """
    width = int(np.max(hi - lo, initial=0))
    k = lo[:, None] + np.arange(width)
    inside = k < hi[:, None]
    k = np.where(inside, k, lo[:, None])
    s = np.where(inside, t[k] - t0[:, None], 0.0)
    A = np.stack([inside.astype(float), s, s * s], axis=-1)
    At = A.transpose(0, 2, 1)
    ata_inv = np.linalg.inv(At @ A)
    return (ata_inv @ (At @ np.where(inside, x[k], 0.0)[..., None]))[..., 0], ata_inv
