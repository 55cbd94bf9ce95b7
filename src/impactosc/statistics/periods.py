"""Period of a Poincare sequence and impacts per orbit: the readings every figure group shares.

Why a module of its own: the bifurcation diagrams, the periodic regime and the grazing all
ask "how many forcing periods until the orbit repeats, and how many impacts in one orbit?".
Kept as a leaf (numpy only, no import from the rest of the package) so that every reader
can use it without import cycles.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["NONPERIODIC", "FAILED", "detect_period", "poincare_period", "impacts_per_orbit"]

NONPERIODIC = 0  # period of a sequence that does not repeat within the record
FAILED = -1  # period of a w whose run was abandoned (see impactosc.dynamics.sweep)


def detect_period(points, tol, max_period: int | None = None, min_repeats: int = 3) -> int:
    """Smallest p with |y[i+p] - y[i]| <= tol for every i and component; 0 if there is none.

    Why: the period of a Poincare sequence in forcing periods is the diagram's main
    reading (1 on the main branch, 2, 4, ... after period doublings, 0 in chaos). A fixed
    tolerance is used rather than a relative one because settled orbits repeat to ~1e-13 m
    while distinct branch points lie micrometres to millimetres apart.

    Parameters
    ----------
    points : array_like, shape (n,) or (n, d)
        The sequence, e.g. x at the sections (m) or columns (x, v).
    tol : float or array_like of shape (d,)
        Largest allowed difference per component (units of the columns), > 0.
    max_period : int, optional
        Largest p tried; default n // min_repeats, so every phase of the orbit is seen at
        least `min_repeats` times (a long random record cannot pass by chance).
    min_repeats : int, default 3
        Used only for the default max_period.
    """
    y = np.asarray(points, dtype=float)
    if y.ndim == 1:
        y = y[:, None]
    if y.ndim != 2 or y.shape[0] < 2:
        raise ValueError(f"points must have shape (n,) or (n, d) with n >= 2, got {np.shape(points)}")
    if not np.all(np.isfinite(y)):
        raise ValueError("points must be finite (abandoned w values have no period to detect)")
    tol = np.broadcast_to(np.asarray(tol, dtype=float), (y.shape[1],))
    if not np.all(np.isfinite(tol)) or np.any(tol <= 0):
        raise ValueError(f"tol must be finite and > 0, got {tol}")
    if not isinstance(min_repeats, (int, np.integer)) or min_repeats < 2:
        raise ValueError(f"min_repeats must be an integer >= 2, got {min_repeats!r}")
    n = y.shape[0]
    max_period = n // min_repeats if max_period is None else int(max_period)
    if not 1 <= max_period < n:
        raise ValueError(f"max_period must be in [1, {n - 1}] for {n} points, got {max_period}")
    for p in range(1, max_period + 1):
        if np.all(np.abs(y[p:] - y[:-p]) <= tol):
            return p
    return NONPERIODIC


def poincare_period(x, v, x_tol: float = 1e-8, v_tol: float = 1e-6, max_period: int | None = None) -> int:
    """Smallest p with |x_{i+p} - x_i| <= x_tol and |v_{i+p} - v_i| <= v_tol for all i; 0 if none.

    Why: the period of the attractor in forcing periods (1 for the orbit before grazing,
    3 after it at w = 23.03); 0 marks a chaotic or not yet settled record. Default
    tolerances (10 nm, 1 um/s) are far above the integration error of the core and far
    below the Poincare-point spacing of the orbits here (tens of um).
    """
    x = np.asarray(x, dtype=float)
    v = np.asarray(v, dtype=float)
    if x.ndim != 1 or x.shape != v.shape or x.size < 2:
        raise ValueError(f"x and v must be 1-D of the same length >= 2, got {x.shape}, {v.shape}")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
        raise ValueError("x and v must be finite")
    max_period = x.size // 2 if max_period is None else int(max_period)
    max_period = max(1, min(max_period, x.size - 1))
    return int(detect_period(np.column_stack([x, v]), (x_tol, v_tol), max_period=max_period))


def impacts_per_orbit(impact_times, forcing_period: float, n_record: int, period: int) -> int:
    """Impacts in one orbit period (period forcing periods), counted over all whole orbits.

    Why count over many orbits: an impact that falls exactly on a window edge would make
    single windows differ by one; over K whole orbits the count is K q +- 1, so q =
    round(count / K) is exact for K >= 3. Times are measured from the start of the record
    (s), which is a Poincare time.
    """
    t = np.asarray(impact_times, dtype=float)
    if not (math.isfinite(forcing_period) and forcing_period > 0):
        raise ValueError(f"forcing_period must be finite and > 0 s, got {forcing_period}")
    if period < 1 or n_record < period:
        raise ValueError(f"need 1 <= period <= n_record, got period {period}, n_record {n_record}")
    k = n_record // period
    span = k * period * forcing_period
    count = int(np.count_nonzero((t >= 0) & (t < span * (1 - 1e-12))))
    return int(round(count / k))
