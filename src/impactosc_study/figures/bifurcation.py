"""Bifurcation diagrams (paper Figs 2 and 3b, the hysteresis overlay and the 2-D map).

Every function takes plain arrays (read from sweep files and the diagram reading by the
workflow scripts) and returns a matplotlib Figure. A diagram holds ~10^5 points, so the
point layers are rasterised (the PDF stays small, axes and labels stay vector) and drawn
as small dots that keep separate branches apart at print size.
"""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt
from matplotlib.colors import BoundaryNorm, ListedColormap

from impactosc_study.figures.style import DOUBLE, apply_style
from impactosc_study.figures.uncertainty import band_width_panel, draw_bands, draw_point_errors, points_text

MM = 1e3  # m -> mm
CM = 1 / 2.54

__all__ = [
    "diagram_panel",
    "mark_transitions",
    "mark_abandoned",
    "period_strip",
    "fig02_poincare",
    "fig03b_isi",
    "overlay_figure",
    "studies_figure",
]

# Colours of the sweep directions wherever two are drawn together.
DIRECTION_COLORS = {"increasing": "tab:blue", "decreasing": "tab:orange"}
MARK_STYLE = {
    "period doubling": ("v", "tab:red"),
    "grazing": ("v", "tab:green"),
    "impact adding": ("v", "tab:purple"),
    "non-periodic boundary": ("v", "0.45"),
}


def diagram_panel(ax, w, y, *, color="k", size=0.6, alpha=1.0, label=None):
    """Points (w, y) of a bifurcation diagram: tiny rasterised dots."""
    w = np.asarray(w, dtype=float)
    y = np.asarray(y, dtype=float)
    if w.shape != y.shape:
        raise ValueError(f"w and y differ in shape: {w.shape}, {y.shape}")
    ax.scatter(w, y, s=size, c=color, marker=".", linewidths=0, alpha=alpha, rasterized=True, label=label)


def mark_transitions(ax, marks, *, legend=True, loc="lower right", anchor=None):
    """Small triangles on the top edge at the detected transitions.

    marks: iterable of (w, kind) with kind a key of MARK_STYLE (others are skipped).
    """
    seen = set()
    for w, kind in marks:
        if kind not in MARK_STYLE:
            continue
        m, c = MARK_STYLE[kind]
        ax.plot(
            [w],
            [1.0],
            marker=m,
            color=c,
            ms=4,
            transform=ax.get_xaxis_transform(),
            clip_on=False,
            ls="none",
            label=kind if kind not in seen else None,
            zorder=6,
        )
        seen.add(kind)
    if legend and seen:
        ax.legend(
            loc=loc,
            bbox_to_anchor=anchor,
            frameon=True,
            framealpha=0.9,
            handletextpad=0.2,
            borderpad=0.3,
            fontsize=6,
            markerscale=1.0,
        )


def mark_abandoned(ax, omegas, label=True):
    """Grey ticks on the bottom edge at w values whose run was abandoned (no points there)."""
    omegas = np.asarray(omegas, dtype=float)
    if omegas.size == 0:
        return
    ax.plot(
        omegas,
        np.zeros_like(omegas),
        marker="|",
        ls="none",
        color="0.55",
        ms=5,
        mew=0.6,
        transform=ax.get_xaxis_transform(),
        clip_on=False,
        zorder=6,
        label=f"no result ({omegas.size} w, see caption)" if label else None,
    )


def _poincare_axes(ax, w, x, x_obstacle, title, marks=(), color="k", abandoned=()):
    diagram_panel(ax, w, np.asarray(x) * MM, color=color)
    if x_obstacle is not None:
        ax.axhline(x_obstacle * MM, color="tab:red", lw=0.6, ls="--")
        ax.text(
            0.5,
            x_obstacle * MM,
            r"obstacle $x_I$",
            color="tab:red",
            transform=ax.get_yaxis_transform(),
            va="bottom",
            ha="center",
            fontsize=6,
        )
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(r"$x$ at $\varphi = 2\pi i$ (mm)")
    ax.set_title(title)
    mark_abandoned(ax, abandoned)
    mark_transitions(ax, marks, loc="lower left", anchor=(0.42, 0.01))


