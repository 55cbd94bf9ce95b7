"""Chunked continuation: one sweep split into jobs that run side by side.

Why: continuation is sequential, yet a workflow wants many cores busy. A sweep is
split into contiguous chunks that run as separate jobs. Each chunk is seeded by a cheap
*coarse* sequential pass (every ``stride``-th w of the same grid, same per-w lengths), which
follows the same attractor: chunk k starts from the coarse pass's end state at the grid
point ``stride`` values before its first w and re-runs those ``stride - 1`` warm-up w values
(discarded), so its first recorded w is reached by the same small steps as in a sequential
sweep. ``tests/test_sweep_chunks.py`` checks chunked == sequential on a short range.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from impactosc.dynamics.sweep import _PER_W, SweepResult, SweepSettings, _check_omegas, continuation

__all__ = ["plan_chunks", "coarse_indices", "coarse_pass", "run_chunk", "merge_chunks", "sweep_chunked"]


def plan_chunks(n: int, n_chunks: int, stride: int) -> list[tuple[int, int]]:
    """Split indices 0..n-1 into n_chunks contiguous ranges [a, b) with every a a multiple of stride.

    Chunk starts sit on the coarse grid (indices 0, stride, 2 stride, ...) so every chunk
    k > 0 can be seeded from the coarse pass at index a - stride.
    """
    if not isinstance(stride, (int, np.integer)) or stride < 1:
        raise ValueError(f"stride must be an integer >= 1, got {stride!r}")
    if not isinstance(n_chunks, (int, np.integer)) or n_chunks < 1:
        raise ValueError(f"n_chunks must be an integer >= 1, got {n_chunks!r}")
    n_coarse = (n - 1) // stride + 1  # coarse points 0, stride, ... <= n-1
    if n_chunks > n_coarse:
        raise ValueError(
            f"{n_chunks} chunks need at least {n_chunks} coarse points; "
            f"n = {n} w values with stride {stride} give {n_coarse}"
        )
    starts = [stride * int(round(k * n_coarse / n_chunks)) for k in range(n_chunks)]
    return [(a, b) for a, b in zip(starts, [*starts[1:], n])]


def coarse_indices(n: int, stride: int) -> np.ndarray:
    """Fine-grid indices of the coarse pass: 0, stride, 2 stride, ..."""
    return np.arange(0, n, stride)


def coarse_pass(omegas, settings: SweepSettings, stride: int, progress=None, on_failure=None) -> SweepResult:
    """Sequential continuation over every stride-th w: the seeds of the chunks (cheap: 1/stride)."""
    w = _check_omegas(omegas)
    return continuation(w[coarse_indices(w.size, stride)], settings, progress=progress, on_failure=on_failure)


def run_chunk(
    omegas,
    settings: SweepSettings,
    chunk: tuple[int, int],
    stride: int,
    seeds: SweepResult | None,
    progress=None,
    on_failure=None,
) -> SweepResult:
    """The fine sweep over indices chunk = (a, b), seeded from the coarse pass.

    Chunk 0 starts like the sequential sweep (from settings.x0, v0); chunk a > 0 starts
    from the coarse end state at w[a - stride], re-runs w[a - stride + 1 .. a - 1] as
    warm-up and keeps w[a .. b - 1].
    """
    w = _check_omegas(omegas)
    a, b = chunk
    if not 0 <= a < b <= w.size:
        raise ValueError(f"chunk {chunk} outside the grid of {w.size} w values")
    if a == 0:
        return continuation(w[:b], settings, progress=progress, on_failure=on_failure)
    if a % stride:
        raise ValueError(f"chunk start {a} is not on the coarse grid (multiple of stride {stride})")
    if seeds is None:
        raise ValueError("chunks after the first need the coarse pass (seeds)")
    j = a // stride - 1
    if j >= len(seeds) or not math.isclose(seeds.omega[j], w[a - stride], rel_tol=0, abs_tol=1e-12):
        raise ValueError(
            f"seeds do not belong to this grid: coarse point {j} is w = "
            f"{seeds.omega[j] if j < len(seeds) else 'missing'}, expected {w[a - stride]}"
        )
    res = continuation(
        w[a - stride + 1 : b],
        settings,
        x0=seeds.x_end[j],
        v0=seeds.v_end[j],
        contact_v0=seeds.contact_v0_end[j],
        first_transient=settings.n_transient,
        progress=progress,
        on_failure=on_failure,
    )
    return res.subset(stride - 1, len(res))


def merge_chunks(chunks: Sequence[SweepResult]) -> SweepResult:
    """Concatenate chunk results (in sweep order) into one sweep."""
    if not chunks:
        raise ValueError("no chunks to merge")
    s = chunks[0].settings
    for c in chunks[1:]:
        if c.settings != s:
            raise ValueError("chunks were computed with different settings")
    offsets = [np.zeros(1, dtype=np.int64)]
    base = 0
    for c in chunks:
        offsets.append(c.impact_offsets[1:] + base)
        base += int(c.impact_offsets[-1])
    merged = SweepResult(
        poincare_x=np.concatenate([c.poincare_x for c in chunks]),
        poincare_v=np.concatenate([c.poincare_v for c in chunks]),
        impact_t=np.concatenate([c.impact_t for c in chunks]),
        impact_v=np.concatenate([c.impact_v for c in chunks]),
        impact_offsets=np.concatenate(offsets),
        settings=s,
        **{k: np.concatenate([getattr(c, k) for c in chunks]) for k in _PER_W},
    )
    _check_omegas(merged.omega)
    return merged


def sweep_chunked(omegas, settings: SweepSettings, n_chunks: int, stride: int) -> SweepResult:
    """In-process equivalent of the workflow's coarse pass + chunk jobs + merge."""
    w = _check_omegas(omegas)
    plan = plan_chunks(w.size, n_chunks, stride)
    seeds = coarse_pass(w, settings, stride) if n_chunks > 1 else None
    return merge_chunks([run_chunk(w, settings, c, stride, seeds) for c in plan])
