"""The benchmark scene every speed comparison shares, and how its error is measured.

The paper's chaotic scene: w = 40.86 rad/s, model BC, from rest; 100 s of transient then
400 s whose impacts are counted (about 2900: on the attractor or not). Accuracy is the
impact-time error over the first 1.5 s (before chaos amplifies differences) against SciPy
DOP853 split at contacts at rtol 1e-13.
"""

from __future__ import annotations

import math

import numpy as np

OMEGA, TRANSIENT, DURATION, ERR_HORIZON = 40.86, 100.0, 400.0, 1.5


def impact_error(times, ref_times) -> float:
    """max |t - t_ref| over the impacts; inf when the counts differ (an impact missed or invented)."""
    n = min(len(times), len(ref_times))
    if n == 0 or len(times) != len(ref_times):
        return math.inf
    return float(np.abs(np.asarray(times[:n]) - ref_times[:n]).max())
