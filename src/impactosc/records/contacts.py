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


def hysteresis_contacts(x, xi, hyst, armed0=False):
    """Onsets and ends of the contacts in the samples x, with hysteresis.

    An onset is a sample at/above xi whose nearest earlier sample that is either armed (below
    xi - hyst; below xi when hyst is 0) or at/above xi is an armed one: after each onset the
    signal must re-arm before the next one counts.  ``armed0``: the state before the first
    sample (False at a record's start: the first contact counts only after an armed sample).
    Returns (onsets: the last sample before each onset, ends: the first armed sample after
    each onset or x.size when the contact has not ended, armed: whether the last marked sample
    is armed, i.e. the state after the last sample).
    """
    above = x >= xi
    armed = x < xi - hyst if hyst > 0 else ~above
    marked = np.flatnonzero(armed | above)
    is_up = above[marked]
    before = np.concatenate([[not armed0], is_up[:-1]])
    onsets = marked[is_up & ~before] - 1
    arm_idx = np.flatnonzero(armed)
    ends = np.append(arm_idx, x.size)[np.searchsorted(arm_idx, onsets + 1)]
    state = bool(armed[marked[-1]]) if marked.size else armed0
    return onsets, ends, state
