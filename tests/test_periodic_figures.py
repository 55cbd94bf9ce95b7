"""The periodic-group figure builders run on small synthetic inputs and write PNG + PDF."""

import math

import numpy as np
import pytest

from impactosc.statistics.periodic_train import impact_map_numbers
from impactosc_study.figures import save_figure
from impactosc_study.figures.periodic import fig03a_impact_construction, fig05_impact_map, grazing_evidence
from impactosc_study.figures.schematic import fig01_rig

XI = -2.086e-3


def _saved(fig, tmp_path, name):
    png, pdf = tmp_path / f"{name}.png", tmp_path / f"{name}.pdf"
    save_figure(fig, png, pdf)
    assert png.stat().st_size > 10_000 and pdf.stat().st_size > 5_000
    return png


def test_fig01(tmp_path):
    fig = fig01_rig()
    texts = " ".join(t.get_text() for t in fig.axes[0].texts)
    for symbol in ("$k$", "$c$", "$m_0$", "$e$", r"$\varphi$", "$x_I$", r"$k_I,\ b$"):
        assert symbol in texts, symbol
    _saved(fig, tmp_path, "fig01")


def test_fig03a_marks_every_crossing(tmp_path):
    t = np.arange(0.0, 2.0, 1e-3)
    x = XI - 1e-3 + 1.2e-3 * np.sin(2 * math.pi * 3 * t)  # crosses xI upwards 6 times
    up = t[1:][(x[:-1] < XI) & (x[1:] >= XI)]
    fig = fig03a_impact_construction(t, x, up, XI, 0.0, 2.0)
    labels = [tx.get_text() for tx in fig.axes[0].texts]
    assert sum(lb.startswith("$T_") for lb in labels) == up.size == 6
    assert sum(lb.startswith("$S_") for lb in labels) == 5
    _saved(fig, tmp_path, "fig03a")
    with pytest.raises(ValueError, match="at least 2 impacts"):
        fig03a_impact_construction(t, x, up[:1], XI, 0.0, 2.0)


def test_fig05(tmp_path):
    levels = np.array([0.0903, 0.1952, 0.2599])
    s = np.tile(np.r_[levels, 3 * 2 * math.pi / 23.03 - levels.sum()], 122)
    t = np.r_[0.0, np.cumsum(s)]
    fig = fig05_impact_map(np.diff(t), impact_map_numbers(t, 23.03).to_dict(), 23.03)
    assert "0.8184" in " ".join(tx.get_text() for tx in fig.axes[1].texts)
    _saved(fig, tmp_path, "fig05")


def test_grazing_figure(tmp_path):
    w = np.round(np.arange(23.3, 22.95, -0.001), 9)
    wg = 23.0441
    gap = np.where(w > wg, 1.1e-3 * (w - wg), np.nan)
    ipp = np.where(w > wg, 1.0, 4 / 3)
    v = np.where(w > wg, 0.076, 0.014)
    branch = {"omega": w, "min_gap": gap, "impacts_per_period": ipp, "min_impact_v": v}
    trials = [
        {
            "omega": wg + d,
            "contact": d < 0,
            "min_gap": 1.1e-3 * d if d > 0 else None,
            "min_impact_v": 1e-2 * math.sqrt(-d) if d < 0 else 0.076,
        }
        for d in (5e-4, -2e-4, 1e-4, -5e-5)
    ]
    stats = {
        "bracket": {"midpoint": wg, "omega_miss": wg + 1e-4, "omega_contact": wg - 5e-5, "trials": trials},
        "gap_fit": {"omega_zero": wg, "slope": 1.1e-3, "omega": [23.049, 23.048, 23.047, 23.046, 23.045]},
        "branch_step": {"impacts_per_period_before": 1.0},
    }
    fig = grazing_evidence(branch, {k: a[::5] for k, a in branch.items()}, stats)
    assert len(fig.axes) == 3  # (a) gap, (b) impact count, (c) log-log approach to grazing
    c = fig.axes[2]
    assert c.get_xscale() == "log" and c.get_yscale() == "log"
    assert len(c.get_legend().get_texts()) == 6  # misses, contacts (branch, bisection), gap line, sqrt law
    _saved(fig, tmp_path, "grazing")
