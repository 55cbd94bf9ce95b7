"""Compile (or load from numba's on-disk cache) the kernels of record extraction, of the obstacle
estimate and of the statistics' mixture fits, on synthetic data, without the core.

Why: every workflow job that reads a record would otherwise compile these kernels itself (about
12 s of CPU each), several of them at once into an empty cache; one job compiles them first,
beside the core's own compile (rule numba_cache_kernels), and the others load them.
"""

from __future__ import annotations

import time

import numpy as np

__all__ = ["warm_up_kernels"]


def warm_up_kernels() -> float:
    """Compile (or load) the kernels; returns the seconds it took.

    The record is a forced oscillation cut by a stiff wall at x = -2 mm (20 s at 2 kHz with 5 um
    of noise): enough impacts for the extraction, the contact-law fit of the obstacle estimate
    and a two-component fit of its intervals to run every kernel they compile.
    """
    from impactosc.records.extract import ExtractOptions, extract_events
    from impactosc.records.obstacle_estimate import estimate_x_impact
    from impactosc.records.record import Record
    from impactosc.statistics.mixture import fit_mixture

    t0 = time.perf_counter()
    rate, omega, wall = 2000.0, 40.86, -2.0e-3
    t = np.arange(0.0, 20.0, 1.0 / rate)
    free = -3.0e-3 + 1.5e-3 * np.sin(omega * t) + 0.3e-3 * np.sin(0.5 * omega * t + 1.0)
    x = np.where(free > wall, wall + 0.02 * (free - wall), free)
    x = x + np.random.default_rng(0).normal(0.0, 5e-6, t.size)
    events, _ = extract_events(Record(t, x, omega, {"x_impact": wall}, None), None, ExtractOptions())
    estimate_x_impact(Record(t, x, omega, {}, None))
    intervals = np.diff(events["impacts"]["t"])
    for family in ("gaussian", "lognormal", "gamma"):
        fit_mixture(intervals, family, n_components=2, n_restarts=1)
    return time.perf_counter() - t0
