"""Figs 2 and 3b with the continued periodic orbits drawn over the brute-force sweep points:
stable branches solid, unstable dashed, one colour per period, the located bifurcation points
marked (supplementary figures; the paper's Figs 2 and 3b stay as they are).

Every function takes the segment dicts as read from results/<study>/runs/orbits/*.json and the sweep
points as arrays, and returns a matplotlib Figure.
"""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt
from matplotlib.lines import Line2D

from impactosc_study.figures.bifurcation import CM, MM, diagram_panel
from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["orbit_figure", "branch_curves", "orbits_over_sweep"]

POINT_STYLE = {"period_doubling": ("o", "tab:red"), "fold": ("s", "tab:blue"), "grazing": ("D", "tab:green")}
JUMP = 0.01  # s: an inter-impact interval that moves more than this between neighbours starts a new curve


def _period_color(n_periods: int):
    return plt.get_cmap("tab10")(int(np.log2(n_periods)) % 10 if n_periods & (n_periods - 1) == 0 else 9)


def _aligned_isis(points):
    """Each orbit's inter-impact intervals, cyclically shifted to match the previous orbit's
    order (the first impact after phase 0 changes identity when an impact crosses phase 0)."""
    out, prev = [], None
    for p in points:
        s = np.asarray(p["isis"], float)
        if prev is not None and prev.size == s.size and s.size:
            shifts = [np.roll(s, k) for k in range(s.size)]
            s = min(shifts, key=lambda r: float(np.abs(r - prev).sum()))
        out.append(s)
        prev = s
    return out


def branch_curves(points, quantity: str):
    """(w, y, stable) curves of one segment: y the k-th Poincare x ('poincare') or the j-th
    inter-impact interval ('isi'); a curve ends where the stability or the number of values
    per orbit changes, or where an interval jumps by more than JUMP."""
    w = np.array([p["omega"] for p in points])
    stable = np.array([p["stable"] for p in points])
    values = [np.asarray(p["poincare_x"], float) for p in points] if quantity == "poincare" else _aligned_isis(points)
    curves, start, join = [], 0, False
    for i in range(1, len(points) + 1):
        last = i == len(points)
        same_size = not last and values[i].size == values[i - 1].size
        jump = same_size and quantity == "isi" and bool(np.any(np.abs(values[i] - values[i - 1]) > JUMP))
        if last or not same_size or jump or stable[i] != stable[start]:
            first = start - 1 if join else start  # a change of stability alone: the curves meet
            ys = np.array([values[k] for k in range(first, i)])
            curves.extend((w[first:i], ys[:, j], bool(stable[start])) for j in range(ys.shape[1]))
            start, join = i, same_size and not jump
    return curves


def orbit_figure(segments: dict, sweep_w, sweep_y, *, quantity: str, x_obstacle=None, title=""):
    """One panel: the sweep's points (grey) and every segment's branches over them, the located
    bifurcation points marked; quantity 'poincare' (Fig 2: x at phase 0, mm) or 'isi' (Fig 3b:
    inter-impact intervals, s). The w axis is the sweep's range."""
    apply_style()
    fig, ax = plt.subplots(figsize=(DOUBLE, 8.5 * CM))
    scale = MM if quantity == "poincare" else 1.0
    diagram_panel(ax, sweep_w, np.asarray(sweep_y) * scale, color="0.6", size=0.5)
    periods = set()
    for seg in segments.values():
        if not seg["points"]:
            continue  # an empty segment (its parent had no doubling to switch at)
        color = _period_color(seg["n_periods"])
        periods.add(seg["n_periods"])
        for w, y, stable in branch_curves(seg["points"], quantity):
            ax.plot(w, y * scale, color=color, lw=1.0 if stable else 0.7, ls="-" if stable else "--", zorder=3)
        for p in seg["special_points"]:
            if not p["located"] or p["kind"] not in POINT_STYLE or not np.min(sweep_w) <= p["omega"] <= np.max(sweep_w):
                continue
            marker, c = POINT_STYLE[p["kind"]]
            if quantity == "poincare":
                ax.plot(p["omega"], p["x0"] * scale, marker, ms=3.5, mfc="none", mec=c, mew=0.9, zorder=5)
            else:
                ax.plot(
                    p["omega"], 1.0, "v", ms=4, color=c, transform=ax.get_xaxis_transform(), clip_on=False, zorder=5
                )
    if x_obstacle is not None:
        ax.axhline(x_obstacle * MM, color="tab:red", lw=0.6, ls=":")
    ax.set_xlim(np.min(sweep_w), np.max(sweep_w))
    if quantity == "isi":
        ax.set_ylim(0, None)
    ax.set_xlabel(r"$\omega$ (rad/s)")
    ax.set_ylabel(r"$x$ at $\varphi = 2\pi i$ (mm)" if quantity == "poincare" else r"$S_j$ (s)")
    ax.set_title(title)
    handles = [Line2D([], [], color="0.6", marker=".", ls="none", label="sweep (brute force)")]
    handles += [Line2D([], [], color=_period_color(n), lw=1.0, label=f"period {n}") for n in sorted(periods)]
    handles += [Line2D([], [], color="k", lw=0.7, ls="--", label="unstable")]
    handles += [Line2D([], [], marker=m if quantity == "poincare" else "v", color=c, mfc="none" if quantity == "poincare" else c,
                       ls="none", label=k.replace("_", " ")) for k, (m, c) in POINT_STYLE.items()]  # fmt: skip
    ax.legend(handles=handles, fontsize=6, ncol=3, loc="upper center" if quantity == "poincare" else "lower center",
              framealpha=0.9)  # fmt: skip
    return fig


def orbits_over_sweep(segment_files: dict, sweep_file, *, quantity: str, x_obstacle=None):
    """:func:`orbit_figure` from the files a workflow writes: the segments' JSON files by name and a
    sweep file; ``quantity`` poincare (Fig 2) or isi (Fig 3b, no obstacle line)."""
    from impactosc.dynamics.sweep import load_sweep
    from impactosc.io.files import read_json

    segments = {name: read_json(path) for name, path in segment_files.items()}
    res, attrs = load_sweep(sweep_file)
    w, y = res.poincare_points() if quantity == "poincare" else res.isi_points()
    figure = "Fig 2" if quantity == "poincare" else "Fig 3b"
    title = rf"{figure} with the continued orbits ({attrs['direction']} $\omega$ sweep in grey)"
    return orbit_figure(
        segments, w, y, quantity=quantity, x_obstacle=x_obstacle if quantity == "poincare" else None, title=title
    )
