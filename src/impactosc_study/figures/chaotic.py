"""Figures 6-11 of the paper (chaotic regime, w = 40.86 rad/s).

Figures 6 and 7 are drawn from the scene's run file (trajectory window, Poincare points,
impact times); Figures 8-11 only from statistics JSON files of
:func:`impactosc.statistics.train_analysis.analyse_train`, so restyling reruns neither a simulation nor a
statistic.  Figures 8-10 take one train (the model) or two (model and a measured or
surrogate record, the paper's experimental panels); the second row/panel is labelled with
the train's own label, so a surrogate is never shown as an experiment.
"""

from __future__ import annotations

import numpy as np

from impactosc import statistics as st
from impactosc.io.files import read_json, read_run
from impactosc.statistics.spectral_lines import trajectory_spectrum
from impactosc_study.figures.style import DOUBLE, SINGLE, apply_style, plt

__all__ = ["fig06", "fig07", "fig08", "fig09", "fig10", "fig11", "make_figure"]

CM = 1 / 2.54
BAR = dict(color="0.75", edgecolor="0.35", linewidth=0.5)
C_MODEL = "C0"
C_MIX = "C3"


def _a(x):
    return np.asarray(x, dtype=float)


def _letter(ax, text):
    ax.set_title(text, loc="left", fontsize=8)


def _panel_name(i: int, stats: dict) -> str:
    return f"({'ab'[i]}) {stats['train']['label']}"


def fig06(trajectory: dict, omega: float, x_obstacle: float, portrait_span: float = 20.0, spectrum: dict | None = None):
    """(a) phase portrait of the chaotic attractor, (b) amplitude spectrum of x.

    The portrait shows the first ``portrait_span`` seconds of the window (the whole 400 s
    fill the attractor's outline into a solid blob); the spectrum uses the whole window.
    """
    apply_style()
    spectrum = spectrum or trajectory_spectrum(trajectory["t"], trajectory["x"], omega)
    fig, (a, b) = plt.subplots(1, 2, figsize=(DOUBLE, 6.0 * CM))
    t = _a(trajectory["t"])
    seg = t <= t[0] + portrait_span
    a.plot(1e3 * _a(trajectory["x"])[seg], _a(trajectory["v"])[seg], color=C_MODEL, lw=0.3, rasterized=True)
    a.axvline(1e3 * x_obstacle, color="k", ls="--", lw=0.7)
    a.annotate(
        r"obstacle $x_I$",
        (1e3 * x_obstacle, a.get_ylim()[1]),
        xytext=(-3, -8),
        textcoords="offset points",
        ha="right",
        va="top",
        fontsize=7,
    )
    a.set_xlabel("x (mm)")
    a.set_ylabel("v (m/s)")
    _letter(a, f"(a) phase portrait, t = {t[0]:.0f}..{t[seg][-1]:.0f} s")

    spec = spectrum["spectrum"]
    keep = (spec.omega > 0) & (spec.omega <= 4.2 * omega)
    b.semilogy(spec.omega[keep], 1e3 * spec.amplitude[keep], color=C_MODEL, lw=0.5)
    dom = spectrum["dominant_omega"]
    b.plot([dom], [2 * 1e3 * spectrum["peak_amplitude"][0]], "v", color="C3", ms=4)
    b.set_xlim(0, 4.2 * omega)
    b.set_ylim(1e3 * spec.amplitude[keep].max() * 1e-5, 1e3 * spec.amplitude[keep].max() * 30)
    b.set_xlabel(r"angular frequency (rad/s)")
    b.set_ylabel("amplitude of x (mm)")
    _letter(b, f"(b) spectrum of x, t = {t[0]:.0f}..{t[-1]:.0f} s")
    b.text(
        0.98,
        0.97,
        rf"dominant peak (marked) {dom:.2f} rad/s"
        "\n"
        rf"forcing $\omega$ = {omega:g} rad/s"
        "\n"
        f"{100 * spectrum['low_power_fraction']:.0f}% of the power below "
        f"{spectrum['low_band']:g}$\\omega$",
        transform=b.transAxes,
        ha="right",
        va="top",
        fontsize=7,
    )
    return fig


