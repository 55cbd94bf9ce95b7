"""Train-level analysis (impactosc.statistics.train_analysis) on synthetic impact trains with known answers.

Poisson train: C_V^2 = 1, Fano factor 1, exponential intervals, no ACF periodicity, one
mixture component.  Periodic train: C_V^2 = 0, Fano << 1, KS rejects.  A known two-component
gamma mixture of intervals is recovered with its weights and modes.  A period-3
short-long-long train gives the f = 1/3 ACF-spectrum peak.  Tolerances are stated per test
from the sampling error of each statistic at the sample size used.
"""

import json
import math

import numpy as np
import pytest

from impactosc.io.files import read_json, write_csv, write_json, write_run
from impactosc.statistics import train_analysis as ch
from impactosc.statistics.ensemble import ensemble_runs, ensemble_summary, ensemble_table
from impactosc.statistics.impact_train import AnalysisOptions, ImpactTrain, load_train
from impactosc.statistics.spectral_lines import trajectory_spectrum

# Fast settings: fewer EM restarts, bootstrap replicates and surrogates than the workflow.
FAST = dict(mixture_components=(1, 2), mixture_restarts=4, ks_bootstrap=199, acf_surrogates=100)


def _train(intervals, t0=100.0, **kw):
    """Train from intervals, observed from t0 to just after the last impact."""
    times = t0 + 0.01 + np.concatenate([[0.0], np.cumsum(intervals)])
    return ImpactTrain(times, t0, float(times[-1]) + 0.01, **kw)


@pytest.fixture(scope="module")
def poisson_stats():
    """Poisson train, rate 7/s on 400 s (about 2800 impacts, like the chaotic scene)."""
    rng = np.random.default_rng(20240601)
    n = rng.poisson(7.0 * 400.0)
    times = np.sort(rng.uniform(100.0, 500.0, n))
    train = ImpactTrain(times, 100.0, 500.0, omega=40.86, label="poisson")
    return ch.analyse_train(train, AnalysisOptions(**FAST))


@pytest.fixture(scope="module")
def mixture_sample():
    """n=3000 intervals from 0.4 Gamma(6, 0.01 s) + 0.6 Gamma(21, 0.01 s): modes 0.05 s, 0.2 s."""
    rng = np.random.default_rng(11)
    n = 3000
    first = rng.random(n) < 0.4
    return np.where(first, rng.gamma(6.0, 0.01, n), rng.gamma(21.0, 0.01, n)), first


@pytest.fixture(scope="module")
def mixture_stats(mixture_sample):
    s, _ = mixture_sample
    rng = np.random.default_rng(3)
    # penetrations: three gaussian modes at 60, 120 and 190 um, the deepest the most frequent
    h = np.concatenate([rng.normal(60e-6, 6e-6, 600), rng.normal(120e-6, 8e-6, 800), rng.normal(190e-6, 5e-6, 1601)])
    train = _train(s, penetrations=h, omega=40.86, label="mixture")
    return ch.analyse_train(train, AnalysisOptions(**FAST))


# --------------------------------------------------------------------------- Poisson


def test_poisson_variability(poisson_stats):
    v = poisson_stats["variability"]
    # sample CV^2 of n ~ 2800 exponential intervals: sd about sqrt(8/n) ~ 0.05 -> 3 sd
    assert abs(v["cv2"] - 1.0) < 0.16
    # the paper's dimensionful version is CV^2 * mean = about 1/7 s here
    assert v["cv2_paper"] == pytest.approx(v["cv2"] * poisson_stats["train"]["mean_isi"], rel=2e-3)
    f = np.asarray(v["fano"]["fano"])
    # Fano factor 1: inside the Poisson 95% band for (almost) every window length
    inside = (f >= v["fano"]["poisson_low"]) & (f <= v["fano"]["poisson_high"])
    assert inside.sum() >= f.size - 1, f
    assert abs(f[0] - 1.0) < 0.1  # 1600 windows of 0.25 s: sd of F ~ sqrt(2/1600) = 0.035


def test_poisson_tests_do_not_reject(poisson_stats):
    assert not poisson_stats["poisson"]["rejected"]
    assert not poisson_stats["stationarity"]["rejected"]
    assert poisson_stats["stationarity"]["counts"].sum() == poisson_stats["train"]["n_impacts"]


