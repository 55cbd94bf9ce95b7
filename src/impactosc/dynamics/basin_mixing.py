"""How mixed the basins are: basin entropy, boundary basin entropy and the fraction of boundary boxes.

Why: fractions say how much of the plane each attractor takes, not how predictable the outcome
of a start is. Daza et al. 2016 (Sci. Rep. 6, 31416) cover the plane with boxes, take in each box
i the fraction p_ij of its starts that reach attractor j and its entropy S_i = -sum_j p_ij log p_ij;
the basin entropy S_b is the mean of S_i over all boxes, the boundary basin entropy S_bb the mean
over the boxes with S_i > 0 (the boundary boxes). S_bb > log 2 is sufficient for a fractal
boundary (a smooth boundary between two basins gives at most log 2 per box); below it the test
says nothing. Every label is a colour, the unresolved and stopped starts too.

Boxes are n x n blocks of a grid (:func:`grid_boxes`) or the cells of a regular partition of a
rectangle for random starts (:func:`sample_boxes`); a box with fewer than `min_starts` starts
cannot show a mixture and is left out (counted in `skipped`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["BasinEntropy", "basin_entropy", "grid_boxes", "sample_boxes"]


@dataclass(frozen=True)
class BasinEntropy:
    """S_b, S_bb (nats), boundary boxes / boxes, and whether S_bb > log 2 (fractal boundary)."""

    entropy: float
    boundary_entropy: float
    boundary_fraction: float
    boxes: int
    boundary_boxes: int
    skipped: int

    @property
    def fractal(self) -> bool:
        return self.boundary_entropy > math.log(2)

    def to_dict(self) -> dict:
        return {**asdict(self), "fractal": self.fractal}


def basin_entropy(labels, boxes, min_starts: int = 2) -> BasinEntropy:
    """Daza's entropies of `labels` (one per start) over `boxes` (the box id of each start; starts
    with a negative id lie in no box)."""
    labels = np.asarray(labels).ravel()
    boxes = np.asarray(boxes).ravel()
    if labels.size == 0 or labels.shape != boxes.shape:
        raise ValueError(f"labels and boxes must be non-empty and of one size, got {labels.size} and {boxes.size}")
    if not isinstance(min_starts, (int, np.integer)) or min_starts < 1:
        raise ValueError(f"min_starts must be an integer >= 1, got {min_starts!r}")
    labels, boxes = labels[boxes >= 0], boxes[boxes >= 0]
    if labels.size == 0:
        raise ValueError("every start lies outside the boxes (box id < 0)")
    _, box = np.unique(boxes, return_inverse=True)
    _, colour = np.unique(labels, return_inverse=True)
    counts = np.zeros((box.max() + 1, colour.max() + 1))
    np.add.at(counts, (box, colour), 1)
    n = counts.sum(axis=1)
    kept = n >= min_starts
    p = counts[kept] / n[kept, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = -np.where(p > 0, p * np.log(p), 0.0).sum(axis=1)
    if s.size == 0:
        raise ValueError(f"no box holds {min_starts} starts: use larger boxes")
    boundary = s > 1e-12  # a box of one colour has S_i = 0 exactly; anything above is a mixture
    return BasinEntropy(
        float(s.mean()), float(s[boundary].mean()) if boundary.any() else 0.0, float(boundary.mean()),
        int(s.size), int(boundary.sum()), int((~kept).sum()),
    )  # fmt: skip


def grid_boxes(shape, size: int) -> np.ndarray:
    """Box ids of a grid of `shape` (rows, columns) in blocks of size x size cells (edges that do
    not fill a block are left out: id -1)."""
    if not isinstance(size, (int, np.integer)) or size < 1:
        raise ValueError(f"box size must be an integer >= 1 cells, got {size!r}")
    rows, cols = shape
    nr, nc = rows // size, cols // size
    if nr == 0 or nc == 0:
        raise ValueError(f"a grid of {rows} x {cols} cells holds no box of {size} x {size}")
    i, j = np.meshgrid(np.arange(rows) // size, np.arange(cols) // size, indexing="ij")
    return np.where((i < nr) & (j < nc), i * nc + j, -1)


def sample_boxes(points, lo, hi, n_boxes) -> np.ndarray:
    """Box ids of points in the rectangle [lo, hi] cut into n_boxes[k] equal parts along axis k."""
    pts = np.atleast_2d(np.asarray(points, dtype=float))
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    n = np.broadcast_to(np.asarray(n_boxes), lo.shape).astype(int)
    if pts.shape[1] != lo.size or hi.shape != lo.shape or np.any(hi <= lo) or np.any(n < 1):
        raise ValueError("points, lo, hi and n_boxes must agree in dimension, with lo < hi and n_boxes >= 1")
    k = np.clip(np.floor((pts - lo) / (hi - lo) * n).astype(int), 0, n - 1)
    return np.ravel_multi_index(tuple(k.T), tuple(n))