def fig02_poincare(w, x, x_obstacle, *, experimental=None, marks=(), abandoned=(), model="model BC", uncertainty=None):
    """Fig 2: Poincare diagrams at increasing w, measured (left) and numerical (right).

    experimental: None or (w, x, label) of a measured (or clearly labelled surrogate)
    diagram; without one the left panel says where to supply it. model: the numerical
    panel's model, as :func:`impactosc_study.figures.model_label` names it. uncertainty: the
    predictions of a model with a covariance (:mod:`.uncertainty`): its branches as bands, its
    points as w +- 2 se, the band's width and the points listed below.
    """
    apply_style()
    if uncertainty:
        fig = plt.figure(figsize=(DOUBLE, 10 * CM))
        grid = fig.add_gridspec(2, 2, height_ratios=[3, 1.2])
        left = fig.add_subplot(grid[0, 0])
        right = fig.add_subplot(grid[0, 1], sharey=left)
        draw_bands(right, uncertainty, "poincare_x", MM)
        draw_point_errors(right, uncertainty, (np.min(w), np.max(w)))  # in the transitions' legend
    else:
        fig, (left, right) = plt.subplots(1, 2, figsize=(DOUBLE, 6.5 * CM), sharey=True)
    if experimental is not None:
        we, xe, label = experimental
        _poincare_axes(left, we, xe, x_obstacle, label)
    else:
        left.set_title("experimental (not supplied)")
        left.text(
            0.5,
            0.5,
            "no measured record configured\n(config: bifurcation.fig02.experimental)",
            ha="center",
            va="center",
            transform=left.transAxes,
            fontsize=7,
            color="0.4",
        )
        left.set_xlabel(r"$\omega$ (rad/s)")
        left.set_ylabel(r"$x$ at $\varphi = 2\pi i$ (mm)")
        left.set_xlim(np.min(w), np.max(w))
    _poincare_axes(
        right,
        w,
        x,
        x_obstacle,
        model + r", increasing $\omega$, $x_I = %.3f$ mm" % (x_obstacle * MM),
        marks,
        abandoned=abandoned,
    )
    right.tick_params(labelleft=True)
    right.set_xlim(np.min(w), np.max(w))
    if uncertainty:
        band_width_panel(fig.add_subplot(grid[1, 1], sharex=right), uncertainty, "poincare_x", 1e6, "µm")
        points_text(fig.add_subplot(grid[1, 0]), uncertainty, model)
    return fig


def fig03b_isi(w, s, *, marks=(), zoom=None, start=None, axes=None, uncertainty=None, model="the model"):
    """Fig 3b: ISI diagram S_j against w (decreasing w), with an optional zoomed panel.

    zoom: None or (w_lo, w_hi) drawn as a second panel (e.g. around the grazing);
    start: the first w of the sweep, marked with an arrow showing the direction;
    axes: existing axes to draw into (one, or two with a zoom), e.g. inside Fig 3;
    uncertainty, model: as for :func:`fig02_poincare`.
    """
    apply_style()
    below = None
    if axes is not None:
        fig = axes[0].figure
    elif uncertainty:
        fig = plt.figure(figsize=(DOUBLE, 10 * CM))
        grid = fig.add_gridspec(2, 2, height_ratios=[3, 1.2], width_ratios=[2.2, 1])
        axes = [fig.add_subplot(grid[0, 0]), *([fig.add_subplot(grid[0, 1])] if zoom is not None else [])]
        below = [fig.add_subplot(grid[1, 0], sharex=axes[0]), fig.add_subplot(grid[1, 1])]
    elif zoom is None:
        fig, ax = plt.subplots(figsize=(DOUBLE, 6.5 * CM))
        axes = [ax]
    else:
        fig, axes = plt.subplots(1, 2, figsize=(DOUBLE, 6.5 * CM), width_ratios=[2.2, 1])
    ax = axes[0]
    if uncertainty:
        for a, span in zip(axes, [(np.min(w), np.max(w)), zoom]):
            draw_bands(a, uncertainty, "isis", label=a is ax)
            draw_point_errors(a, uncertainty, span, label=a is ax)  # in the transitions' legend
    diagram_panel(ax, w, s)
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(r"$S_j$ (s)")
    ax.set_title(r"inter-impact intervals, decreasing $\omega$")
    ax.set_xlim(np.min(w), np.max(w))
    ax.set_ylim(0, None)
    mark_transitions(ax, marks, loc="upper center")
    if start is not None:
        ax.annotate(
            "",
            xy=(start - 0.06 * (np.max(w) - np.min(w)), 0.03),
            xytext=(start, 0.03),
            xycoords=("data", "axes fraction"),
            arrowprops=dict(arrowstyle="->", lw=0.8, color="0.3"),
        )
    if zoom is not None:
        lo, hi = zoom
        sel = (w >= lo) & (w <= hi)
        z = axes[1]
        diagram_panel(z, w[sel], s[sel], size=1.5)
        z.set_xlim(lo, hi)
        z.set_ylim(0, None)
        z.set_xlabel(r"$\omega$ (rad/s)")
        z.set_title("zoom: grazing")
        mark_transitions(z, [(m, k) for m, k in marks if lo <= m <= hi], legend=False)
        ax.axvspan(lo, hi, facecolor="0.93", edgecolor="0.6", lw=0.5, zorder=0)
    if below is not None:
        band_width_panel(below[0], uncertainty, "isis", 1e3, "ms")
        points_text(below[1], uncertainty, model)
    return fig


