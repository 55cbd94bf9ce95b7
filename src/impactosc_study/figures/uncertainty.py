"""Error bars of a model with a covariance on the bifurcation diagrams (Figs 2 and 3b).

Why: a diagram of an identified model is one model among those its records allow; drawn with
its located points as w +- 2 se and its continued branches as bands of +- 2 se, a reader sees
which transitions are robust and where two diagrams differ beyond the fit's uncertainty.

Every function takes the predictions of the segments as the workflow writes them (rule
prediction_segment: ``points`` with ``se``, ``band`` with each sampled orbit's values and
standard errors) and draws into given axes.  The paper's model BC is stated exactly and has no
predictions: its figures call none of this.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.transforms import blended_transform_factory

__all__ = ["draw_bands", "draw_point_errors", "band_width_panel", "points_text", "BAND_COLOR"]

BAND_COLOR = "tab:cyan"
POINT_STYLE = {"grazing": ("o", "tab:green"), "period_doubling": ("s", "tab:red"), "fold": ("D", "tab:purple")}
#: Quantities of a band and what they are called on an axis.
LABELS = {"poincare_x": r"$x$ at $\varphi = 2\pi i$", "isis": r"$S_j$"}


def _runs(band: dict, quantity: str) -> list:
    """(w, values, se) of each stretch of stable orbits with the same number of values and
    finite standard errors, the values of each orbit sorted (sorted, each stays continuous
    along the branch where an impact moves across the phase origin)."""
    runs, current = [], []
    for i, w in enumerate(band["omega"]):
        v, s = np.asarray(band[quantity][i], float), np.asarray(band[f"se_{quantity}"][i], float)
        ok = bool(band["stable"][i]) and v.size > 0 and bool(np.all(np.isfinite(s)))
        if not ok or (current and current[-1][1].size != v.size):
            runs.append(current)
            current = []
        if ok:
            order = np.argsort(v)
            current.append((float(w), v[order], s[order]))
    runs.append(current)
    out = []
    for run in (r for r in runs if len(r) >= 2):
        ws = np.array([r[0] for r in run])
        order = np.argsort(ws)
        out.append((ws[order], np.array([r[1] for r in run])[order], np.array([r[2] for r in run])[order]))
    return out


def draw_bands(ax, predictions: list[dict], quantity: str, scale: float = 1.0, *, label=True):
    """Each segment's stable orbits as a band of their values +- 2 se (times ``scale``)."""
    first = label
    for found in predictions:
        for w, v, s in _runs(found["band"], quantity):
            for k in range(v.shape[1]):
                ax.fill_between(
                    w,
                    (v[:, k] - 2 * s[:, k]) * scale,
                    (v[:, k] + 2 * s[:, k]) * scale,
                    color=BAND_COLOR,
                    alpha=0.45,
                    lw=0.8,
                    edgecolor=BAND_COLOR,
                    zorder=1,
                    label=r"continued stable orbits $\pm 2$ se" if first else None,
                )
                first = False


def _located(predictions):
    """The points with a standard error (a JSON file writes a missing one, nan, as null)."""
    return [p for found in predictions for p in found["points"] if p["se"] is not None and math.isfinite(p["se"])]


def draw_point_errors(ax, predictions: list[dict], w_range, *, height: float = 0.06, label: bool = True):
    """Each located point with a standard error within ``w_range`` as w +- 2 se: a horizontal
    error bar at ``height`` (axes fraction) above the w axis, labelled once per kind for the
    axes' legend (``label``)."""
    tr = blended_transform_factory(ax.transData, ax.transAxes)
    seen = set()
    lo, hi = w_range
    for p in _located(predictions):
        if not lo <= p["omega"] <= hi:
            continue
        marker, color = POINT_STYLE.get(p["kind"], ("^", "0.3"))
        name = f"{p['kind'].replace('_', ' ')}: $\\omega \\pm 2$ se"
        ax.errorbar(
            p["omega"],
            height,
            xerr=2 * p["se"],
            fmt=marker,
            ms=3,
            color=color,
            ecolor=color,
            elinewidth=1.2,
            capsize=2.5,
            transform=tr,
            zorder=5,
            clip_on=False,
            label=name if label and name not in seen else None,
        )
        seen.add(name)


def band_width_panel(ax, predictions: list[dict], quantity: str, scale: float, unit: str):
    """2 se of the band against w (the band's full half-width, which at a diagram's scale may be
    thinner than its line), one line per branch value."""
    for found in predictions:
        for w, _v, s in _runs(found["band"], quantity):
            ax.plot(w, 2 * s * scale, color=BAND_COLOR, lw=0.8)
    ax.set_ylabel(f"2 se of {LABELS[quantity]}\n({unit})", fontsize=7)
    ax.set_ylim(0, None)
    ax.set_xlabel(r"$\omega$ (rad/s)")


def points_text(ax, predictions: list[dict], model: str):
    """The located points with their standard errors, as text in an empty panel."""
    ax.axis("off")
    rows = [
        f"{p['kind'].replace('_', ' ')}, period {p['n_periods']}: {p['omega']:.4f} $\\pm$ {p['se']:.2g}"
        for p in sorted(_located(predictions), key=lambda p: p["omega"])
    ]
    text = f"located points of {model}\n(w $\\pm$ 1 se from its covariance, rad/s)\n\n" + (
        "\n".join(rows) or "none located"
    )
    ax.text(0.0, 1.0, text, va="top", ha="left", fontsize=6.5, transform=ax.transAxes)
