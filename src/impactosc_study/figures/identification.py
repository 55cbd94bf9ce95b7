"""Figure of an identification: measured against simulated windows, residuals, parameters.

Reads what :func:`impactosc.identification.report.write_fit_windows` stored and the parameter
rows of :func:`impactosc.identification.report.parameter_rows`.
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np

from impactosc_study.figures.style import DOUBLE, apply_style

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
    """Top: for each record the window with the highest turning point, samples and the fitted
    model; below it a zoom on that contact (+-6 ms, height above the fitted obstacle); bottom
    left: histogram of every residual against the fitted noise; bottom right: the parameters."""
    apply_style()
    labels = win["labels"]
    n_rec = len(labels)
    xi = next((r["field_value"] for r in rows if r["field"] == "xI"), math.nan)
    fig = plt.figure(figsize=(DOUBLE, 0.95 * DOUBLE))
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.6, 1.0])
    axes = top.subplots(2, n_rec, squeeze=False, height_ratios=[1.2, 1.0])
    for r in range(n_rec):
        ax, az = axes[0, r], axes[1, r]
        j = _window_with_contact(win, r)
        if j is None:
            continue
        sl = slice(win["offset"][j], win["offset"][j] + win["n"][j])
        t = win["t_start"][j] + win["dt"][j] * np.arange(win["n"][j])
        x, xm = win["x"][sl], win["x_model"][sl]
        ax.plot(t, 1e3 * x, ".", ms=1.5, color="0.4", label="record")
        ax.plot(t, 1e3 * xm, "-", color="C3", lw=0.8, label="identified model")
        ax.set_title(f"{labels[r]}, w = {win['omega'][j]:.4g} rad/s", fontsize=7)
        ax.set_xlabel("t (s; with an encoder, phase / w)")
        k = int(np.argmax(xm))
        near = np.abs(t - t[k]) <= 6e-3
        az.plot(1e3 * (t[near] - t[k]), 1e6 * (x[near] - xi), ".", ms=3, color="0.4")
        az.plot(1e3 * (t[near] - t[k]), 1e6 * (xm[near] - xi), "-", color="C3", lw=0.8)
        az.axhline(0, color="k", lw=0.5, ls="--")
        az.set_xlabel("t - t(top) (ms)")
        if r == 0:
            ax.set_ylabel("x (mm)")
            az.set_ylabel("x - xI (um)")
            ax.legend(loc="lower left", frameon=False)
    ax, axt = bottom.subplots(1, 2, width_ratios=[1.0, 1.3])
    s = win["residual_rms_m"]
    resid = win["x"] - win["x_model"]
    ok = np.isfinite(resid)
    ax.hist(1e6 * resid[ok], bins=80, density=True, color="0.6")
    u = np.linspace(-5 * s, 5 * s, 200)
    ax.plot(1e6 * u, np.exp(-0.5 * (u / s) ** 2) / (s * 1e6 * math.sqrt(2 * math.pi)), color="C3")
    ax.set_xlabel("residual (um)")
    ax.set_ylabel("density")
    ax.set_title(f"all {ok.sum()} samples; Gaussian of the fitted rms {1e6 * s:.2f} um", fontsize=7)
    axt.axis("off")
    cells = [
        [r["field"], _format_value(r["field_value"], r["field_stderr"]), r["unit"], r["status"][:28]] for r in rows
    ]
    table = axt.table(
        cellText=cells,
        colLabels=["parameter", "value +- standard error", "unit", "status"],
        colWidths=[0.14, 0.44, 0.17, 0.25],
        loc="center",
        cellLoc="left",
    )
    table.auto_set_font_size(False)
    table.set_fontsize(6.5)
    table.scale(1.0, 1.2)
    fig.suptitle(title, fontsize=8)
    return fig
