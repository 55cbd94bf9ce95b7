"""Holt's CV2, LV, LvR and the serial correlations against Elephant, SciPy and known values,
through the library and through ``impactosc stats`` on run files."""

import json
import warnings

import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.io.files import write_run
from impactosc.statistics import (
    holt_cv2,
    local_variation,
    revised_local_variation,
    serial_correlation,
)

#: Relative agreement with Elephant asked of every value: the formulas are the same sums, so only
#: rounding differs (Elephant's LvR works in ms: one multiplication by 1e3, a few 1e-16).
REL = 1e-12


def _synthetic(kind: str, rng) -> np.ndarray:
    """Event times of three trains with known character, about 7 events per second over 200 s."""
    if kind == "poisson":
        s = rng.exponential(1 / 7, 1400)
    elif kind == "gamma":
        s = rng.gamma(4.0, 1 / 28, 1400)  # shape 4: CV^2 = 1/4, more regular than Poisson
    else:  # periodic with 2 ms jitter of each event
        t = 0.5 + np.arange(1400) / 7 + rng.normal(0, 2e-3, 1400)
        return np.sort(t)
    return 0.5 + np.cumsum(s)


TRAINS = ("poisson", "gamma", "periodic")


def _elephant_values(S) -> dict:
    es = pytest.importorskip("elephant.statistics")
    pq = pytest.importorskip("quantities")
    with warnings.catch_warnings():  # Elephant warns that plain arrays are taken as ms
        warnings.simplefilter("ignore")
        return {
            "cv2": es.cv2(S),
            "lv": es.lv(S),
            "lvr": es.lvr(S * pq.s, R=5 * pq.ms),
            "lvr_20ms": es.lvr(S * pq.s, R=20 * pq.ms),
        }


def _pearson_lags(S, lags=10) -> np.ndarray:
    """scipy.stats.pearsonr of the shifted copies: the independent reference of the serial correlation
    (Elephant 1.2 has no serial correlation of the intervals)."""
    from scipy import stats

    return np.array([stats.pearsonr(S[:-k], S[k:]).statistic for k in range(1, lags + 1)])


@pytest.mark.parametrize("kind", TRAINS)
def test_library_agrees_with_elephant(kind):
    S = np.diff(_synthetic(kind, np.random.default_rng(3)))
    ref = _elephant_values(S)
    assert holt_cv2(S) == pytest.approx(ref["cv2"], rel=REL)
    assert local_variation(S) == pytest.approx(ref["lv"], rel=REL)
    assert revised_local_variation(S) == pytest.approx(ref["lvr"], rel=REL)
    assert revised_local_variation(S, 0.02) == pytest.approx(ref["lvr_20ms"], rel=REL)
    # Pearson's r: the same sums in another order, agreement to rounding
    np.testing.assert_allclose(serial_correlation(S), _pearson_lags(S), rtol=REL, atol=1e-14)


def test_known_values():
    # a periodic train: every neighbour ratio 0, LvR = 3 (1 + 4R/(2T)) (1 - 1) = 0
    S = np.full(50, 0.1)
    assert holt_cv2(S) == 0.0 and local_variation(S) == 0.0 and revised_local_variation(S) == 0.0
    # alternating a, b: |b - a|/(a + b) at every pair, so CV2 = 2 r and LV = 3 r^2, r = 1/3 here;
    # serial correlation -1 at odd lags and +1 at even ones
    S = np.tile([0.1, 0.2], 30)
    assert holt_cv2(S) == pytest.approx(2 / 3, rel=1e-14)
    assert local_variation(S) == pytest.approx(1 / 3, rel=1e-14)
    r = serial_correlation(S, 4)
    np.testing.assert_allclose(r, [-1, 1, -1, 1], atol=1e-12)
    # LvR at R = 0 is LV written with 1 - 4 ab/(a+b)^2 = ((a-b)/(a+b))^2 (Shinomoto 2009, eq. 3)
    S = np.random.default_rng(0).gamma(2.0, 0.05, 500)
    assert revised_local_variation(S, 0.0) == pytest.approx(local_variation(S), rel=1e-12)


