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

__all__ = ["map2d_figure", "map2d_curves_figure", "curves_band_figure"]

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


def curves_band_figure(curves: dict, bands: dict, parameter: str, unit_scale: float, unit: str, *, own, model: str):
    """Two-parameter curves, each with its band: w* +- 2 se as horizontal bars at the band's
    points and as thin lines through their ends (left), and 2 se itself against the parameter
    (right: at a diagram's scale a band of micro-rad/s is thinner than its line). ``curves``,
    ``bands``: the workflow's curve and band files by name; ``own``: the model's value of the
    parameter, dotted."""
    apply_style()
    fig, (ax, width) = plt.subplots(1, 2, figsize=(DOUBLE, 9.0 * CM), sharey=True, width_ratios=[3, 1])
    for name, curve in curves.items():
        color = CURVE_COLORS.get(curve["kind"], "tab:purple")
        w = [p["omega"] for p in curve["points"]]
        v = np.array([p["value"] for p in curve["points"]]) * unit_scale
        ax.plot(w, v, color=color, lw=1.0, label=name.replace("_", " "))
        band = bands[name]
        bw, bv, se = (
            np.array([np.nan if x is None else x for x in band[k]], dtype=float) for k in ("omega", "value", "se")
        )
        ok = np.isfinite(se)
        ax.errorbar(bw[ok], bv[ok] * unit_scale, xerr=2 * se[ok], fmt="none", ecolor=color, elinewidth=0.8, capsize=2)
        for sign in (-1, 1):
            ax.plot(bw[ok] + sign * 2 * se[ok], bv[ok] * unit_scale, color=color, lw=0.5, ls=":")
        width.plot(2 * se[ok], bv[ok] * unit_scale, "o-", color=color, ms=2, lw=0.8)
        codim = curve.get("codim_two", [])
        if codim:
            ax.plot([c["omega"] for c in codim], [c["value"] * unit_scale for c in codim], "*", color="gold", mec="k",
                    mew=0.5, ms=9)  # fmt: skip
    for a in (ax, width):
        a.axhline(own * unit_scale, color="0.4", lw=0.6, ls=":")
    ax.errorbar([], [], xerr=[], fmt="none", ecolor="0.3", capsize=2, label=r"$\omega^* \pm 2$ se")
    ax.set_xlabel(r"$\omega$ (rad/s)")
    name = PARAMETER_LABELS.get(parameter, parameter)
    ax.set_ylabel(f"{name} ({unit})")
    ax.set_title(rf"bifurcation curves in ($\omega$, {name}) of {model}, $\pm 2$ se from its covariance", fontsize=8)
    ax.legend(loc="best", fontsize=6, framealpha=0.85)
    width.set_xscale("log")
    width.set_xlabel(r"2 se of $\omega^*$ (rad/s)")
    width.set_title("the band's width", fontsize=8)
    return fig
