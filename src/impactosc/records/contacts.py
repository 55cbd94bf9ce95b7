"""Contacts of a sampled record: where each one starts and ends, and its penetration vertex.

Why a module: extraction (:mod:`impactosc.records.extract`) finds contacts the same way in a
record held in memory and in one read in chunks.
"""

from __future__ import annotations

import numpy as np

from impactosc.records.sample_fits import quadratic_fits


def _segment_argmax(x, start, stop):
    """Index of the (first) largest sample of x in each of the disjoint ranges [start, stop)."""
    size = stop - start
    if not size.size:
        return np.empty(0, int)
    offset = np.cumsum(size) - size  # where each range starts in the gathered samples
    seg = np.repeat(np.arange(size.size), size)
    pos = np.arange(size.sum()) - offset[seg] + start[seg]
    is_top = x[pos] == np.maximum.reduceat(x[pos], offset)[seg]
    hits = np.flatnonzero(is_top)
    return pos[hits[np.unique(seg[hits], return_index=True)[1]]]


def _peaks(t, x, j, half):
    """Vertex (time, value) of a quadratic through samples j-half..j+half (arrays of j).

    The sample itself where the window has fewer than 3 samples, the fit is not a maximum
    (noise-dominated) or the vertex lies outside the window.
    """
    lo, hi = np.maximum(0, j - half), np.minimum(x.size, j + half + 1)
    tp, xp = t[j].copy(), x[j].copy()
    f = np.flatnonzero(hi - lo >= 3)
    c, _ = quadratic_fits(t, x, lo[f], hi[f], t[j[f]])
    with np.errstate(divide="ignore", invalid="ignore"):
        s = -c[:, 1] / (2 * c[:, 2])
    use = (c[:, 2] < 0) & (np.abs(s) <= (t[hi[f] - 1] - t[lo[f]]) / 2)
    f, c, s = f[use], c[use], s[use]
    tp[f], xp[f] = t[j[f]] + s, c[:, 0] + c[:, 1] * s + c[:, 2] * s * s
    return tp, xp