def fig07(poincare_x, impact_times):
    """(a) Poincare return map x_j -> x_{j+1} at phi = 2 pi i, (b) impact map S_j -> S_{j+1}."""
    apply_style()
    fig, (a, b) = plt.subplots(1, 2, figsize=(DOUBLE, 7.0 * CM))
    x0, x1 = st.return_map(1e3 * _a(poincare_x))
    a.plot(x0, x1, ".", ms=1.2, color=C_MODEL, rasterized=True)
    a.set_xlabel(r"$x_j$ (mm)")
    a.set_ylabel(r"$x_{j+1}$ (mm)")
    _letter(a, rf"(a) Poincaré return map, $\varphi = 2\pi i$ ({x0.size} pairs)")
    s0, s1 = st.return_map(st.inter_impact_intervals(impact_times))
    b.plot(s0, s1, ".", ms=1.2, color=C_MODEL, rasterized=True)
    b.set_xlabel(r"$S_j$ (s)")
    b.set_ylabel(r"$S_{j+1}$ (s)")
    _letter(b, f"(b) impact map ({s0.size} pairs)")
    for ax in (a, b):
        ax.set_aspect("equal", adjustable="datalim")
    return fig


def fig08(trains: list[dict]):
    """C_V^2 as the paper computed it, the dimensionless CV^2 and the Fano factor; one row per train."""
    apply_style()
    fig, axes = plt.subplots(len(trains), 3, figsize=(DOUBLE, 5.2 * CM * len(trains)), squeeze=False)
    for i, s in enumerate(trains):
        v = s["variability"]
        n = _a(v["sample_size"])
        a, b, c = axes[i]
        a.plot(n, v["cv2_paper_running"], color=C_MODEL)
        a.axhline(v["cv2_paper"], color="k", ls=":", lw=0.6)
        a.set_ylim(0, min(4 * v["cv2_paper"], max(v["cv2_paper_running"])))
        a.set_xlabel("sample size i")
        a.set_ylabel(r"$C_V^2$ = var/mean (s)")
        _letter(a, f"{_panel_name(i, s)}\npaper's $C_V^2$ -> {v['cv2_paper']:.4f} s")
        b.plot(n, v["cv2_running"], color="C2")
        b.axhline(1.0, color="0.5", ls="--", lw=0.7)
        b.text(n[-1], 0.97, "Poisson", ha="right", va="top", fontsize=7, color="0.4")
        b.set_ylim(0, 1.1)
        b.set_xlabel("sample size i")
        b.set_ylabel(r"var/mean$^2$ (dimensionless)")
        _letter(b, f"dimensionless CV$^2$ -> {v['cv2']:.3f}")
        f = v["fano"]
        w = _a(f["windows"])
        c.fill_between(w, f["poisson_low"], f["poisson_high"], color="0.85", lw=0, label="Poisson 95% band")
        c.axhline(1.0, color="0.5", ls="--", lw=0.7)
        c.plot(w, f["fano"], "o-", ms=3, color="C1", label="impact train")
        c.set_xscale("log")
        c.set_yscale("log")
        c.set_xlabel("counting window (s)")
        c.set_ylabel("Fano factor var(N)/mean(N)")
        c.legend(loc="lower left", frameon=False)
        _letter(c, "Fano factor of counts")
    return fig