def test_poisson_local_measures_near_one():
    # exponential intervals: E[CV2] = E[LV] = 1 (Holt 1996, Shinomoto 2003); the neighbour terms are
    # 1-dependent with sd < 1, so 6/sqrt(n) is a wide (> 5 sd) band
    S = np.random.default_rng(11).exponential(0.2, 20000)
    band = 6 / np.sqrt(S.size)
    assert abs(holt_cv2(S) - 1) < band
    assert abs(local_variation(S) - 1) < 2 * band  # LV's terms have twice the spread
    assert np.all(np.abs(serial_correlation(S)) < 4 / np.sqrt(S.size))


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: holt_cv2([0.1]), "too few samples"),
        (lambda: local_variation([0.1, -0.2, 0.3]), "strictly positive"),
        (lambda: revised_local_variation([0.1, 0.2, 0.3], -1e-3), "refractoriness"),
        (lambda: serial_correlation(np.ones(20) * 0.1, 2), "constant"),
        (lambda: serial_correlation([0.1, 0.2, 0.3, 0.4], 10), "too few samples"),
        (lambda: serial_correlation([0.1, 0.2, 0.3, 0.4, 0.5], 0), "max_lag"),
    ],
)
def test_bad_input_names_the_problem(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def _run_file(path, times, t_start, t_stop, **extra):
    write_run(path, {"impacts": {"t": np.asarray(times)}, **extra}, {"t_start": t_start, "t_stop": t_stop})
    return path


def _stats_json(tmp_path, run, *args):
    out = tmp_path / (run.stem + ".json")
    assert main(["stats", str(run), "--json", str(out), *args]) == 0
    return json.loads(out.read_text())


@pytest.mark.parametrize("kind", TRAINS)
def test_command_agrees_with_elephant_on_synthetic_trains(kind, tmp_path):
    t = _synthetic(kind, np.random.default_rng(5))
    run = _run_file(tmp_path / f"{kind}.h5", t, 0.0, float(np.ceil(t[-1])))
    got = _stats_json(tmp_path, run)
    S = np.diff(t)
    ref = _elephant_values(S)
    for key in ("cv2", "lv", "lvr"):
        assert got[key] == pytest.approx(ref[key], rel=REL), key
    np.testing.assert_allclose(got["serial_correlation"], _pearson_lags(S), rtol=REL, atol=1e-14)
    assert got["serial_correlation_lags"] == list(range(1, 11))


def test_command_agrees_with_elephant_on_the_chaotic_train(tmp_path):
    from impactosc.core.simulation import simulate

    # 60 s of the paper's chaotic scene (about 430 impacts): the train the paper's statistics describe
    res = simulate(40.86, 100.0, 60.0, record=("impacts", "penetrations"))
    run = tmp_path / "chaos.h5"
    write_run(run, res.events, res.attrs)
    got = _stats_json(tmp_path, run, "--refractoriness", "0.002")
    S = np.diff(res.events["impacts"]["t"])
    ref = _elephant_values(S)
    assert got["cv2"] == pytest.approx(ref["cv2"], rel=REL)
    assert got["lv"] == pytest.approx(ref["lv"], rel=REL)
    pq = pytest.importorskip("quantities")
    from elephant.statistics import lvr

    assert got["lvr"] == pytest.approx(lvr(S * pq.s, R=2 * pq.ms), rel=REL)
    assert got["lvr_refractoriness"] == 0.002
    np.testing.assert_allclose(got["serial_correlation"], _pearson_lags(S), rtol=REL, atol=1e-14)
    # the paper's numbers come out of the same analysis: counts, C_V^2 in s, penetration modes
    assert got["n_impacts"] == S.size + 1 and len(got["window_counts"]) == 5
    assert got["cv2_paper"] == pytest.approx(np.var(S, ddof=1) / S.mean(), rel=1e-10)  # rounding of two sums
    assert got["penetration_modes"]
