"""Work-precision figure: wall time against error per solver, and the chaotic statistics
against tolerance.

Top rows (DiffEqBenchmarks style): one panel per scene and error metric, log-log, one line
per solver through its tolerance sweep; each point is the minimum wall time of several
runs, JIT compile excluded. Errors below the reference's own uncertainty cannot be told
apart from it: that region is shaded and such errors are drawn at its edge.
Compiled peers (CyRK methods) are lines like SciPy's; a point whose 500 s run from rest
left the attractor (or stopped) is an open marker with a label, a run that stopped within
the horizon an open marker at the panel's right edge (its errors are infinite); heyoka's
free-flight floor is a dotted horizontal line; a peer that is not installed is noted in
the panel ("CyRK not installed"), and so is a sweep the time budget per point stopped.
Bottom row: the chaotic train's statistics at each tolerance of the core, against the mean
+- 2 std band of an ensemble of realisations (the statistics, not the trajectory, must
converge for a chaotic train).
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import matplotlib.transforms as mtransforms
import numpy as np
from matplotlib.lines import Line2D

from impactosc_bench.event_errors import METRICS
from impactosc_bench.workprecision import METRIC_LABELS
from impactosc_bench.wp_solvers import CORE, SCIPY_METHODS
from impactosc_study.figures.style import DOUBLE, apply_style

STYLES = {
    CORE: dict(color="black", marker="o", lw=1.6, ms=3.5, zorder=5),
    "RK45": dict(color="C0", marker="s", lw=0.9, ms=3),
    "DOP853": dict(color="C1", marker="^", lw=0.9, ms=3),
    "Radau": dict(color="C2", marker="D", lw=0.9, ms=2.8),
    "LSODA": dict(color="C3", marker="v", lw=0.9, ms=3),
    "CyRK DOP853": dict(color="C4", marker="P", lw=1.1, ms=3.5, ls="--"),
    "CyRK Vern8": dict(color="C5", marker="X", lw=1.1, ms=3.5, ls="--"),
    "CyRK Vern7": dict(color="C6", marker="*", lw=1.1, ms=4, ls="--"),
}
FLOOR_STYLE = dict(color="0.35", lw=0.8, ls=":")
OPEN_MARKER = dict(marker="o", ms=6, mfc="none", mew=0.9, ls="none", zorder=6)
SCENE_TITLES = {"periodic": "period-4 orbit", "chaotic": "chaotic attractor"}
STAT_PANELS = (
    ("window_counts", "impacts per 80 s window"),
    ("cv2_paper", "paper's $C_V^2$ = var(S)/mean(S) (s)"),
    ("isi_first_maximum", "ISI density maximum $T_1$ (s)"),
    ("isi_last_maximum", "ISI density maximum $T_2$ (s)"),
)


def _float(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def _counts(v):
    """Window counts as floats, from a list or the CSV's space-joined string."""
    return [_float(c) for c in (v.split() if isinstance(v, str) else v)]


def solver_label(solver: str) -> str:
    """Legend name: the core, "SciPy <method>", or a peer's own name ("CyRK DOP853")."""
    if solver == CORE:
        return "impactosc core"
    return f"SciPy {solver}" if solver in SCIPY_METHODS else str(solver)


def _off_attractor(r) -> bool:
    return r.get("on_attractor") in (False, "no")


def unavailable_notes(rows, scene) -> list[str]:
    """One short line per peer family that could not run on `scene` ("CyRK not installed")."""
    notes = {}
    for r in rows:
        if r["scene"] != scene or r.get("status") != "unavailable":
            continue
        family = str(r["solver"]).split()[0]
        why = str(r.get("note", ""))
        if "not installed" in why:
            notes[family] = f"{family} not installed"
        else:
            notes[family] = f"{family} unavailable: {why.splitlines()[0][:60]}"
    return list(notes.values())


def budget_notes(rows, scene) -> list[str]:
    """One line per solver whose sweep the time budget per point stopped (its skipped rows)."""
    out = {}
    for r in rows:
        if r["scene"] == scene and r.get("status") == "skipped" and r["solver"] not in out:
            out[r["solver"]] = f"{solver_label(r['solver'])}: {r.get('note', 'skipped')}"
    return list(out.values())