def test_poisson_no_periodicity_one_component(poisson_stats):
    acf = poisson_stats["acf"]
    assert acf["n_significant"] == 0
    mix = poisson_stats["mixture"]
    # exponential = gamma with shape 1: one component, gamma family
    assert mix["best"] == "gamma x1"
    fit = next(f for f in mix["fits"] if f["family"] == "gamma" and f["n_components"] == 1)
    assert fit["params"]["shape"][0] == pytest.approx(1.0, abs=0.08)  # ML shape sd ~ 0.02


# -------------------------------------------------------------------------- periodic


def test_periodic_train():
    rng = np.random.default_rng(5)
    train = _train(0.1 + rng.normal(0.0, 1e-4, 3000), omega=40.86, label="periodic")
    s = ch.analyse_train(train, AnalysisOptions(**FAST), parts=("stationarity", "variability", "poisson"))
    assert s["variability"]["cv2"] < 1e-5  # (1e-4 / 0.1)^2 = 1e-6
    # a periodic count in a window of w = (m + p) periods is m or m + 1 (fraction p of the
    # windows): F = p (1 - p) / (w / T) <= 0.25 T / w; 1e-4 s jitter adds nothing visible
    fano = s["variability"]["fano"]
    bound = 0.25 * 0.1 / np.asarray(fano["windows"])
    assert np.all(np.asarray(fano["fano"]) <= bound * 1.1 + 1e-3), fano["fano"]
    assert np.all(s["variability"]["fano"]["below_poisson"])
    assert s["poisson"]["rejected"]
    assert not s["stationarity"]["rejected"]
    c = s["stationarity"]["counts"]
    assert c.max() - c.min() <= 1


# --------------------------------------------------------------------------- mixture


def test_mixture_recovered(mixture_stats, mixture_sample):
    _, first = mixture_sample
    mix = mixture_stats["mixture"]
    assert mix["best"] == "gamma x2"
    assert mix["delta_bic_2_vs_1"] > 100
    fit = next(f for f in mix["fits"] if f["family"] == "gamma" and f["n_components"] == 2)
    # weights: binomial sd sqrt(0.24/3000) ~ 0.009 -> 4 sd
    np.testing.assert_allclose(fit["weights"], [first.mean(), 1 - first.mean()], atol=0.035)
    # modes (shape - 1) * scale = 0.05 and 0.2 s; ML scatter of the modes is a few ms
    np.testing.assert_allclose(fit["modes"], [0.05, 0.20], atol=0.006)
    # mixture curves are stored on the kernel-density grid and integrate to about 1
    grid = np.asarray(mix["grid"])
    pdf = np.asarray(mix["curves"]["gamma x2"]["pdf"])
    assert np.trapezoid(pdf, grid) == pytest.approx(1.0, abs=0.01)
    comps = np.asarray(mix["curves"]["gamma x2"]["components"])
    np.testing.assert_allclose(comps.sum(axis=0), pdf, rtol=1e-10)


def test_isi_density_maxima_and_forcing(mixture_stats):
    d = mixture_stats["isi_density"]
    assert d["n_modes"] == 2
    # kernel maxima are shifted towards each other by the smoothing (bandwidth ~ 0.013 s)
    np.testing.assert_allclose(d["maxima"], [0.05, 0.2], atol=0.012)
    assert d["histogram_relative_frequency"].sum() == pytest.approx(1.0)
    assert d["histogram_edges"].size == 11
    assert d["forcing_period"] == pytest.approx(2 * math.pi / 40.86)
    assert not d["forcing_is_maximum"]
    sc = d["scales"]
    assert sc["short_fraction"] == pytest.approx(0.4, abs=0.03)
    assert 0.05 < sc["split"] < 0.2


def test_penetration_modes(mixture_stats):
    p = mixture_stats["penetrations"]
    assert p["n_modes"] == 3
    np.testing.assert_allclose(p["maxima"], [60e-6, 120e-6, 190e-6], atol=6e-6)
    assert p["main_is_deepest"]
    assert p["maxima_relative_height"][-1] == 1.0


# ------------------------------------------------------------------------------ ACF


