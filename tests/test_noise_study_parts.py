"""The noise study split into jobs (one per noise level, one for the realism rows, a merge) gives
the rows of the study run in one process: the same numbers, in the same order.

Why it can: every rate's clean record is a deterministic simulation (the levels sample the same
clean runs, simulated once and read back from their run files as the workflow's jobs do, or
simulate them again), and a level computed alone draws and discards the noise of the levels
before it from the same seeded generator. The
workflow's merge also copies the parts' table cells; that the merged files equal the one-process
files is checked on the tiny configuration (CHANGELOG), this test checks the rows themselves.
"""

import math

import numpy as np
import pytest

from impactosc.io.files import read_run, write_run
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_study.noise_study import clean_runs, merge_levels, noise_level_rows, noise_study, realism_rows

OPTIONS = AnalysisOptions(acf_surrogates=10, ks_bootstrap=0, mixture_restarts=1, fano_windows=(0.5, 1.0, 2.0))
SCENE = (40.86, 20.0, 12.0)  # w (rad/s), transient and duration (s)
RATES = [1000.0, 2000.0]
NOISES = [0.0, 1e-6, 2e-5]  # two noisy levels: the second one's draw follows the first one's
STUDY = {"analysis": OPTIONS, "seed": 3, "x_impact_span": 12.0, "x_impact_noise": [2e-5]}


def same(a, b) -> bool:
    """Equal values, NaN equal to NaN, arrays element by element."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return a == b


@pytest.fixture(scope="module")
def whole():
    realism = [{"quantum": 1e-6}]
    return noise_study(*SCENE, RATES, NOISES, realism=realism, realism_rate=2000.0, **STUDY)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Each rate's clean run written to a run file and read back, as a level's job gets it."""
    folder = tmp_path_factory.mktemp("clean")
    out = []
    for rate, res in zip(RATES, clean_runs(*SCENE, RATES), strict=True):
        path = write_run(folder / f"{rate:g}.h5", res.events, res.attrs, res.trajectory, compress=False)
        events, _, trajectory = read_run(path)
        out.append((events, trajectory))
    return out


def test_levels_and_realism_merge_into_the_whole_study(whole, runs):
    # every level but the last samples the shared runs; the last simulates its own
    last = len(NOISES) - 1
    levels = [
        noise_level_rows(*SCENE, RATES, NOISES, level, runs=runs if level < last else None, **STUDY)
        for level in range(len(NOISES))
    ]
    realism = realism_rows(*SCENE, 2000.0, 5e-6, [{"quantum": 1e-6}], seed=3, x_impact_span=12.0)
    merged = merge_levels(levels, len(RATES)) + realism
    assert [(r["rate_hz"], r["noise_m"], r["method"]) for r in merged] == [
        (r["rate_hz"], r["noise_m"], r["method"]) for r in whole
    ]
    for got, want in zip(merged, whole):
        assert got.keys() == want.keys(), (want["method"], got.keys() ^ want.keys())
        differ = [k for k in want if not same(got[k], want[k])]
        assert not differ, f"{want['rate_hz']} Hz, {want['noise_m']} m, {want['method']}: {differ} differ"


def test_a_level_needs_one_run_per_rate(runs):
    with pytest.raises(ValueError, match="1 clean runs for 2 rates"):
        noise_level_rows(*SCENE, RATES, NOISES, 0, runs=runs[:1], **STUDY)


def test_noisy_levels_differ_and_the_estimate_is_where_asked(whole):
    by = {(r["rate_hz"], r["noise_m"], r["method"]): r for r in whole}
    # the levels are real noise draws: the timing error grows with the noise
    assert by[(2000.0, 2e-5, "hysteresis")]["timing_rms_s"] > by[(2000.0, 1e-6, "hysteresis")]["timing_rms_s"]
    assert "x_impact_err_m" in by[(1000.0, 2e-5, "hysteresis")]
    assert "x_impact_err_m" not in by[(1000.0, 1e-6, "hysteresis")]


def test_merge_levels_orders_rate_by_rate_and_refuses_a_ragged_level():
    levels = [["a1", "b1", "a2", "b2"], ["c1", "c2"]]  # level 0 has two rows per rate, level 1 one
    assert merge_levels(levels, 2) == ["a1", "b1", "c1", "a2", "b2", "c2"]
    with pytest.raises(ValueError, match="noise level 1: 3 rows do not split into 2 rates"):
        merge_levels([["a1", "a2"], ["c1", "c2", "c3"]], 2)