def _wp_panel(ax, rows, scene, metric, show_legend):
    ok = [r for r in rows if r["scene"] == scene and r["status"] == "ok"]
    unc = _float(next(r for r in rows if r["scene"] == scene)[f"reference_{metric}"])
    floor = unc if unc > 0 else 1e-16
    marked = {}  # (solver, what happened in the 500 s run) -> rtols of the open markers
    for solver in dict.fromkeys(r["solver"] for r in rows):
        pts = sorted((r for r in ok if r["solver"] == solver), key=lambda r: -_float(r["rtol"]))
        style = STYLES.get(solver, {})
        stopped = [r for r in rows if r["scene"] == scene and r["solver"] == solver and r["status"] == "stopped"]
        if stopped:  # errors are infinite: at the right edge, at their wall time
            edge = mtransforms.blended_transform_factory(ax.transAxes, ax.transData)
            for r in stopped:
                ax.plot(
                    [0.97], [_float(r["wall_time"])], transform=edge, color=style.get("color", "0.3"), **OPEN_MARKER
                )
                ann = ax.annotate(
                    f"{solver_label(solver)} rtol {_float(r['rtol']):.0e}: stopped",
                    (0.97, _float(r["wall_time"])),
                    xycoords=edge,
                    textcoords="offset points",
                    xytext=(-4, 4),
                    fontsize=4.5,
                    ha="right",
                    color=style.get("color", "0.3"),
                )
                ann.set_in_layout(False)
        if not pts:
            continue
        err = np.maximum([_float(r[metric]) for r in pts], floor)
        wall = np.array([_float(r["wall_time"]) for r in pts])
        ax.loglog(err, wall, label=solver_label(solver), **style)
        for r, e, w in zip(pts, err, wall):
            if _off_attractor(r):
                ax.plot([e], [w], color=style.get("color", "0.3"), **OPEN_MARKER)
                stopped_500 = str(r.get("attractor_note", "")).startswith("500 s run stopped")
                what = "stops" if stopped_500 else "leaves the attractor"
                marked.setdefault((solver, what), []).append(f"{_float(r['rtol']):.0e}")
        if solver == CORE:  # tolerance labels: loosest below-right, tightest above-right
            for r, e, w, off, ha in (
                (pts[0], err[0], wall[0], (3, -8), "left"),
                (pts[-1], err[-1], wall[-1], (4, 4), "left"),
            ):
                ann = ax.annotate(
                    f"rtol {_float(r['rtol']):.0e}", (e, w), textcoords="offset points", xytext=off, fontsize=5, ha=ha
                )
                ann.set_in_layout(False)
    if marked and metric == METRICS[0]:  # the labels of the open markers, once per scene
        lines = [f"{solver_label(solver)} rtol {', '.join(rtols)}: {what}" for (solver, what), rtols in marked.items()]
        ax.text(
            0.03,
            0.08,
            "open markers, 500 s from rest:\n" + "\n".join(lines),
            transform=ax.transAxes,
            fontsize=4.5,
            va="bottom",
            ha="left",
            color="0.2",
        )
    for r in (r for r in rows if r["scene"] == scene and r["status"] == "floor"):
        ax.axhline(_float(r["wall_time"]), label=f"floor: {r['solver']}, tol {_float(r['rtol']):.0e}", **FLOOR_STYLE)
    budget = budget_notes(rows, scene)
    if budget and metric == METRICS[0]:  # fewer points, not different numbers: say where a sweep stops
        ax.text(0.03, 0.97, "\n".join(budget), transform=ax.transAxes, fontsize=4.5, va="top", ha="left", color="0.35")
    notes = unavailable_notes(rows, scene)
    if notes:
        ax.text(0.03, 0.03, "\n".join(notes), transform=ax.transAxes, fontsize=5.5, color="C3", va="bottom")
    lo, hi = ax.get_xlim()
    ax.axvspan(min(lo, floor / 10), floor, color="0.88", zorder=0, lw=0)
    ax.set_xlim(min(lo, floor / 3), hi)
    ax.set_xlabel(METRIC_LABELS[metric])
    if metric == METRICS[0]:
        ax.set_ylabel("wall time (s)")
    horizon = _float(ok[0]["horizon"]) if ok else math.nan
    ax.set_title(f"{SCENE_TITLES.get(scene, scene)}, {horizon:g} s", fontsize=7)
    ax.grid(True, which="major", lw=0.3, alpha=0.5)
    if show_legend:
        ax.legend(loc="upper right", frameon=False, fontsize=5.5, handlelength=1.8)


