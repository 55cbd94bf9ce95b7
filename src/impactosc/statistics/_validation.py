"""Input checks shared by the statistics modules.

Every public function validates its arrays here so that bad input fails early with a
message that names the argument and the problem (empty, non-finite, unsorted, too short)
instead of surfacing later as a NaN or an obscure numpy error.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "as_finite_1d",
    "as_positive_1d",
    "as_event_times",
    "check_positive_scalar",
    "check_time_span",
]


def as_finite_1d(values, name: str, min_size: int = 1) -> np.ndarray:
    """Return ``values`` as a 1-D float array, or raise ValueError naming ``name``.

    Checks, in order: one-dimensional, not empty, at least ``min_size`` samples, all finite.
    """
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a one-dimensional array, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} is empty")
    if arr.size < min_size:
        raise ValueError(f"{name} has too few samples: need at least {min_size}, got {arr.size}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name} contains non-finite values (NaN or inf); first at index {i}: {arr[i]}")
    return arr


def as_positive_1d(values, name: str, min_size: int = 1) -> np.ndarray:
    """Like :func:`as_finite_1d`, and additionally require every value > 0."""
    arr = as_finite_1d(values, name, min_size)
    nonpos = arr <= 0
    if nonpos.any():
        i = int(np.flatnonzero(nonpos)[0])
        raise ValueError(f"{name} must be strictly positive; first non-positive value at index {i}: {arr[i]}")
    return arr


def as_event_times(times, name: str = "times", min_size: int = 1) -> np.ndarray:
    """Return event times as a finite, strictly increasing 1-D float array (seconds)."""
    arr = as_finite_1d(times, name, min_size)
    step = np.diff(arr)
    bad = step <= 0
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{name} must be strictly increasing; first violation at index {i}: "
            f"{name}[{i}]={arr[i]!r} >= {name}[{i + 1}]={arr[i + 1]!r}"
        )
    return arr


def check_positive_scalar(value, name: str) -> float:
    """Return ``value`` as a float, or raise ValueError if it is not finite and > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not np.isfinite(v) or v <= 0:
        raise ValueError(f"{name} must be finite and positive, got {value!r}")
    return v


def check_time_span(t_start, t_stop) -> tuple[float, float]:
    """Return the observation span ``(t_start, t_stop)`` in s, requiring t_stop > t_start."""
    a, b = float(t_start), float(t_stop)
    if not (np.isfinite(a) and np.isfinite(b)):
        raise ValueError(f"t_start and t_stop must be finite, got {t_start!r}, {t_stop!r}")
    if b <= a:
        raise ValueError(f"t_stop must be greater than t_start, got t_start={a}, t_stop={b}")
    return a, b
