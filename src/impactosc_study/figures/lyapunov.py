"""Lyapunov exponents: the chaotic spectrum's convergence in time over realisations, and the
largest exponent drawn under the bifurcation diagrams (Figs 2 and 3b)."""

from __future__ import annotations

import math

import numpy as np
from matplotlib import pyplot as plt

from impactosc_study.figures.bifurcation import CM, MM, diagram_panel
from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["convergence_figure", "diagram_with_exponent", "sweep_with_exponent"]

#: the paper's figure of each quantity drawn over a sweep: Fig 2 the Poincare points, Fig 3b the intervals
FIGURE_OF = {"poincare": "Fig 2", "isi": "Fig 3b"}


def convergence_figure(runs: list[dict], mean_per_second, spread_per_second):
    """Running estimates of both exponents (per second) against the length of the run, one
    line per realisation; the realisations' mean and spread (one standard deviation) as a band."""
    apply_style()
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE, 6.0 * CM))
    for i, ax in enumerate(axes):
        for r in runs:
            running = np.asarray(r["running"], float)[:, i] * r["omega"] / (2 * math.pi)
            t = np.arange(1, len(running) + 1) * 2 * math.pi / r["omega"]
            ax.plot(t, running, lw=0.7, label=f"x0 = {r['x0'] * MM:g} mm")
        m, s = mean_per_second[i], spread_per_second[i]
        ax.axhspan(m - s, m + s, color="0.85", zorder=0)
        ax.axhline(m, color="k", lw=0.6, ls="--")
        ax.set_xscale("log")
        ax.set_xlabel("length of the run (s)")
        ax.set_ylabel(rf"$\lambda_{i + 1}$ (1/s)")
        ax.set_title(rf"$\lambda_{i + 1}$ = {m:.3f} $\pm$ {s:.3f} /s")
    axes[0].legend(fontsize=6)
    return fig


def diagram_with_exponent(sweep_w, sweep_y, w, lambda1, *, quantity: str, x_obstacle=None, title=""):
    """The sweep's diagram (Poincare x or inter-impact intervals) with the largest exponent
    per forcing period at every w in a panel under it (positive: chaos; negative: periodic)."""
    apply_style()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(DOUBLE, 10 * CM), sharex=True, height_ratios=[2, 1])
    scale = MM if quantity == "poincare" else 1.0
    diagram_panel(top, sweep_w, np.asarray(sweep_y) * scale)
    if x_obstacle is not None and quantity == "poincare":
        top.axhline(x_obstacle * MM, color="tab:red", lw=0.6, ls="--")
    top.set_ylabel(r"$x$ at $\varphi = 2\pi i$ (mm)" if quantity == "poincare" else r"$S_j$ (s)")
    top.set_title(title)
    lam = np.asarray(lambda1, float)
    bottom.axhline(0.0, color="0.5", lw=0.6)
    bottom.plot(w, lam, color="k", lw=0.6)
    bottom.fill_between(w, 0, lam, where=lam > 0, color="tab:red", alpha=0.4, lw=0)
    bottom.set_ylabel(r"$\lambda_1$ per period")
    bottom.set_xlabel(r"$\omega$ (rad/s)")
    bottom.set_xlim(np.min(sweep_w), np.max(sweep_w))
    lo = np.nanpercentile(lam, 1) if np.isfinite(lam).any() else -1.0
    bottom.set_ylim(max(lo * 1.1, -3.0), None)
    return fig


def sweep_with_exponent(sweep_file, lambdas_file, *, quantity: str, x_obstacle=None):
    """:func:`diagram_with_exponent` from the files a workflow writes: a sweep file and that sweep's
    lambda1 CSV (columns omega, lambda1_per_period); ``quantity`` poincare (Fig 2) or isi (Fig 3b)."""
    from impactosc.dynamics.sweep import load_sweep
    from impactosc.io.files import read_csv

    res, attrs = load_sweep(sweep_file)
    rows = read_csv(lambdas_file, numbers=True)
    w = [float(r["omega"]) for r in rows]
    lam = [float(r["lambda1_per_period"]) for r in rows]
    sw, sy = res.poincare_points() if quantity == "poincare" else res.isi_points()
    title = f"{FIGURE_OF[quantity]} with the largest Lyapunov exponent ({attrs['direction']} w)"
    return diagram_with_exponent(sw, sy, w, lam, quantity=quantity, x_obstacle=x_obstacle, title=title)
