"""Figure of the dynamic-noise study (:mod:`impactosc_study.dynamic_noise`): the pooled ISI densities of
the chaotic scene under each noise in the dynamics, and how far each statistic moves with intensity."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from impactosc_study.figures.style import DOUBLE, apply_style

#: statistics drawn against intensity: (column, label)
_STATS = (
    ("cv2_paper", "$C_V^2$ (paper, s)"),
    ("holt_cv2", "CV2"),
    ("lv", "LV"),
    ("serial_correlation_1", "r(1)"),
    ("acf_peak_frequency", "ACF peak freq."),
    ("penetration_n_modes", "penetration modes"),
    ("n_impacts", "impacts"),
)
_NAMES = {"motor": "motor speed jitter", "force": "random force on the cart"}


def dynamic_noise_figure(ladders: list[dict], found: dict):
    """Top: pooled ISI kernel densities per level (black: no noise); bottom: each statistic at each
    level relative to the noise-free run (r(1): difference), per noise."""
    apply_style()
    fig, axes = plt.subplots(2, len(ladders), figsize=(DOUBLE, 0.62 * DOUBLE), squeeze=False, layout="constrained")
    for col, ladder in enumerate(ladders):
        rows = sorted(ladder["rows"], key=lambda r: r["rms"])
        name, unit = rows[0]["noise"], rows[0]["unit"]
        top, bottom = axes[0, col], axes[1, col]
        dens = sorted(ladder["densities"], key=lambda d: d["rms"])
        shades = plt.cm.plasma(np.linspace(0, 0.85, max(len(dens) - 1, 1)))
        for k, d in enumerate(dens):
            style = {"color": "k", "lw": 1.5} if d["rms"] == 0 else {"color": shades[k - 1], "lw": 0.9}
            top.plot(d["grid"], d["density"], label=f"{d['rms']:g} {unit}", **style)
        merged = found[name]["merge_rms"]
        verdict = f"merge at {merged:g} {unit}" if merged is not None else "no merge"
        top.set_title(f"({'ab'[col]}) {_NAMES[name]}, tau {rows[0]['tau_s']:g} s: {verdict}", fontsize=6)
        top.set_xlabel("inter-impact interval (s)")
        top.set_ylabel("density (pooled seeds)")
        top.legend(fontsize=5, title="rms", title_fontsize=5)
        base = rows[0]
        levels = [r["rms"] for r in rows[1:]]
        for key, label in _STATS:
            if key == "serial_correlation_1":
                values = [r[key] - base[key] for r in rows[1:]]
            else:
                values = [r[key] / base[key] - 1 if base[key] else np.nan for r in rows[1:]]
            bottom.plot(levels, values, "o-", ms=3, label=label)
        bottom.axhline(0.0, color="k", lw=0.5)
        bottom.set_xscale("log")
        bottom.set_xlabel(f"{_NAMES[name]} rms ({unit})")
        bottom.set_ylabel("change from no noise")
        bottom.set_title(f"({'cd'[col]}) means of {rows[-1]['members']} seeds, relative (r(1): difference)", fontsize=6)
        bottom.legend(fontsize=5)
    return fig