def test_period3_pattern_gives_one_third_peak():
    rng = np.random.default_rng(8)
    n = 1000
    pattern = np.tile([0.05, 0.2, 0.2], n)
    s = pattern + rng.normal(0.0, 0.03, pattern.size).clip(-0.04, 0.04)
    stats = ch.analyse_train(_train(s), AnalysisOptions(**FAST), parts=("isi_density", "acf"))
    acf = stats["acf"]
    assert acf["value"][0] == 1.0
    assert acf["peak_frequency"][0] == pytest.approx(1 / 3, abs=0.01)
    assert acf["significant"][0]
    pat = acf["strongest_pattern"]
    assert (pat["intervals"], pat["n_short"], pat["n_long"]) == (3, 1, 2)
    assert pat["duration_s"] == pytest.approx(0.45, abs=0.01)


def test_iid_train_has_no_significant_acf_peak(mixture_stats):
    # the mixture intervals are drawn independently: no periodicity in their order
    assert mixture_stats["acf"]["n_significant"] == 0


# ------------------------------------------------------------------- input handling


def test_train_validation():
    t = np.arange(20.0)
    with pytest.raises(ValueError, match="outside the observation span"):
        ImpactTrain(t, 1.0, 30.0)
    with pytest.raises(ValueError, match="t_start < t_stop"):
        ImpactTrain(t, 30.0, 0.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        ImpactTrain(t[::-1], 0.0, 30.0)
    with pytest.raises(ValueError, match="too few"):
        ImpactTrain(t[:5], 0.0, 30.0)
    with pytest.raises(ValueError, match="penetrations must be >= 0"):
        ImpactTrain(t, 0.0, 30.0, penetrations=-np.ones(20))
    with pytest.raises(ValueError, match="omega"):
        ImpactTrain(t, 0.0, 30.0, omega=-1.0)


def test_options_validation():
    with pytest.raises(ValueError, match="unknown analysis option"):
        AnalysisOptions.from_config({"n_window": 5})
    with pytest.raises(ValueError, match="alpha"):
        AnalysisOptions(alpha=1.5)
    with pytest.raises(ValueError, match="n_windows"):
        AnalysisOptions(n_windows=1)
    with pytest.raises(ValueError, match="mixture_families"):
        AnalysisOptions(mixture_families=("weibull",))
    opts = AnalysisOptions.from_config({"fano_windows": [1, 2], "mixture_components": [2]})
    assert opts.fano_windows == (1, 2) and opts.mixture_components == (2,)
    with pytest.raises(ValueError, match="unknown part"):
        ch.analyse_train(_train(np.full(20, 0.1)), parts=("spectrum",))


def test_fano_windows_too_long_for_span():
    train = _train(np.random.default_rng(1).exponential(0.1, 50))
    with pytest.raises(ValueError, match="no Fano window fits"):
        ch.analyse_train(train, AnalysisOptions(fano_windows=(100.0,)), parts=("variability",))


def test_config_analysis_section_matches_options():
    """Every key of the config's chaotic.analysis section is an AnalysisOptions field."""
    from pathlib import Path

    from impactosc_study.config import load_config

    root = Path(__file__).resolve().parents[1]
    cfg = load_config(root / "config/config.yaml", root / "workflow/schemas/config.schema.yaml")
    opts = AnalysisOptions.from_config(cfg["chaotic"]["analysis"])
    assert opts.histogram_bins == 10 and opts.n_windows == 5  # the paper's choices


# ------------------------------------------------------------- files, JSON, summaries


def test_load_train_span_sources(tmp_path):
    t = 100.0 + np.cumsum(np.full(30, 0.1))
    h = np.linspace(1e-5, 2e-4, 30)
    attrs = {"omega": 40.86, "transient": 100.0, "duration": 4.0}
    write_run(tmp_path / "sim.h5", {"impacts": {"t": t, "v": np.ones(30)}, "penetrations": {"t": t, "h": h}}, attrs)
    tr = load_train(tmp_path / "sim.h5")
    assert (tr.t_start, tr.t_stop, tr.label) == (100.0, 104.0, "sim")
    assert tr.omega == 40.86 and tr.penetrations.size == 30
    write_run(tmp_path / "meas.h5", {"impacts": {"t": t}}, {"t_start": 99.0, "t_stop": 105.0, **attrs})
    tr = load_train(tmp_path / "meas.h5", label="surrogate")
    assert (tr.t_start, tr.t_stop, tr.label) == (99.0, 105.0, "surrogate")
    assert tr.penetrations is None
    write_run(tmp_path / "bare.h5", {"impacts": {"t": t}}, {})
    tr = load_train(tmp_path / "bare.h5")
    assert (tr.t_start, tr.t_stop) == (t[0], t[-1]) and tr.omega is None
    assert tr.span_source == "first and last impact"
    write_run(tmp_path / "none.h5", {"poincare": {"t": t}}, {})
    with pytest.raises(ValueError, match="no impacts/t"):
        load_train(tmp_path / "none.h5")


def test_json_roundtrip(tmp_path, poisson_stats):
    path = write_json(tmp_path / "s.json", {**poisson_stats, "bad": np.array([np.nan, 1.0])})
    back = read_json(path)
    assert back["bad"] == [None, 1.0]
    assert back["train"]["n_impacts"] == poisson_stats["train"]["n_impacts"]
    assert back["stationarity"]["counts"] == poisson_stats["stationarity"]["counts"].tolist()
    json.dumps(back)  # plain JSON types only
    assert ch.key_numbers(back) == json.loads(json.dumps(ch.key_numbers(poisson_stats)))
    with pytest.raises(FileNotFoundError):
        read_json(tmp_path / "missing.json")


def test_ensemble_summary():
    members = {
        "a": {"n_impacts": 10, "window_counts": [5, 5], "mixture_best": "gamma x2", "rtol": 1e-8},
        "b": {"n_impacts": 14, "window_counts": [6, 8], "mixture_best": "gamma x2", "rtol": 1e-9},
        "c": {"n_impacts": 12, "window_counts": [7, 5], "mixture_best": "gamma x3", "rtol": 1e-9},
    }
    s = ensemble_summary(members)
    assert s["numeric"]["n_impacts"] == {"mean": 12.0, "sd": 2.0, "min": 10.0, "max": 14.0, "n": 3}
    assert "rtol" not in s["numeric"]
    assert s["window_counts"]["mean"] == 6.0 and s["window_counts"]["n"] == 6
    assert s["categorical"]["mixture_best"] == {"gamma x2": 2, "gamma x3": 1}
    rows = ensemble_table(members)
    assert rows[0]["window_counts"] == "5 5"
    with pytest.raises(ValueError, match="at least 2 members"):
        ensemble_summary({"a": members["a"]})


def test_trajectory_spectrum_dominant_line():
    dt = 2e-3
    t = np.arange(0.0, 200.0, dt)
    omega = 40.86
    rng = np.random.default_rng(2)
    slow = np.convolve(rng.normal(size=t.size), np.ones(200) / 200, mode="same")  # < ~15 rad/s
    x = 1e-3 * np.sin(omega * t) + 2e-4 * slow
    sp = trajectory_spectrum(t, x, omega)
    assert abs(sp["dominant_omega"] - omega) < sp["d_omega"]
    assert 0.0 < sp["low_power_fraction"] < 0.5
    with pytest.raises(ValueError, match="uniformly sampled"):
        trajectory_spectrum(np.r_[t[:10], t[11:20]], x[:19], omega)


def test_csv_writer(tmp_path):
    p = write_csv(tmp_path / "x.csv", [{"a": 1.0 / 3, "b": None}, {"a": 2, "b": "z"}])
    assert p.read_text() == "a,b\n0.333333,\n2,z\n"
    with pytest.raises(ValueError, match="no rows"):
        write_csv(tmp_path / "y.csv", [])


def test_ensemble_runs_names_and_tolerances():
    runs = ensemble_runs({"x0": 0.0}, {"rtol": 1e-10, "atol": 1e-12}, {"rtol": [1e-8], "x0": [1e-4, -1e-3]})
    assert runs == {
        "rtol1e-08": {"rtol": 1e-8, "atol": pytest.approx(1e-10), "x0": 0.0},
        "x0+1.0e-04": {"rtol": 1e-10, "atol": 1e-12, "x0": 1e-4},
        "x0-1.0e-03": {"rtol": 1e-10, "atol": 1e-12, "x0": -1e-3},
    }
    with pytest.raises(ValueError, match="repeat"):
        ensemble_runs({}, {"rtol": 1e-10, "atol": 1e-12}, {"x0": [1e-4, 1.00001e-4]})
