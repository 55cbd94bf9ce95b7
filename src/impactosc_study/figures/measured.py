"""Supplementary figure of the measured-records group: sensor noise and sampling against
the extracted impact train (timing error and its Cramer-Rao bound, C_V^2, ISI bimodality,
the obstacle estimate, the sensor-realism cases).

Reads the rows of :func:`impactosc_study.noise_study.noise_study` (as stored in its JSON).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["noise_study_figure"]


def _um(rows):
    return np.array([1e6 * r["noise_m"] for r in rows])


def noise_study_figure(rows: list[dict], density_rate: float):
    """(a) timing error vs noise, (b) C_V^2 vs noise, (c) ISI densities at one rate,
    (d) timing error against its Cramer-Rao bound, (e) the obstacle estimate's error with its
    stated 2 sigma, (f) the sensor-realism cases."""
    apply_style()
    fig, axes = plt.subplots(2, 3, figsize=(DOUBLE, 0.72 * DOUBLE))
    ax = axes.ravel()
    rates = sorted({r["rate_hz"] for r in rows if not r["method"].startswith("realism")})
    colors = dict(zip(rates, plt.cm.viridis(np.linspace(0, 0.8, len(rates)))))
    for rate in rates:
        c = colors[rate]
        hy = [r for r in rows if r["rate_hz"] == rate and r["method"] == "hysteresis"]
        nv = [r for r in rows if r["rate_hz"] == rate and r["method"] == "naive threshold"]
        ex = [r for r in rows if r["rate_hz"] == rate and r["method"] == "exact events"]
        ax[0].plot(_um(hy), [r["timing_rms_s"] * 1e3 for r in hy], "o-", color=c, ms=3, label=f"{rate / 1e3:g} kHz")
        ax[0].plot(_um(hy), [r["sigma_t_median_s"] * 1e3 for r in hy], "--", color=c)
        ok = [r for r in hy if "cv2_paper" in r]
        ax[1].plot(_um(ok), [r["cv2_paper"] for r in ok], "o-", color=c, ms=3, label=f"{rate / 1e3:g} kHz")
        okn = [r for r in nv if "cv2_paper" in r]
        ax[1].plot(_um(okn), [r["cv2_paper"] for r in okn], "x:", color=c, ms=3)
        if ex:
            ax[1].axhline(ex[0]["cv2_paper"], color=c, lw=0.5, alpha=0.6)
        _crb_panel(ax[3], hy, c, rate)
        _x_impact_panel(ax[4], hy, c, rate, rates.index(rate) - (len(rates) - 1) / 2)
    for a in (ax[0], ax[1], ax[3], ax[4]):
        a.set_xscale("symlog", linthresh=1.0)
        a.set_xlim(left=-0.2)
        a.set_xlabel("sensor noise std (um)")
    ax[0].set_yscale("log")
    ax[0].set_ylabel("impact-time error (ms)")
    ax[0].set_title("(a) timing: rms error (o-), stated $\\sigma_t$ (--)", fontsize=7)
    ax[0].legend(fontsize=5, ncol=2, loc="upper left")
    ax[1].set_ylabel(r"$C_V^2$ = var/mean of the ISIs (s)")
    ax[1].set_title("(b) $C_V^2$: hysteresis (o-), naive (x:), exact (thin)", fontsize=7)
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
    ax[3].axhline(1.0, color="k", lw=0.6)
    ax[3].set_ylabel("rms of timing error / bound")
    ax[3].set_title("(d) timing error / Cramer-Rao bound")
    ax[3].legend(fontsize=5)
    ax[4].axhspan(-3, 3, color="0.9", zorder=0, label="+-3 um")
    ax[4].axhline(0.0, color="k", lw=0.6)
    ax[4].set_ylabel(r"estimated - true $x_I$ (um)")
    ax[4].set_title(r"(e) $x_I$ estimate (bars: 2$\sigma$)")
    ax[4].legend(fontsize=5)
    _realism_panel(ax[5], [r for r in rows if r["method"].startswith("realism")])
    return fig


def _crb_panel(ax, hy, color, rate):
    """timing_crb_ratio (rms of error / bound) of the hysteresis rows with noise against noise
    (without noise the error is the fit's model error alone, which no noise bound describes)."""
    ok = [r for r in hy if r["noise_m"] > 0 and np.isfinite(r.get("timing_crb_ratio", np.nan))]
    ax.plot(_um(ok), [r["timing_crb_ratio"] for r in ok], "o-", color=color, ms=3, label=f"{rate / 1e3:g} kHz")


def _x_impact_panel(ax, hy, color, rate, shift):
    """x_impact error +- 2 stated sigma against noise (points shifted by rate for legibility)."""
    ok = [r for r in hy if np.isfinite(r.get("x_impact_err_m", np.nan))]
    if not ok:
        return
    x = _um(ok) * (1.0 + 0.06 * shift)
    err = [1e6 * r["x_impact_err_m"] for r in ok]
    bar = [2e6 * r["x_impact_sigma_m"] for r in ok]
    ax.errorbar(x, err, yerr=bar, fmt="o", color=color, ms=3, capsize=1.5, lw=0.8, label=f"{rate / 1e3:g} kHz")


def _realism_panel(ax, rows):
    """Per sensor-realism case: |timing bias| and rms timing error (symlog, us)."""
    if not rows:
        ax.set_axis_off()
        return
    names = [r["method"].removeprefix("realism: ") for r in rows]
    y = np.arange(len(rows))
    bias = [1e6 * abs(r["timing_bias_s"]) for r in rows]
    rms = [1e6 * r["timing_rms_s"] for r in rows]
    ax.barh(y - 0.2, bias, height=0.4, color="C3", label="|timing bias|")
    ax.barh(y + 0.2, rms, height=0.4, color="C0", label="rms timing error")
    ax.set_yticks(y, ["\n".join(_wrap(n)) for n in names], fontsize=5)
    ax.invert_yaxis()
    ax.set_xscale("symlog", linthresh=10.0)
    ax.set_xlabel("us")
    ax.set_xlim(0, 10 ** np.ceil(np.log10(max(*bias, *rms))))
    ax.set_title("(f) sensor realism")
    ax.legend(fontsize=5, loc="upper center", bbox_to_anchor=(0.5, -0.25), ncol=2)


def _wrap(text, width=28):
    """Split a case name at '; ' and ', ' into lines of about ``width`` characters."""
    lines, line = [], ""
    for word in text.replace("; ", ", ").split(", "):
        if line and len(line) + len(word) > width:
            lines.append(line)
            line = word
        else:
            line = f"{line}, {word}" if line else word
    return [*lines, line]
