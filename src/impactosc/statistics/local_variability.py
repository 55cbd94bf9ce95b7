"""Local interval variability (CV2, LV, LvR) and the serial correlations of the intervals.

Why: C_V^2 = var(S)/mean(S)^2 compares every interval with the train's overall mean, so a
drifting rate (a rig warming up, a slow change of w) inflates it. The local measures compare
each interval with its neighbour only and stay valid when the rate drifts; they are what
spike-train analysis reports, so a rig's train and the model's can be set beside neural data:

* :func:`holt_cv2`  Holt et al. 1996: mean of ``2 |S_{i+1} - S_i| / (S_{i+1} + S_i)``
* :func:`local_variation`  LV, Shinomoto et al. 2003: ``3/(n-1) sum ((S_i - S_{i+1}) / (S_i + S_{i+1}))^2``
* :func:`revised_local_variation`  LvR, Shinomoto et al. 2009, with a refractoriness R (s)
* :func:`serial_correlation`  Pearson correlation of ``(S_i, S_{i+k})`` for lags k = 1..K

All three local measures are 1 for a Poisson train and 0 for a periodic one; the definitions
are Elephant's (``elephant.statistics.cv2``, ``lv``, ``lvr``), against which the tests check them.
"""

from __future__ import annotations

import numpy as np

from impactosc.statistics._validation import as_positive_1d

__all__ = [
    "DEFAULT_REFRACTORINESS",
    "holt_cv2",
    "local_variation",
    "revised_local_variation",
    "serial_correlation",
]

#: LvR's refractoriness constant R in s: 5 ms, Shinomoto et al. 2009's choice and Elephant's default.
DEFAULT_REFRACTORINESS = 5e-3


def _neighbour_ratio(S) -> np.ndarray:
    """``(S_{i+1} - S_i) / (S_{i+1} + S_i)`` for the n - 1 neighbouring pairs (n >= 2 intervals)."""
    s = as_positive_1d(S, "intervals", min_size=2)
    return np.diff(s) / (s[:-1] + s[1:])


def holt_cv2(S) -> float:
    """Holt's CV2: the mean of ``2 |S_{i+1} - S_i| / (S_{i+1} + S_i)`` (dimensionless).

    Why: a local CV, each interval compared with the next only, so slow rate changes do not
    count as irregularity (Holt et al. 1996). Needs at least 2 intervals (3 events).
    """
    return float(2.0 * np.mean(np.abs(_neighbour_ratio(S))))


def local_variation(S) -> float:
    """Shinomoto's local variation LV = ``3/(n-1) sum ((S_i - S_{i+1}) / (S_i + S_{i+1}))^2``.

    Why: like CV2 it is local, and it separates regular (LV < 1), Poisson (1) and bursty (> 1)
    firing more sharply (Shinomoto et al. 2003). Needs at least 2 intervals.
    """
    return float(3.0 * np.mean(np.square(_neighbour_ratio(S))))


def revised_local_variation(S, refractoriness: float = DEFAULT_REFRACTORINESS) -> float:
    """LvR (Shinomoto et al. 2009): ``3/(n-1) sum (1 - 4 S_i S_{i+1} / (S_i + S_{i+1})^2) (1 + 4 R / (S_i + S_{i+1}))``.

    Why: LV with a refractory period R (s) taken out, which makes it nearly invariant to the
    rate; R = 5 ms is the published choice (and Elephant's default), an impact train's own
    dead time may differ. Needs at least 2 intervals.
    """
    r = float(refractoriness)
    if not np.isfinite(r) or r < 0:
        raise ValueError(f"the refractoriness R must be finite and >= 0 s, got {refractoriness!r}")
    s = as_positive_1d(S, "intervals", min_size=2)
    total = s[:-1] + s[1:]
    first = 1.0 - 4.0 * s[:-1] * s[1:] / total**2
    return float(3.0 / (s.size - 1) * np.sum(first * (1.0 + 4.0 * r / total)))


def serial_correlation(S, max_lag: int = 10) -> np.ndarray:
    """Serial correlation coefficients of the intervals at lags 1..max_lag.

    Why: the local measures and C_V^2 see only the interval distribution's spread; a chaotic
    train's intervals are ordered (short ones follow long ones), which these coefficients show.
    Lag k is Pearson's r of the pairs ``(S_i, S_{i+k})``, i = 1..n-k (each member's own mean and
    spread), so it is bounded by 1 and equals ``numpy.corrcoef`` of the two shifted copies.
    The paper's eq. (3) ACF (:func:`impactosc.statistics.acf.autocorrelation`) uses the overall
    mean with an n/(n-k+1) factor instead, and differs from it by O(1/n).

    Returns
    -------
    ndarray, shape (max_lag,)
        The coefficient at lag 1, 2, ..., max_lag (dimensionless).
    """
    k_max = int(max_lag)
    if k_max < 1:
        raise ValueError(f"max_lag must be >= 1, got {max_lag}")
    # three pairs at the largest lag at least: with two, r is always +-1
    s = as_positive_1d(S, "intervals", min_size=k_max + 3)
    out = np.empty(k_max)
    for k in range(1, k_max + 1):
        if np.ptp(s[:-k]) == 0 or np.ptp(s[k:]) == 0:
            raise ValueError(f"the intervals are constant at lag {k}: their serial correlation is undefined")
        a = s[:-k] - s[:-k].mean()
        b = s[k:] - s[k:].mean()
        out[k - 1] = np.dot(a, b) / np.sqrt(np.dot(a, a) * np.dot(b, b))
    return out
