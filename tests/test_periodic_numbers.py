"""Section 2.1 numbers, Poincare period and the Fig 4c spectrum analysis on synthetic input."""

import json
import math

import numpy as np
import pytest

from impactosc.io.files import write_json
from impactosc.statistics.periodic_train import impact_map_numbers
from impactosc.statistics.periods import poincare_period
from impactosc.statistics.spectral_lines import analyse_spectrum
from impactosc_study.paper.rows.periodic import periodic_rows as table_rows

OMEGA = 23.03
LEVELS = np.array([0.09034927, 0.19520570, 0.25988248])  # s


def period3_train():
    """4 impacts per 3 forcing periods: the fourth interval closes 3 * 2 pi / w exactly."""
    last = 3 * 2 * math.pi / OMEGA - LEVELS.sum()
    s = np.tile(np.r_[LEVELS, last], 122)
    return 200.0 + np.r_[0.0, np.cumsum(s)]


def test_impact_map_numbers_period3():
    n = impact_map_numbers(period3_train(), OMEGA)
    assert n.n_impacts == 489 and len(n.levels) == 4 and n.counts == (122, 122, 122, 122)
    assert n.counts_equal
    assert n.periods_in_total == pytest.approx(3.0, abs=1e-9)
    assert n.orbit_period == pytest.approx(3 * 2 * math.pi / OMEGA, rel=1e-12)
    with pytest.raises(ValueError, match="omega"):
        impact_map_numbers(period3_train(), -1.0)


def test_poincare_period():
    rng = np.random.default_rng(3)
    cyc = rng.normal(size=(3, 2))
    pts = np.tile(cyc, (20, 1)) + rng.normal(scale=1e-10, size=(60, 2))
    assert poincare_period(pts[:, 0], pts[:, 1]) == 3
    assert poincare_period(np.full(10, 1.0), np.zeros(10)) == 1
    assert poincare_period(rng.normal(size=40), rng.normal(size=40)) == 0  # no period: chaos-like
    with pytest.raises(ValueError, match="same length"):
        poincare_period([1.0, 2.0], [1.0])


def synthetic_x(omega1, t):
    """Lines at w1 and the paper's combinations plus harmonics of w, amplitudes ~ Fig 4c."""
    w = OMEGA
    x = 1e-3 * np.sin(w * t) + 5e-4 * np.sin(omega1 * t + 0.3) + 3e-4 * np.sin(2 * w * t + 1.0)
    for k, m, a in ((1, -1, 4e-5), (1, 1, 3e-4), (2, -1, 1e-4), (2, 1, 1e-4), (3, -1, 8e-5)):
        x += a * np.sin((k * w + m * omega1) * t + 0.1 * k)
    return x


def test_spectrum_finds_w_over_3():
    t = np.arange(0, 100.0, 1e-3)
    sp = analyse_spectrum(synthetic_x(OMEGA / 3, t), 1e-3, OMEGA)
    assert not sp.harmonics_only
    assert sp.omega1 == pytest.approx(OMEGA / 3, abs=0.1 * sp.resolution)
    assert sp.ratio_fraction == (1, 3)
    assert all(math.isfinite(v["found"]) for v in sp.labels.values())
    for v in sp.labels.values():
        assert v["found"] == pytest.approx(v["expected"], abs=sp.resolution)


def test_spectrum_incommensurate_w1_is_not_a_small_fraction():
    t = np.arange(0, 100.0, 1e-3)
    w1 = OMEGA * (math.sqrt(5) - 1) / 2 * 0.5  # 0.309 w: golden-ratio based, irrational
    sp = analyse_spectrum(synthetic_x(w1, t), 1e-3, OMEGA, max_denominator=12)
    assert sp.omega1 == pytest.approx(w1, abs=0.1 * sp.resolution)
    p, q = sp.ratio_fraction
    assert abs(sp.omega1 - p / q * OMEGA) > sp.resolution  # the nearest small fraction is off by > 1 bin


def test_spectrum_harmonics_only():
    t = np.arange(0, 60.0, 1e-3)
    x = 1e-3 * np.sin(OMEGA * t) + 2e-4 * np.sin(2 * OMEGA * t + 0.5) + 5e-5 * np.sin(3 * OMEGA * t)
    sp = analyse_spectrum(x, 1e-3, OMEGA)
    assert sp.harmonics_only and math.isnan(sp.omega1) and sp.labels == {}


def test_write_json_maps_nan_to_null(tmp_path):
    p = tmp_path / "a.json"
    write_json(p, {"a": math.nan, "b": [1.0, np.inf], "c": np.int64(3), "d": np.bool_(True)})
    data = json.loads(p.read_text())
    assert "git_commit" in data.pop("provenance")  # the writer's own entry (impactosc.io.files.provenance)
    assert data == {"a": None, "b": [1.0, None], "c": 3, "d": True}


def test_table_rows_agreement_logic():
    im = {
        "n_impacts": 489,
        "levels": [0.09, 0.195, 0.26, 0.273],
        "counts": [122] * 4,
        "n_levels": 4,
        "counts_equal": True,
        "total": 0.81848,
        "periods_in_total": 3.0,
        "orbit_period": 0.81848,
    }
    sp = {
        "omega1": OMEGA / 3,
        "omega1_over_omega": 1 / 3,
        "omega1_over_omega_fraction": [1, 3],
        "resolution": 0.06,
        "labels": {k: {"found": 1.0} for k in "abcdf"},
        "harmonics_only": False,
    }
    after = {
        "omega": OMEGA,
        "duration": 100.0,
        "transient": 200.0,
        "impact_map": im,
        "spectrum": sp,
        "poincare_period": 3,
    }
    before = {
        "omega": 23.05,
        "spectrum": {"harmonics_only": True},
        "poincare_period": 1,
        "impacts_per_period": 1.0,
        "min_gap": 6.4e-6,
    }
    rest = {"omega": 23.05, "impact_map": im, "poincare_period": 3}
    grazing = {
        "bracket": {"omega_contact": 23.04411, "omega_miss": 23.04413, "width": 2e-5},
        "omega_g": 23.04412,
        "paper_omegas": [23.05, 23.03],
        "gap_fit": {"omega_zero": 23.044122},
        "between_paper_omegas": True,
    }
    rows = table_rows(
        {"after_grazing": after, "before_grazing_branch": before, "before_grazing_from_rest": rest}, grazing
    )
    agrees = {r["quantity"]: r["agrees"] for r in rows}
    assert sum(a == "yes" for a in agrees.values()) == 7
    assert any(a == "lines yes; quasi-periodic reading no" for a in agrees.values())
    assert any(a == "yes on the branch" for a in agrees.values())
    im["total"] = 0.8190  # off by more than the paper's last digit
    rows = table_rows(
        {"after_grazing": after, "before_grazing_branch": before, "before_grazing_from_rest": rest}, grazing
    )
    assert [r["agrees"] for r in rows if r["quantity"].startswith("sum of the four")] == ["no"]