def _density_panel(ax, d: dict, scale: float, color: str):
    """Relative-frequency bars, the kernel density scaled to bar heights and its maxima.

    The density is multiplied by the bin width so it is on the scale of the bars; each
    maximum is marked on the curve.
    """
    edges = scale * _a(d["histogram_edges"])
    ax.bar(
        edges[:-1],
        d["histogram_relative_frequency"],
        width=np.diff(edges),
        align="edge",
        label=f"{len(edges) - 1}-bin histogram",
        **BAR,
    )
    bw = d["bin_width"]
    grid = _a(d["kde_grid"])
    keep = grid >= 0  # positive quantities: do not draw the kernel tail below zero
    ax.plot(scale * grid[keep], bw * _a(d["kde_density"])[keep], color=color, label="kernel density")
    for m, h in zip(_a(d["maxima"]), _a(d["maxima_density"])):
        ax.plot([scale * m], [bw * h], "v", color=color, ms=4)
    ax.set_ylabel("relative frequency")
    ax.set_xlim(left=0)


def _label_maxima(ax, d: dict, scale: float, color: str, fmt: str, unit: str):
    """Label each density maximum with its position and relative height, above every
    bar and curve drawn at that position (call after drawing everything)."""
    edges = scale * _a(d["histogram_edges"])
    rf = _a(d["histogram_relative_frequency"])
    for m, r in zip(scale * _a(d["maxima"]), _a(d["maxima_relative_height"])):
        j = int(np.clip(np.searchsorted(edges, m) - 1, 0, rf.size - 1))
        y = max([rf[j]] + [float(np.interp(m, *line.get_data())) for line in ax.lines if np.size(line.get_xdata()) > 2])
        ax.annotate(
            f"{format(m, fmt)} {unit} ({r:.2f})",
            (m, y),
            xytext=(0, 3),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=6.5,
            color=color,
        )


def fig09(trains: list[dict]):
    """Relative-frequency ISI histogram, kernel density, its maxima and mixture fits."""
    apply_style()
    fig, axes = plt.subplots(
        1, len(trains), figsize=(max(1.15 * SINGLE, DOUBLE * len(trains) / 2), 7.0 * CM), squeeze=False
    )
    for i, s in enumerate(trains):
        ax, d = axes[0][i], s["isi_density"]
        _density_panel(ax, d, 1.0, C_MODEL)
        bw = d["bin_width"]
        mix = s.get("mixture")
        if mix:
            grid = _a(mix["grid"])
            k2 = mix["best_by_k"].get("2")
            if k2:
                ax.plot(
                    grid, bw * _a(mix["curves"][k2]["pdf"]), color=C_MIX, ls="--", label=f"2-component ML fit ({k2})"
                )
            if mix["best"] != k2:
                ax.plot(
                    grid,
                    bw * _a(mix["curves"][mix["best"]]["pdf"]),
                    color="C4",
                    ls=":",
                    label=f"BIC-best fit ({mix['best']})",
                )
        _label_maxima(ax, d, 1.0, C_MODEL, ".3f", "s")
        top = ax.get_ylim()[1]
        if d.get("forcing_period"):
            ax.axvline(
                d["forcing_period"],
                color="k",
                ls="-.",
                lw=0.7,
                label=rf"forcing period $2\pi/\omega$ = {d['forcing_period']:.3f} s",
            )
        ax.set_xlabel("inter-impact interval S (s)")
        ax.set_ylim(0, top * 1.5)
        ax.legend(loc="upper left", frameon=False, fontsize=6)
        _letter(ax, f"{_panel_name(i, s)}: {d['n']} intervals")
    return fig


