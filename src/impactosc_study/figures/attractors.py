"""The attractors along w: their Poincare points and the share of starts each takes.

Takes the surveys along w and the track of each attractor (impactosc.dynamics.attractor_continuation)
and returns a matplotlib Figure: (a) the Poincare x of every attractor at every w, coloured by its
track (the same attractor along w), with the w where Figs 2 and 3b differ marked; (b) the fractions
of the random starts stacked per track, unresolved and stopped starts in grey on top.
"""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt

from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["attractors_figure"]

MM = 1e3
COLORS = [c for i, c in enumerate(plt.get_cmap("tab10").colors) if i != 7]  # grey is for the unresolved
#: points drawn per non-periodic attractor and w (its recorded set holds about 1000)
CLOUD_POINTS = 150


def attractors_figure(surveys, track_ids, differing_omegas):
    apply_style()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(DOUBLE, 0.75 * DOUBLE), sharex=True, constrained_layout=True)
    for w in differing_omegas:
        for ax in (top, bottom):
            ax.axvline(w, color="0.85", lw=0.6, zorder=0)
    omegas = np.array([s.omega for s in surveys])
    tracks = sorted({t for ids in track_ids for t in ids})
    frac = np.zeros((len(tracks), omegas.size))
    other = np.zeros(omegas.size)
    for i, (s, ids) in enumerate(zip(surveys, track_ids)):
        n = s.labels.size
        for k, (a, t) in enumerate(zip(s.attractors, ids)):
            pts = a.points[:: max(1, a.points.shape[0] // CLOUD_POINTS)]
            top.plot(np.full(pts.shape[0], s.omega), pts[:, 0] * MM, ".", ms=3 if a.period else 0.8,
                     color=COLORS[t % len(COLORS)], zorder=3 if a.period else 2, rasterized=True)  # fmt: skip
            frac[tracks.index(t), i] = np.count_nonzero(s.labels == k + 1) / n
        other[i] = np.count_nonzero(s.labels <= 0) / n
    bottom.stackplot(omegas, *frac, other, colors=[*(COLORS[t % len(COLORS)] for t in tracks), "0.6"], step="mid")
    top.set_ylabel("Poincare x (mm)")
    bottom.set_ylabel("fraction of starts")
    bottom.set_xlabel("w (rad/s)")
    bottom.set_ylim(0, 1)
    bottom.set_xlim(omegas.min(), omegas.max())
    top.set_title(
        "(a) attractors found by recurrence (colour: one attractor followed along w; grey lines: Figs 2 and 3b differ)",
        loc="left",
        fontsize="small",
    )
    bottom.set_title(
        f"(b) basin fractions of {surveys[0].labels.size} random starts per w (grey: unresolved or stopped)",
        loc="left",
        fontsize="small",
    )
    return fig
