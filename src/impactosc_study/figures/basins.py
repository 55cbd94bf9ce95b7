"""Basins of attraction over the plane of initial states (x0, v0) at phase 0.

Takes plain arrays and rows (read from the merged basin file and the fractions table by the
workflow script) and returns a matplotlib Figure: (a) the class of every cell with the
attractors' Poincare points, rest (0, 0) and the obstacle marked, the fractions in the legend;
(b) the forcing periods each cell needed until it was classified (slow near basin boundaries).
"""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt
from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import NullFormatter, ScalarFormatter

from impactosc.dynamics.basins import FAILED, UNRESOLVED
from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["basins_figure"]

MM = 1e3  # m -> mm
CM = 1 / 2.54
ATTRACTOR_COLORS = ["#6baed6", "#fd8d3c", "#74c476", "#9e9ac8", "#f768a1", "#fee391"]
ATTRACTOR_MARKERS = ["o", "^", "s", "D", "v", "P"]
UNRESOLVED_COLOR, FAILED_COLOR = "0.55", "k"


def basins_figure(x0, v0, classes, periods, attractors, fractions, rest, *, omega, x_obstacle=None):
    """Basin map of a class grid (rows v0, columns x0; codes as impactosc.dynamics.basins).

    attractors: the reference attractors (name, n_periods, impacts, Poincare points x, v);
    fractions: rows of basin_fractions (class, name, cells, fraction, se);
    rest: (class code, name) where rest (0, 0) lands; x_obstacle: xI (m), drawn dashed.
    """
    apply_style()
    k = len(attractors)
    colors = [FAILED_COLOR, UNRESOLVED_COLOR, *(ATTRACTOR_COLORS[i % len(ATTRACTOR_COLORS)] for i in range(k))]
    cmap = ListedColormap(colors)
    norm = BoundaryNorm(np.arange(FAILED - 0.5, k + 1.0), cmap.N)
    x = np.asarray(x0) * MM
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE, 8.0 * CM), sharey=True)
    axes[0].pcolormesh(x, v0, classes, cmap=cmap, norm=norm, shading="nearest", rasterized=True)
    p = np.asarray(periods, dtype=float)
    im = axes[1].pcolormesh(
        x, v0, p, cmap="viridis", norm=LogNorm(max(1.0, p.min()), max(2.0, p.max())), shading="nearest", rasterized=True
    )
    ticks = [t for t in (6, 10, 20, 30, 50, 100, 200, 400, 1000) if p.min() <= t <= p.max()]
    cb = fig.colorbar(im, ax=axes[1], ticks=ticks or None)
    cb.ax.yaxis.set_major_formatter(ScalarFormatter())
    cb.ax.yaxis.set_minor_formatter(NullFormatter())
    cb.set_label("forcing periods until classified")

    main = {r["class"]: r for r in fractions if not r["name"].startswith("unresolved,")}
    handles = []
    for i, a in enumerate(attractors):
        r = main[i + 1]
        impacts = f"{a.impacts} impact{'s' if a.impacts != 1 else ''} per {a.n_periods} T"
        label = f"{a.name} ({impacts}): {100 * r['fraction']:.1f} $\\pm$ {100 * r['se']:.1f} % of cells"
        handles.append(Patch(facecolor=colors[i + 2], edgecolor="none", label=label))
    for code, color in ((UNRESOLVED, UNRESOLVED_COLOR), (FAILED, FAILED_COLOR)):
        r = main.get(code)
        if r and r["cells"]:
            handles.append(
                Patch(facecolor=color, label=f"{r['name']}: {100 * r['fraction']:.1f} $\\pm$ {100 * r['se']:.1f} %")
            )
    for ax in axes:
        for i, a in enumerate(attractors):
            ax.plot(
                np.asarray(a.x) * MM, a.v, ATTRACTOR_MARKERS[i % len(ATTRACTOR_MARKERS)], ms=6 if i == 0 else 4,
                mfc=colors[i + 2] if i else "none", mec="k", mew=0.8, zorder=4,
            )  # fmt: skip
        ax.plot(0.0, 0.0, "*", ms=9, mfc="white", mec="k", mew=0.7, zorder=5)
        if x_obstacle is not None:
            ax.axvline(x_obstacle * MM, color="k", lw=0.6, ls="--", zorder=3)
        ax.set_xlabel(r"$x_0$ (mm)")
        ax.set_xlim(x[0], x[-1])
    handles += [
        Line2D([], [], ls="none", marker=ATTRACTOR_MARKERS[i % len(ATTRACTOR_MARKERS)], mfc=colors[i + 2] if i else "none",
               mec="k", ms=6 if i == 0 else 4, label=f"{a.name}: Poincare points")
        for i, a in enumerate(attractors)
    ]  # fmt: skip
    handles.append(Line2D([], [], ls="none", marker="*", mfc="white", mec="k", ms=9, label=f"rest (0, 0): {rest[1]}"))
    if x_obstacle is not None:
        handles.append(Line2D([], [], color="k", lw=0.6, ls="--", label=r"obstacle $x_I$ (right: starts in contact)"))
    axes[0].set_ylabel(r"$v_0$ (m/s)")
    n = int(np.asarray(classes).size)
    axes[0].set_title(f"(a) attractor reached, $\\omega$ = {omega:g} rad/s, {n} cells")
    axes[1].set_title("(b) periods until classified (early exit)")
    fig.legend(handles=handles, loc="outside lower center", ncols=2, frameon=False)
    return fig