MARKED = ("period doubling",)


def marks_of(summary):
    """(w, kind) of the transitions worth a mark in a diagram: period doublings and grazings."""
    out = []
    for t in summary["transitions"]:
        if t["is_grazing"]:
            out.append((t["omega"], "grazing"))
        elif t["kind"] in MARKED:
            out.append((t["omega"], t["kind"]))
    return out


def fig03b_arguments(res, attrs, summary, zoom_near, zoom_half_width):
    """(w, S, keyword arguments) of fig03b_isi from a sweep and its reading.

    Shared by the stand-alone Fig 3b and the two-panel Fig 3; the zoom is centred on the
    grazing nearest to `zoom_near` (rad/s), when the reading found one.
    """
    w, s = res.isi_points()
    zoom = None
    if summary["grazings"]:
        g = min(summary["grazings"], key=lambda g: abs(g["omega_zero"] - zoom_near))
        zoom = (g["omega_zero"] - zoom_half_width, g["omega_zero"] + zoom_half_width)
    return w, s, dict(marks=marks_of(summary), zoom=zoom, start=float(attrs["grid_start"]))


def period_strip(ax, rows):
    """One horizontal band per sweep, coloured by the period read at each w.

    rows: list of (label, omega, period) with period as in impactosc.statistics.periods
    (NONPERIODIC = 0: non-periodic, FAILED = -1: no result).
    """
    cmap, norm, _labels = _period_colors()
    for k, (_label, w, p) in enumerate(rows):
        order = np.argsort(w)
        w, p = np.asarray(w)[order], np.asarray(p)[order]
        edges = np.concatenate([[w[0]], 0.5 * (w[1:] + w[:-1]), [w[-1]]])
        ax.pcolormesh(edges, [k - 0.4, k + 0.4], _period_class(p)[None, :], cmap=cmap, norm=norm, rasterized=True)
    ax.set_yticks(range(len(rows)), [r[0] for r in rows])
    ax.set_ylim(-0.6, len(rows) - 0.4)
    handles = [
        plt.Rectangle((0, 0), 1, 1, facecolor=cmap(norm(v)), edgecolor="0.5", lw=0.4) for v in (1, 2, 3, 4, 5, 0, -1)
    ]
    ax.legend(
        handles,
        ["period 1", "2", "3", "4", "5", "non-periodic", "no result"],
        ncols=7,
        fontsize=6,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.95),
        frameon=False,
        handlelength=1.0,
        columnspacing=0.8,
    )


