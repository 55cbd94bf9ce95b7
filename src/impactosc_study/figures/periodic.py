"""Figures of the periodic regime and the grazing bifurcation (paper Figs 3a, 4, 5; grazing).

Every function takes plain arrays/dicts (read from run and statistics files by the
workflow scripts) and returns a matplotlib Figure; no numerics beyond slicing happen here,
so restyling a figure never reruns a simulation or a statistic.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from matplotlib import pyplot as plt
from matplotlib.patches import Rectangle

from impactosc_study.figures.style import DOUBLE, SINGLE, apply_style
from impactosc_study.paper.numbers import PERIODIC

MM = 1e3  # m -> mm
UM = 1e6  # m -> um

__all__ = ["fig03a_impact_construction", "fig04_grazing_portraits", "fig05_impact_map", "grazing_evidence"]


def fig03a_impact_construction(t, x, impact_t, x_impact_level, t_start: float, span: float, ax=None):
    """x(t) with the level xI, the impact moments T_j (upward crossings) and the intervals S_j.

    Draws into `ax` when given (Fig 3 puts this panel beside the ISI diagram), else into a
    figure of its own; returns the figure.
    """
    apply_style()
    sel = (t >= t_start) & (t <= t_start + span)
    if sel.sum() < 2:
        raise ValueError(f"the trajectory has no samples in [{t_start}, {t_start + span}] s")
    tj = np.asarray(impact_t)[(impact_t >= t_start) & (impact_t <= t_start + span)]
    if tj.size < 2:
        raise ValueError(f"need at least 2 impacts in [{t_start}, {t_start + span}] s to draw an interval")
    if ax is None:
        fig, ax = plt.subplots(figsize=(SINGLE * 1.25, 5.2 / 2.54))
    else:
        fig = ax.figure
    tt = t[sel] - t_start
    xi = x_impact_level * MM
    ax.plot(tt, x[sel] * MM, color="0.15", lw=0.9, label="$x(t)$")
    ax.axhline(xi, color="tab:red", lw=0.8, ls="--")
    ax.text(tt[-1], xi - 0.08, r"$x = x_I$", color="tab:red", ha="right", va="top", fontsize=7)
    top = max(float(x[sel].max() * MM), xi) + 0.35
    for j, T in enumerate(tj):
        ax.plot([T - t_start], [xi], "o", ms=3.5, mfc="white", mec="tab:red", mew=0.9, zorder=5)
        ax.axvline(T - t_start, color="tab:red", lw=0.4, alpha=0.5)
        ax.text(T - t_start, top + 0.22, f"$T_{{{j + 1}}}$", ha="center", va="bottom", fontsize=7)
    for j, (a, b) in enumerate(itertools.pairwise(tj)):
        ax.annotate(
            "",
            xy=(b - t_start, top),
            xytext=(a - t_start, top),
            arrowprops=dict(arrowstyle="<->", lw=0.7, color="tab:blue", shrinkA=0, shrinkB=0),
        )
        ax.text(
            0.5 * (a + b) - t_start, top - 0.05, f"$S_{{{j + 1}}}$", ha="center", va="top", fontsize=7, color="tab:blue"
        )
    ax.set_xlim(0, span)
    ax.set_ylim(float(x[sel].min() * MM) - 0.2, top + 0.8)
    ax.set_xlabel(f"$t - {t_start:g}$ s")
    ax.set_ylabel("$x$ (mm)")
    return fig


def _phase_panel(ax, x, v, x_impact_level, title, inset_box, inset_loc):
    xi = x_impact_level * MM
    ax.plot(x * MM, v, color="0.15", lw=0.6)
    ax.axvline(xi, color="tab:red", lw=0.8, ls="--")
    ax.set_xlabel("$x$ (mm)")
    ax.set_ylabel(r"$\dot x$ (m/s)")
    ax.set_title(title, loc="left")
    (x0, x1), (v0, v1) = inset_box
    ax.add_patch(Rectangle((x0 * MM, v0), (x1 - x0) * MM, v1 - v0, fill=False, ec="tab:blue", lw=0.7, zorder=4))
    ins = ax.inset_axes(inset_loc)
    inside = (x >= x0) & (x <= x1) & (v >= v0) & (v <= v1)
    # draw only the segments near the box so the inset stays light
    near = np.convolve(inside.astype(float), np.ones(5), mode="same") > 0
    xx = np.where(near, (x - x_impact_level) * UM, np.nan)
    ins.plot(xx, np.where(near, v * 1e3, np.nan), color="0.15", lw=0.8)
    ins.axvline(0.0, color="tab:red", lw=0.8, ls="--")
    ins.set_xlim((x0 - x_impact_level) * UM, (x1 - x_impact_level) * UM)
    ins.set_ylim(v0 * 1e3, v1 * 1e3)
    ins.set_xlabel(r"$x - x_I$ ($\mu$m)", fontsize=6, labelpad=1)
    ins.set_ylabel(r"$\dot x$ (mm/s)", fontsize=6, labelpad=0)
    ins.tick_params(labelsize=5.5, length=2, pad=1)
    for s in ins.spines.values():
        s.set_edgecolor("tab:blue")


def fig04_grazing_portraits(before: dict, after: dict, spectrum: dict, x_impact_level: float):
    """Phase portraits at w = 23.05 (branch, before grazing) and 23.03 (after) with grazing
    insets, and the labelled spectrum of x at 23.03.

    before/after: dicts with omega, x, v (trajectory samples), inset (((x0, x1), (v0, v1)) in
    m and m/s), note (inset text). spectrum: the spectrum statistics (omega_axis,
    amplitude, peaks, omega1, labels, ...) of :func:`impactosc.statistics.spectral_lines.analyse_spectrum`.
    """
    apply_style()
    fig = plt.figure(figsize=(DOUBLE, 12.0 / 2.54))
    gs = fig.add_gridspec(2, 2, height_ratios=[1.15, 1.0])
    for k, (d, label) in enumerate(((before, "(a)"), (after, "(b)"))):
        ax = fig.add_subplot(gs[0, k])
        title = f"{label} $\\omega = {d['omega']:g}$ rad/s  {d['tag']}" + (f"\n{d['note']}" if d.get("note") else "")
        _phase_panel(ax, d["x"], d["v"], x_impact_level, title, d["inset"], [0.16, 0.52, 0.36, 0.44])
    ax = fig.add_subplot(gs[1, :])
    om = np.asarray(spectrum["omega_axis"])
    amp = np.asarray(spectrum["amplitude"])
    w = spectrum["omega"]
    ax.semilogy(om, amp * MM, color="0.2", lw=0.6)
    ax.set_xlim(0, om[-1])
    ax.set_ylim(1e-7, 1e1)
    ax.set_xlabel(r"$\omega'$ (rad/s)")
    ax.set_ylabel("amplitude of $x$ (mm)")
    w1 = spectrum["omega1"]
    p, q = spectrum["omega1_over_omega_fraction"]
    ax.set_title(
        f"(c) spectrum of $x$ at $\\omega = {w:g}$ rad/s: $\\omega_1 = {w1:.4f}$ rad/s "
        f"$= {spectrum['omega1_over_omega']:.5f}\\,\\omega \\approx ({p}/{q})\\,\\omega$\n"
        r"$a, b, c, d, f = \omega-\omega_1,\ \omega+\omega_1,\ 2\omega-\omega_1,\ "
        r"2\omega+\omega_1,\ 3\omega-\omega_1$",
        loc="left",
    )
    peaks_om = np.asarray(spectrum["peaks_omega"])
    peaks_amp = np.asarray(spectrum["peaks_amplitude"]) * MM

    def mark(freq, text, color):
        j = int(np.argmin(np.abs(peaks_om - freq)))
        ax.annotate(
            text,
            xy=(peaks_om[j], peaks_amp[j]),
            xytext=(0, 7),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=7,
            color=color,
            arrowprops=dict(arrowstyle="-", lw=0.5, color=color, shrinkA=0, shrinkB=1),
        )

    for k in range(1, int(om[-1] // w) + 1):
        mark(k * w, rf"${k if k > 1 else ''}\omega$", "tab:blue")
    mark(w1, r"$\omega_1$", "tab:green")
    for name, lab in spectrum["labels"].items():
        if math.isfinite(lab["found"]):
            mark(lab["found"], f"${name}$", "tab:red")
    return fig


def fig05_impact_map(isi, numbers: dict, omega: float):
    """(a) successive iterations S_{j+1} vs S_j; (b) histogram of the S_j with the sum of the levels."""
    apply_style()
    s = np.asarray(isi, dtype=float)
    fig, (a, b) = plt.subplots(1, 2, figsize=(DOUBLE, 6.0 / 2.54))
    a.plot(s[:-1], s[1:], "o", ms=4, mfc="none", mec="tab:blue", mew=0.9)
    levels = numbers["levels"]
    # the cycle order of the four points, from the sequence itself
    first = s[: len(levels) + 2]  # one full cycle of arrows
    for p, q, r in zip(first[:-2], first[1:-1], first[2:]):
        a.annotate(
            "", xy=(q, r), xytext=(p, q), arrowprops=dict(arrowstyle="->", lw=0.5, color="0.5", shrinkA=4, shrinkB=4)
        )
    lo, hi = 0.0, max(levels) * 1.1
    a.plot([lo, hi], [lo, hi], color="0.7", lw=0.5, ls=":")
    a.set_xlim(lo, hi)
    a.set_ylim(lo, hi)
    a.set_aspect("equal")
    a.set_xlabel("$S_j$ (s)")
    a.set_ylabel("$S_{j+1}$ (s)")
    a.set_title(f"(a) {s.size - 1} pairs, {len(levels)} distinct points", loc="left")
    width = 0.005  # s; the levels are > 0.01 s apart, so each falls in its own bin
    b.hist(s, bins=np.arange(0.0, hi + width, width), color="tab:blue", alpha=0.8)
    cmax = max(numbers["counts"])
    for k, (lv, c) in enumerate(zip(levels, numbers["counts"])):  # staggered: close levels do not collide
        b.text(lv, c + 0.03 * cmax + (k % 2) * 0.2 * cmax, f"{lv:.5f} s\n({c})", ha="center", va="bottom", fontsize=6)
    b.set_xlim(lo, hi)
    b.set_ylim(0, cmax * 1.75)
    b.set_xlabel("$S_j$ (s)")
    b.set_ylabel(f"count per {width * 1e3:g} ms bin")
    b.set_title(f"(b) {numbers['n_impacts']} impacts, {s.size} intervals", loc="left")
    q = round(numbers["periods_in_total"])
    b.text(
        0.02,
        0.97,
        f"$\\sum$ levels = {numbers['total']:.5f} s (paper: {PERIODIC['levels_sum']} s)\n"
        f"${q}\\cdot 2\\pi/\\omega$ = {q * 2 * math.pi / omega:.5f} s",
        transform=b.transAxes,
        ha="left",
        va="top",
        fontsize=6.5,
    )
    return fig


def grazing_evidence(branch: dict, from_rest: dict, stats: dict, paper_omegas=(23.05, 23.03), window=(22.95, 23.3)):
    """Near-miss gap and impacts per period vs w along the branch and from rest, and a zoom
    of the bracket: gap of the misses with the fitted line, impact velocity of the contacts.

    branch/from_rest: dicts of per-w arrays (omega, min_gap m, impacts_per_period,
    min_impact_v m/s) from :func:`impactosc.dynamics.grazing.sweep_summary`; stats: the grazing
    statistics (bracket with trials, fit).
    """
    apply_style()
    # JSON null (no near miss / no impact) -> NaN
    branch = {k: np.asarray(v, dtype=float) for k, v in branch.items()}
    from_rest = {k: np.asarray(v, dtype=float) for k, v in from_rest.items()}
    fig = plt.figure(figsize=(DOUBLE, 11.5 / 2.54))
    gs = fig.add_gridspec(2, 2, width_ratios=[1.25, 1.0])
    a = fig.add_subplot(gs[0, 0])
    b = fig.add_subplot(gs[1, 0], sharex=a)
    c = fig.add_subplot(gs[:, 1])
    wstar = stats["bracket"]["midpoint"]
    lo, hi = window

    def in_win(d):
        w = np.asarray(d["omega"])
        return (w >= lo - 1e-9) & (w <= hi + 1e-9)

    for d, style, label in (
        (branch, dict(color="tab:blue", ms=2.2, marker="o", ls="-", lw=0.6), "branch, decreasing $\\omega$"),
        (
            from_rest,
            dict(color="tab:orange", ms=3.2, marker="s", mfc="none", ls="none", mew=0.7),
            "from rest at each $\\omega$",
        ),
    ):
        m = in_win(d)
        w = np.asarray(d["omega"])[m]
        a.plot(w, np.asarray(d["min_gap"])[m] * UM, label=label, **style)
        b.plot(w, np.asarray(d["impacts_per_period"])[m], label=label, **style)
    for ax in (a, b):
        for wp in paper_omegas:
            ax.axvline(wp, color="0.5", lw=0.6, ls=":")
        ax.axvline(wstar, color="tab:red", lw=0.8)
    a.plot([], [], color="0.5", lw=0.6, ls=":", label="paper: " + ", ".join(f"{wp:g}" for wp in paper_omegas))
    a.plot([], [], color="tab:red", lw=0.8, label=rf"grazing $\omega_g$ = {wstar:.5f}")
    a.set_ylabel(r"smallest near-miss gap $x_I - \max x$ ($\mu$m)")
    a.set_ylim(bottom=0)
    a.legend(loc="upper center", bbox_to_anchor=(0.62, 1.0), frameon=False)
    a.set_title("(a) near misses of the attractor", loc="left")
    b.set_ylabel("impacts per forcing period")
    b.set_xlabel(r"$\omega$ (rad/s)")
    b.set_xlim(lo, hi)
    b.set_ylim(0.8, 2.2)
    b.set_title("(b) impact count", loc="left")
    plt.setp(a.get_xticklabels(), visible=False)

    # (c) approach to grazing on log-log axes: the miss gap closes linearly, the impact
    # velocity of the new contact opens like a square root (both vanish at omega_g)
    fit = stats["gap_fit"]
    trials = stats["bracket"]["trials"]
    bw, gap, bv = branch["omega"], branch["min_gap"], branch["min_impact_v"]
    ipp = branch["impacts_per_period"]
    ref = stats["branch_step"]["impacts_per_period_before"]
    d = bw - wstar
    miss = (d > 0) & (d <= 0.01) & np.isfinite(gap) & np.isclose(ipp, ref)
    # contacts of the grazing orbit itself: impacts per period went up, no near miss left
    graze = (d < 0) & (d >= -0.01) & ~np.isfinite(gap)
    tw = np.array([t["omega"] for t in trials], dtype=float) - wstar
    tmiss = np.array([not t["contact"] for t in trials], dtype=bool)
    tg = np.array([t["min_gap"] for t in trials], dtype=float)
    tv = np.array([t["min_impact_v"] for t in trials], dtype=float)
    c.loglog(d[miss], gap[miss], "o", color="tab:blue", ms=3, label=r"branch: near-miss gap ($\omega > \omega_g$)")
    c.loglog(tw[tmiss], tg[tmiss], "D", color="tab:blue", mfc="none", ms=4, label="bisection: miss, gap")
    xs = np.logspace(-6.5, -2, 50)
    c.loglog(
        xs,
        fit["slope"] * (xs + wstar - fit["omega_zero"]),
        color="tab:blue",
        lw=0.6,
        ls="--",
        label=f"line through the last {len(fit['omega'])} gaps (zero at {fit['omega_zero']:.6f})",
    )
    c.loglog(-d[graze], bv[graze], "o", color="tab:red", ms=3, label=r"branch: slowest impact ($\omega < \omega_g$)")
    c.loglog(
        -tw[~tmiss], tv[~tmiss], "D", color="tab:red", mfc="none", ms=4, label="bisection: contact, slowest impact"
    )
    if np.any(~tmiss):
        k = np.argmax(np.where(~tmiss, -tw, -np.inf))
        c.loglog(
            xs,
            tv[k] * np.sqrt(xs / -tw[k]),
            color="tab:red",
            lw=0.6,
            ls=":",
            label=r"$\propto |\omega-\omega_g|^{1/2}$",
        )
    c.set_xlabel(r"$|\omega - \omega_g|$ (rad/s)")
    c.set_ylabel("gap (m, blue) / impact velocity (m/s, red)")
    br = stats["bracket"]
    c.set_title(
        f"(c) $\\omega_g$ = {wstar:.6f} rad/s,\nbracket [{min(br['omega_contact'], br['omega_miss']):.7f}, "
        f"{max(br['omega_contact'], br['omega_miss']):.7f}]",
        loc="left",
    )
    c.legend(loc="lower right", frameon=False, fontsize=6)
    return fig