def _shared_legend(fig, axes, rows):
    """One legend for the work-precision panels: every line of any panel (the peers run on
    some scenes only), and the open marker if one is drawn."""
    handles, labels = {}, []
    for ax in axes.flat:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in handles:
                handles[lab] = h
                labels.append(lab)
    if any(_off_attractor(r) or r.get("status") == "stopped" for r in rows):
        labels.append("open: off the attractor or stopped (labelled)")
        handles[labels[-1]] = Line2D([], [], color="0.3", **OPEN_MARKER)
    fig.legend(
        [handles[lab] for lab in labels],
        labels,
        loc="outside lower center",
        ncols=min(len(labels), 3),
        frameon=False,
        fontsize=5.5,
        handlelength=2.2,
    )


def _stat_panel(ax, stats_rows, key, label):
    sweep = sorted((r for r in stats_rows if r["kind"] == "sweep"), key=lambda r: -_float(r["rtol"]))
    ens = [r for r in stats_rows if r["kind"] == "ensemble"]
    rt = np.array([_float(r["rtol"]) for r in sweep])
    if key == "window_counts":
        vals = np.array([_counts(r[key]) for r in sweep])
        ev = np.array([_counts(r[key]) for r in ens])
        mean, std = ev.mean(), ev.std(ddof=1)
        for j in range(vals.shape[1]):
            ax.semilogx(rt, vals[:, j], ".", color="black", ms=2.5, alpha=0.8)
    else:
        vals = np.array([_float(r[key]) for r in sweep])
        ev = np.array([_float(r[key]) for r in ens])
        mean, std = ev.mean(), ev.std(ddof=1)
        ax.semilogx(rt, vals, "o-", color="black", ms=3, lw=0.9)
    ax.axhspan(mean - 2 * std, mean + 2 * std, color="C0", alpha=0.18, lw=0)
    ax.axhline(mean, color="C0", lw=0.8)
    ax.invert_xaxis()
    ax.set_xlabel("core rtol")
    ax.set_ylabel(label, fontsize=6.5)
    ax.grid(True, which="major", lw=0.3, alpha=0.5)


def plot_work_precision(rows, stats_rows, *, jit: dict | None = None, n_ensemble: int | None = None):
    """The figure from the rows of work_precision.csv and the statistics CSV (save it with
    :func:`impactosc_study.figures.style.save_figure`)."""
    apply_style()
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig = plt.figure(figsize=(DOUBLE, DOUBLE * (0.36 * len(scenes) + 0.46)))
    # two subfigures, so the 3-column and the 4-column rows are laid out independently
    top, bottom = fig.subfigures(2, 1, height_ratios=[len(scenes) + 0.3, 0.85])
    axes = top.subplots(len(scenes), len(METRICS), squeeze=False)
    for i, scene in enumerate(scenes):
        for j, metric in enumerate(METRICS):
            _wp_panel(axes[i, j], rows, scene, metric, show_legend=False)
    _shared_legend(top, axes, rows)
    for ax, (key, label) in zip(bottom.subplots(1, len(STAT_PANELS)), STAT_PANELS):
        _stat_panel(ax, stats_rows, key, label)
    n_ens = n_ensemble if n_ensemble is not None else sum(1 for r in stats_rows if r["kind"] == "ensemble")
    note = "Minimum wall time of repeated runs; grey: below the reference's own uncertainty."
    if jit:
        cold = f"{jit['cold']:.0f} s cold" if jit.get("cold") is not None else "cold not measured"
        note += f"\nJIT compile of the core excluded: {cold}, {jit['cached']:.1f} s from cache."
    if any(str(r["solver"]).startswith("CyRK") and r.get("status") != "unavailable" for r in rows):
        note += (
            "\nCyRK (dashed): the model in one right-hand side, no splitting at contacts; numba cfunc "
            "right-hand side and events on CyRK's dense output."
        )
    note += (
        f"\nBottom: chaotic scene (100 s + 400 s) at each core rtol; band: mean $\\pm$ 2 std of {n_ens} realisations."
    )
    fig.suptitle(note, fontsize=6)
    return fig
