"""Figure of an identification: measured against simulated windows, residuals, parameters.

Reads what :func:`impactosc.identification.report.write_fit_windows` stored and the parameter
rows of :func:`impactosc.identification.report.parameter_rows`.
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np

from .style import DOUBLE, apply_style

__all__ = ["identification_figure"]


def _window_with_contact(win, r):
    """Index of record r's window with the deepest excursion above its median top (a contact)."""
    idx = np.flatnonzero(win["record"] == r)
    tops = [np.max(win["x"][win["offset"][j] : win["offset"][j] + win["n"][j]]) for j in idx]
    return int(idx[int(np.argmax(tops))]) if idx.size else None


def _format_value(v, se):
    if not math.isfinite(se) or se <= 0:
        return f"{v:.6g}"
    digits = max(0, -int(math.floor(math.log10(se))) + 1)
    return f"{v:.{digits}f} +- {se:.2g}" if abs(v) < 1e4 else f"{v:.5e} +- {se:.2g}"


def identification_figure(win: dict, rows: list[dict], title: str):
    """Top: one window per record, samples and the fitted model; middle: its residuals;
    bottom left: histogram of all residuals against the fitted noise; bottom right: the table."""
    apply_style()
    labels = win["labels"]
    n_rec = len(labels)
    fig = plt.figure(figsize=(DOUBLE, 0.95 * DOUBLE))
    grid = fig.add_gridspec(3, max(n_rec, 2), height_ratios=[1.3, 0.7, 1.4])
    resid_all = win["x"] - win["x_model"]
    for r in range(n_rec):
        j = _window_with_contact(win, r)
        ax = fig.add_subplot(grid[0, r])
        axr = fig.add_subplot(grid[1, r], sharex=ax)
        if j is None:
            continue
        sl = slice(win["offset"][j], win["offset"][j] + win["n"][j])
        t = win["t_start"][j] + win["dt"][j] * np.arange(win["n"][j])
        ax.plot(t, 1e3 * win["x"][sl], ".", ms=1.5, color="0.4", label="record")
        ax.plot(t, 1e3 * win["x_model"][sl], "-", color="C3", lw=0.8, label="identified model")
        axr.plot(t, 1e6 * (win["x"][sl] - win["x_model"][sl]), ".", ms=1.2, color="C0")
        axr.axhline(0, color="k", lw=0.5)
        ax.set_title(f"{labels[r]}, w = {win['omega'][j]:.4g} rad/s", fontsize=7)
        axr.set_xlabel("t (s, forcing phase / w)")
        if r == 0:
            ax.set_ylabel("x (mm)")
            axr.set_ylabel("residual (um)")
            ax.legend(loc="lower left", frameon=False)
    ax = fig.add_subplot(grid[2, 0])
    s = win["residual_rms_m"]
    ok = np.isfinite(resid_all)
    ax.hist(1e6 * resid_all[ok], bins=80, density=True, color="0.6")
    u = np.linspace(-5 * s, 5 * s, 200)
    ax.plot(1e6 * u, np.exp(-0.5 * (u / s) ** 2) / (s * 1e6 * math.sqrt(2 * math.pi)), color="C3")
    ax.set_xlabel("residual (um)")
    ax.set_ylabel("density")
    ax.set_title(f"all {ok.sum()} samples; Gaussian of the fitted rms {1e6 * s:.2f} um", fontsize=7)
    axt = fig.add_subplot(grid[2, 1:])
    axt.axis("off")
    cells = [
        [r["field"], _format_value(r["field_value"], r["field_stderr"]), r["unit"], r["status"][:40]] for r in rows
    ]
    table = axt.table(cellText=cells, colLabels=["parameter", "value +- standard error", "unit", ""], loc="center")
    table.auto_set_font_size(False)
    table.set_fontsize(6.5)
    table.scale(1.0, 1.15)
    fig.suptitle(title, fontsize=8)
    return fig
