"""Supplementary figure of the measured-records group: sensor noise and sampling against
the extracted impact train (timing error, C_V^2, ISI bimodality).

Reads the rows of :func:`impactosc.measured.surrogate.noise_study` (as stored in its JSON).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from .style import DOUBLE, apply_style

__all__ = ["noise_study_figure"]


def _um(rows):
    return np.array([1e6 * r["noise_m"] for r in rows])


def noise_study_figure(rows: list[dict], density_rate: float):
    """(a) timing error vs noise, (b) C_V^2 vs noise, (c) ISI densities at one rate."""
    apply_style()
    fig, ax = plt.subplots(1, 3, figsize=(DOUBLE, 0.36 * DOUBLE))
    rates = sorted({r["rate_hz"] for r in rows})
    colors = dict(zip(rates, plt.cm.viridis(np.linspace(0, 0.8, len(rates)))))
    for rate in rates:
        c = colors[rate]
        hy = [r for r in rows if r["rate_hz"] == rate and r["method"] == "hysteresis"]
        nv = [r for r in rows if r["rate_hz"] == rate and r["method"] == "naive threshold"]
        ex = [r for r in rows if r["rate_hz"] == rate and r["method"] == "exact events"]
        ax[0].plot(
            _um(hy), [r["timing_rms_s"] * 1e3 for r in hy], "o-", color=c, ms=3, label=f"{rate / 1e3:g} kHz rms error"
        )
        ax[0].plot(
            _um(hy),
            [r["sigma_t_median_s"] * 1e3 for r in hy],
            "--",
            color=c,
            label=f"{rate / 1e3:g} kHz stated $\\sigma_t$ (median)",
        )
        ok = [r for r in hy if "cv2_paper" in r]
        ax[1].plot(_um(ok), [r["cv2_paper"] for r in ok], "o-", color=c, ms=3, label=f"{rate / 1e3:g} kHz, hysteresis")
        okn = [r for r in nv if "cv2_paper" in r]
        ax[1].plot(
            _um(okn), [r["cv2_paper"] for r in okn], "x:", color=c, ms=3, label=f"{rate / 1e3:g} kHz, naive threshold"
        )
        if ex:
            ax[1].axhline(ex[0]["cv2_paper"], color=c, lw=0.5, alpha=0.6)
    for a in ax[:2]:
        a.set_xscale("symlog", linthresh=1.0)
        a.set_xlim(left=-0.2)
        a.set_xlabel("sensor noise std (um)")
    ax[0].set_yscale("log")
    ax[0].set_ylabel("impact-time error (ms)")
    ax[0].set_title("(a) timing: actual rms vs stated")
    ax[0].legend(fontsize=5, ncol=1, loc="lower right")
    ax[1].set_ylabel(r"$C_V^2$ = var/mean of the ISIs (s)")
    ax[1].set_title("(b) $C_V^2$ (thin lines: exact events)")
    ax[1].legend(fontsize=5, loc="upper left")
    dens = [
        r
        for r in rows
        if r["rate_hz"] == density_rate and "kde_grid" in r and r["method"] in ("exact events", "hysteresis")
    ]
    if not dens:
        raise ValueError(f"density_rate {density_rate} Hz is not one of the study's rates {rates}")
    shades = plt.cm.plasma(np.linspace(0, 0.85, max(len(dens) - 1, 1)))
    for k, r in enumerate(dens):
        if r["method"] == "exact events":
            ax[2].plot(r["kde_grid"], r["kde_density"], color="k", lw=1.6, label="exact events")
        else:
            ax[2].plot(
                r["kde_grid"],
                r["kde_density"],
                color=shades[k - 1],
                lw=0.8,
                label=f"{1e6 * r['noise_m']:g} um ({r['isi_n_modes']} max.)",
            )
    ax[2].set_xlabel("inter-impact interval S (s)")
    ax[2].set_ylabel("kernel density (1/s)")
    ax[2].set_title(f"(c) ISI density at {density_rate / 1e3:g} kHz")
    ax[2].legend(fontsize=5)
    return fig
