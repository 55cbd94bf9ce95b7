"""Two-parameter diagrams: the 2-D map of the attractor's period over (w, xI or m0e), and the
bifurcation curves continued in those two parameters over it.

Every function takes plain arrays (read from the map and curve files by the workflow scripts)
and returns a matplotlib Figure.
"""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt

from impactosc_study.figures.bifurcation import CM, _period_class, _period_colors
from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["map2d_figure", "map2d_curves_figure"]

PARAMETER_LABELS = {"xI": r"obstacle $x_I$", "m0e": r"unbalance $m_0 e$"}


def map2d_figure(omega, values, period, rate, parameter: str, unit_scale: float, unit: str, marker=None):
    """2-D map: period (forcing periods) and impacts per forcing period over (w, parameter).

    period: (n_values, n_w) with 0 = non-periodic and -1 = abandoned; rate: same shape.
    marker: optional parameter value drawn as a dashed line (the paper's xI).
    """
    apply_style()
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE, 7.0 * CM), sharey=True)
    y = np.asarray(values) * unit_scale
    cmap, norm, labels = _period_colors()
    im = axes[0].pcolormesh(omega, y, _period_class(period), cmap=cmap, norm=norm, shading="nearest", rasterized=True)
    cb = fig.colorbar(im, ax=axes[0], ticks=np.arange(-1, 11))
    cb.ax.set_yticklabels(labels, fontsize=6)

    im2 = axes[1].pcolormesh(omega, y, np.asarray(rate), cmap="viridis", shading="nearest", rasterized=True)
    cb2 = fig.colorbar(im2, ax=axes[1])
    cb2.set_label("impacts per forcing period")
    for ax in axes:
        ax.set_xlabel(r"$\omega$ (rad/s)")
        if marker is not None:
            ax.axhline(marker * unit_scale, color="tab:red", lw=0.7, ls="--")
    axes[0].set_ylabel(f"{PARAMETER_LABELS.get(parameter, parameter)} ({unit})")
    axes[0].set_title(r"period in forcing periods (rows followed in increasing $\omega$)")
    axes[1].set_title("impact rate")
    return fig


CURVE_COLORS = {"grazing": "tab:green", "period_doubling": "tab:red", "fold": "k"}
CURVE_DASHES = ["-", "--", "-.", ":"]  # the k-th curve of one kind


def map2d_curves_figure(omega, values, period, curves, parameter: str, unit_scale: float, unit: str, marks=()):
    """The map's period (as :func:`map2d_figure`, left panel) with two-parameter curves over it.

    curves: {label: (kind, w, value, codim_w, codim_value)}, each curve's points in order and its
    codimension-two points (drawn as stars); marks: (w, value) points such as the paper's scenes,
    drawn as white circles, with a dotted line along the first mark's value. Outside the map's
    grid the axes are light grey."""
    apply_style()
    fig, ax = plt.subplots(figsize=(DOUBLE, 9.0 * CM))
    ax.set_facecolor("0.85")
    cmap, norm, labels = _period_colors()
    im = ax.pcolormesh(omega, np.asarray(values) * unit_scale, _period_class(period), cmap=cmap, norm=norm,
                       shading="nearest", rasterized=True)  # fmt: skip
    cb = fig.colorbar(im, ax=ax, ticks=np.arange(-1, 11))
    cb.ax.set_yticklabels(labels, fontsize=6)
    cb.set_label("period of the attractor (forcing periods)")
    seen = {}
    for label, (kind, w, v, cw, cv) in curves.items():
        k = seen[kind] = seen.get(kind, -1) + 1
        ax.plot(w, np.asarray(v) * unit_scale, color=CURVE_COLORS.get(kind, "tab:purple"),
                ls=CURVE_DASHES[k % len(CURVE_DASHES)], lw=1.2, label=label)  # fmt: skip
        if len(cw):
            ax.plot(cw, np.asarray(cv) * unit_scale, "*", color="gold", mec="k", mew=0.5, ms=9)
    if any(len(c[3]) for c in curves.values()):
        ax.plot([], [], "*", color="gold", mec="k", mew=0.5, ms=9, label="codimension two")
    if marks:
        ax.axhline(marks[0][1] * unit_scale, color="w", lw=0.6, ls=":")
        ax.plot([w for w, _ in marks], [v * unit_scale for _, v in marks], "o", mfc="w", mec="k", ms=4,
                label="the paper's scenes")  # fmt: skip
    w_min = min([float(np.min(omega))] + [float(np.min(c[1])) for c in curves.values() if len(c[1])])
    ax.set_xlim(w_min - 0.2, float(np.max(omega)) + 0.2)
    ax.set_ylim(np.min(values) * unit_scale, np.max(values) * unit_scale)
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(f"{PARAMETER_LABELS.get(parameter, parameter)} ({unit})")
    name = PARAMETER_LABELS.get(parameter, parameter)
    ax.set_title(rf"bifurcation curves continued in ($\omega$, {name}) over the 2-D map")
    ax.legend(loc="upper center", fontsize=6, framealpha=0.85)  # over the period-1 region, uniform
    return fig