def overlay_figure(sweeps, x_obstacle, *, windows=()):
    """Both sweep directions on one diagram (Poincare x and ISIs) and the period each reads.

    sweeps: list of (label, w_poincare, x, w_isi, s, direction, omega, period) with
    direction in DIRECTION_COLORS; windows: (w_lo, w_hi) intervals where the directions
    settle on different attractors (hysteresis), shaded.
    """
    apply_style()
    fig, axes = plt.subplots(3, 1, figsize=(DOUBLE, 13.0 * CM), sharex=True, height_ratios=[3, 3, 0.8])
    lo = max(np.min(sw[6]) for sw in sweeps)
    hi = min(np.max(sw[6]) for sw in sweeps)
    sizes = [1.2, 0.35]  # the second direction drawn smaller on top, so both stay visible
    for k, (label, wp, x, wi, s, direction, _, _) in enumerate(sweeps):
        color = DIRECTION_COLORS[direction]
        keep = (wp >= lo) & (wp <= hi)
        diagram_panel(axes[0], wp[keep], x[keep] * MM, color=color, size=sizes[min(k, 1)])
        keep = (wi >= lo) & (wi <= hi)
        diagram_panel(axes[1], wi[keep], s[keep], color=color, size=sizes[min(k, 1)])
        axes[0].plot([], [], "o", ms=3, color=color, label=label)
    for a, b in windows:
        for ax in axes[:2]:
            ax.axvspan(a - 0.01, b + 0.01, color="0.85", zorder=0, lw=0)
    if windows:
        axes[0].fill_between([], [], color="0.85", label="directions settle differently")
    axes[0].axhline(x_obstacle * MM, color="tab:red", lw=0.6, ls="--")
    axes[0].set_ylabel(r"$x$ at $\varphi = 2\pi i$ (mm)")
    axes[0].legend(loc="lower left", fontsize=6, frameon=True, framealpha=0.9)
    axes[0].set_title("increasing and decreasing sweeps over their common range")
    axes[1].set_ylabel(r"$S_j$ (s)")
    axes[1].set_ylim(0, None)
    period_strip(axes[2], [(sw[0].split(" ")[0], sw[6], sw[7]) for sw in sweeps])
    axes[2].set_xlabel(r"$\omega$ (rad/s)")
    axes[2].set_xlim(lo, hi)
    return fig


# Colours of the studies in a comparison: this study, then the other one.
STUDY_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red")
# each later layer drawn smaller on top of the earlier ones, so that all stay visible
STUDY_SIZES = (1.2, 0.35, 0.2)
STUDY_QUANTITIES = {
    "poincare": (MM, r"$x$ at $\varphi = 2\pi i$ (mm)", "Poincare points"),
    "isi": (1.0, r"$S_j$ (s)", "inter-impact intervals"),
}


def studies_figure(layers, quantity, *, title=""):
    """Several studies' (or models') diagrams over each other (Fig 2's Poincare points or Fig 3b's
    ISIs) and the period each reads, drawn as :func:`overlay_figure` draws two sweep directions.

    layers: list of (label, w, y, x_obstacle, omega, period), this study first: y the Poincare
    x (m) for quantity "poincare" (each study's obstacle a dashed line of its colour) or the
    ISIs (s) for "isi"; omega, period the diagram reading per w (as period_strip takes them).
    """
    scale, ylabel, what = STUDY_QUANTITIES[quantity]
    apply_style()
    fig, axes = plt.subplots(2, 1, figsize=(DOUBLE, 9.5 * CM), sharex=True, height_ratios=[3, 0.8])
    for k, (label, w, y, x_obstacle, _, _) in enumerate(layers):
        color = STUDY_COLORS[k % len(STUDY_COLORS)]
        diagram_panel(axes[0], w, np.asarray(y) * scale, color=color, size=STUDY_SIZES[min(k, len(STUDY_SIZES) - 1)])
        axes[0].plot([], [], "o", ms=3, color=color, label=label)
        if quantity == "poincare":
            axes[0].axhline(x_obstacle * MM, color=color, lw=0.6, ls="--")
    if quantity == "poincare":
        axes[0].plot([], [], color="0.4", lw=0.6, ls="--", label=r"obstacle $x_I$ of each")
    else:
        axes[0].set_ylim(0, None)
    axes[0].set_ylabel(ylabel)
    axes[0].legend(loc="lower left", fontsize=6, frameon=True, framealpha=0.9)
    axes[0].set_title(title or f"{what} of {' and '.join(layer[0] for layer in layers)}")
    period_strip(axes[1], [(label, omega, period) for label, _, _, _, omega, period in layers])
    axes[1].set_xlabel(r"$\omega$ (rad/s)")
    axes[1].set_xlim(min(np.min(layer[4]) for layer in layers), max(np.max(layer[4]) for layer in layers))
    return fig


def _period_colors():
    colors = [
        "white",
        "0.25",
        "#c6dbef",
        "#2171b5",
        "#41ab5d",
        "#fd8d3c",
        "#a63603",
        "#6a51a3",
        "#d4b9da",
        "#ffd92f",
        "#e7298a",
        "#66c2a5",
    ]
    cmap = ListedColormap(colors)
    norm = BoundaryNorm(np.arange(-1.5, len(colors) - 1.5 + 1e-9), cmap.N)
    return cmap, norm, ["no result", "non-periodic"] + [str(k) for k in range(1, 10)] + [">= 10"]


def _period_class(period):
    p = np.asarray(period)
    return np.where(p < 0, -1, np.where(p == 0, 0, np.minimum(p, 10)))
