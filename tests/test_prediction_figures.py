"""Error bars on the bifurcation diagrams of a model with a covariance, and the Monte Carlo
check's verdicts, on synthetic predictions whose every number is known."""

import math

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

from impactosc.identification.predictions import check_row
from impactosc_study.figures.bifurcation import fig02_poincare, fig03b_isi
from impactosc_study.figures.uncertainty import _runs, draw_bands, draw_point_errors


def _predictions():
    """One period-1 segment: 6 orbits (the 4th unstable), one interval each; two located points."""
    w = [30.0, 31.0, 32.0, 33.0, 34.0, 35.0]
    band = {
        "omega": w,
        "stable": [True, True, True, False, True, True],
        "poincare_x": [[-1e-3 - 1e-5 * i] for i in range(6)],
        "se_poincare_x": [[2e-6]] * 6,
        "isis": [[2 * math.pi / wi] for wi in w],
        "se_isis": [[1e-4], [1e-4], [None], [1e-4], [1e-4], [1e-4]],  # a nan, read from JSON
    }
    points = [
        {"kind": "grazing", "omega": 30.5, "n_periods": 1, "se": 0.05, "note": ""},
        {"kind": "period_doubling", "omega": 34.5, "n_periods": 1, "se": 0.1, "note": ""},
        {"kind": "fold", "omega": 33.5, "n_periods": 1, "se": None, "note": "no sensitivity"},  # nan, read from JSON
    ]
    return [{"segment": "period1", "n_periods": 1, "points": points, "band": band}]


def test_bands_follow_stable_orbits_with_finite_errors_only():
    band = _predictions()[0]["band"]
    # Poincare x: orbits 0-2 and 4-5 (the unstable one splits the branch)
    assert [list(w) for w, _v, _s in _runs(band, "poincare_x")] == [[30.0, 31.0, 32.0], [34.0, 35.0]]
    # intervals: orbit 2 has no standard error, so 0-1 and 4-5
    assert [list(w) for w, _v, _s in _runs(band, "isis")] == [[30.0, 31.0], [34.0, 35.0]]


def test_band_and_error_bars_are_two_standard_errors():
    from matplotlib import pyplot as plt

    fig, ax = plt.subplots()
    ax.set_xlim(29, 36)
    draw_bands(ax, _predictions(), "poincare_x", 1e3)
    fill = ax.collections[0].get_paths()[0].vertices
    # the band of the first run spans x +- 2 se = +- 4e-6 m = +- 4e-3 mm
    assert fill[:, 1].max() - fill[:, 1].min() == pytest.approx((2e-5 + 8e-6) * 1e3, rel=1e-9)
    draw_point_errors(ax, _predictions(), (29, 36))
    bars = [c for c in ax.containers if hasattr(c, "has_xerr") and c.has_xerr]
    widths = sorted(np.ptp(b.lines[2][0].get_segments()[0][:, 0]) for b in bars)
    assert widths == pytest.approx([0.2, 0.4])  # 2 x 2 se of the grazing and of the doubling; the fold has none
    plt.close(fig)


def test_figures_with_uncertainty_have_the_width_panel_and_the_list():
    from matplotlib import pyplot as plt

    w = np.linspace(29, 36, 50)
    fig = fig02_poincare(w, -1e-3 + 0 * w, -2e-3, uncertainty=_predictions(), model="rig")
    assert len(fig.axes) == 4
    assert "grazing, period 1: 30.5000 $\\pm$ 0.05" in fig.axes[3].texts[0].get_text()
    plt.close(fig)
    fig = fig03b_isi(w, 2 * np.pi / w, zoom=(30, 31), uncertainty=_predictions(), model="rig")
    assert len(fig.axes) == 4
    plt.close(fig)
    fig = fig02_poincare(w, -1e-3 + 0 * w, -2e-3)  # no covariance: the paper's two panels only
    assert len(fig.axes) == 2
    plt.close(fig)


def test_monte_carlo_verdicts():
    rng = np.random.default_rng(0)
    point = {"kind": "period_doubling", "omega": 37.0, "se": 0.1}
    draws = 37.0 + 0.1 * rng.standard_normal(4000)
    agree = check_row(point, draws, [point], linear=draws - 0.03)
    assert agree["verdict"] == "agree" and agree["ratio"] == pytest.approx(1.0, abs=0.05)
    # relocated 0.3 se from the linear prediction of every draw; the spread's sampling error
    assert agree["nonlinearity_in_se"] == pytest.approx(0.3) and agree["spread_sampling_error"] == pytest.approx(
        1 / np.sqrt(2 * 3999)
    )
    wide = check_row(point, 37.0 + 0.13 * rng.standard_normal(4000), [point])
    assert wide["verdict"] == "DISAGREE"
    fold = {"kind": "fold", "omega": 37.3, "se": math.nan}
    draws = np.append(37.0 + 0.1 * rng.standard_normal(200), [np.nan, np.nan])
    near = check_row(point, draws, [point, fold], near=5.0)
    assert near["relocated"] == 200 and near["draws"] == 202
    assert "fold at w = 37.3000 (3.0 se)" in near["near"] and "2 draws not relocated" in near["near"]


def test_curves_with_bands_draw_two_standard_errors_and_the_width():
    from matplotlib import pyplot as plt

    from impactosc_study.figures.two_parameter import curves_band_figure

    curve = {
        "kind": "period_doubling",
        "points": [{"omega": 37.0 + 0.1 * i, "value": -2e-3 - 1e-4 * i} for i in range(5)],
    }
    band = {"omega": [37.0, 37.2, 37.4], "value": [-2e-3, -2.2e-3, -2.4e-3], "se": [0.01, None, 0.02]}
    fig = curves_band_figure({"d": curve}, {"d": band}, "xI", 1e3, "mm", own=-2.086e-3, model="rig")
    ax, width = fig.axes
    bars = [c for c in ax.containers if c.has_xerr and len(c.lines[2][0].get_segments())]
    assert sorted(np.ptp(seg[:, 0]) for seg in bars[0].lines[2][0].get_segments()) == pytest.approx([0.04, 0.08])
    # the width panel: 2 se at the two points that have one (the null one, nan, is left out)
    np.testing.assert_allclose(width.lines[0].get_xdata(), [0.02, 0.04])
    plt.close(fig)