def fig10(trains: list[dict]):
    """ACF of eq. (3) (left) and its Fourier transform (right); one row per train."""
    apply_style()
    fig, axes = plt.subplots(len(trains), 2, figsize=(DOUBLE, 5.6 * CM * len(trains)), squeeze=False)
    for i, s in enumerate(trains):
        a, b = axes[i]
        c = s["acf"]
        k = _a(c["k"])
        a.axhspan(-c["noise_level"], c["noise_level"], color="0.88", lw=0, label=r"$\pm 2/\sqrt{n}$ (uncorrelated)")
        a.vlines(k, 0, c["value"], color=C_MODEL, lw=0.8)
        a.plot(k, c["value"], "o", ms=2, color=C_MODEL)
        a.axhline(0, color="k", lw=0.5)
        a.set_xlabel("k (lag k - 1 intervals)")
        a.set_ylabel("ACF(k)")
        a.legend(loc="upper right", frameon=False)
        _letter(a, f"{_panel_name(i, s)}: ACF, eq. (3)")

        f = _a(c["frequency"])
        mag = _a(c["magnitude"])
        b.plot(f, mag, color=C_MODEL, label="one-sided spectrum")
        b.plot(1 - f, mag, color="0.65", lw=0.7, label="mirror image f -> 1 - f (two-sided DFT)")
        if c.get("surrogate_level") is not None:
            b.axhline(
                c["surrogate_level"],
                color="k",
                ls="--",
                lw=0.7,
                label=f"{100 * (1 - s['options']['alpha']):.0f}% level, shuffled ISIs",
            )
        for fp, mp, sig in zip(c["peak_frequency"], c["peak_magnitude"], c["significant"]):
            b.plot([fp], [mp], "v" if sig else "x", color="C3" if sig else "0.4", ms=4)
            b.annotate(
                f"{fp:.3f} ({1 / fp:.2f} int., {c['mean_isi'] / fp:.2f} s)",
                (fp, mp),
                xytext=(4, 2),
                textcoords="offset points",
                fontsize=6.5,
            )
        b.set_xlim(0, 1)
        b.set_ylim(0, 1.6 * mag.max())
        b.set_xlabel("frequency (cycles per interval)")
        b.set_ylabel("|Fourier transform of ACF|")
        b.legend(loc="upper right", frameon=False, fontsize=6)
        _letter(b, "Fourier transform of the ACF")
    return fig


def fig11(stats: dict):
    """Relative-frequency histogram of the maximal penetrations H_j and its modes."""
    apply_style()
    d = stats["penetrations"]
    if not d:
        raise ValueError(f"train {stats['train']['label']!r} has no penetrations to plot")
    fig, ax = plt.subplots(figsize=(1.15 * SINGLE, 6.5 * CM))
    _density_panel(ax, d, 1e6, C_MODEL)
    _label_maxima(ax, d, 1e6, C_MODEL, ".0f", "\u00b5m")
    ax.set_ylim(0, ax.get_ylim()[1] * 1.25)
    ax.set_xlabel(r"maximal penetration $H_j$ ($\mu$m)")
    ax.legend(loc="upper left", frameon=False, fontsize=6)
    _letter(ax, f"{stats['train']['label']}: {d['n']} penetrations, {d['n_modes']} modes")
    return fig


def make_figure(nn, run=None, stats=(), portrait_span: float | None = None):
    """Build paper figure ``nn`` (6-11) from a run file (6, 7) or statistics JSONs (8-11).

    Parameters
    ----------
    nn : int or str
        Figure number.
    run : path, optional
        HDF5 run file of the chaos scene (Figs 6 and 7).
    stats : sequence of paths
        Statistics JSON files (model first, then an optional second train) for Figs 8-11.
    portrait_span : float, optional
        Seconds of trajectory in the Fig 6a phase portrait (default 20).
    """
    nn = int(nn)
    if nn in (6, 7):
        if run is None:
            raise ValueError(f"figure {nn} needs the scene's run file")
        events, attrs, traj = read_run(run)
        if nn == 6:
            if traj is None:
                raise ValueError(f"{run} has no trajectory window; figure 6 needs one")
            return fig06(
                traj, attrs["omega"], attrs["param_xI"], portrait_span=20.0 if portrait_span is None else portrait_span
            )
        return fig07(events["poincare"]["x"], events["impacts"]["t"])
    if nn not in (8, 9, 10, 11):
        raise ValueError(f"figure {nn} is not in the chaotic group (6-11)")
    if not stats:
        raise ValueError(f"figure {nn} needs at least one statistics file")
    trains = [read_json(p) for p in stats]
    if nn == 11:
        return fig11(trains[0])
    return {8: fig08, 9: fig09, 10: fig10}[nn](trains)
