"""The noise study split into jobs (one per sampling rate, one for the realism rows, concatenated)
gives the rows of the study run in one process: the same numbers, in the same order.

Why it can: every rate's clean record is a deterministic simulation, and each rate draws its
noise from a generator of its own, seeded alike: a rate computed alone draws what it draws in the
whole study. The workflow's merge also copies the parts' table cells; this test checks the rows.
"""

import math

import numpy as np
import pytest

from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_study.noise_study import noise_study, realism_rows

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


def test_rates_and_realism_concatenate_into_the_whole_study(whole):
    parts = [noise_study(*SCENE, [rate], NOISES, **STUDY) for rate in RATES]
    realism = realism_rows(*SCENE, 2000.0, 5e-6, [{"quantum": 1e-6}], seed=3, x_impact_span=12.0)
    merged = [row for part in parts for row in part] + realism
    assert [(r["rate_hz"], r["noise_m"], r["method"]) for r in merged] == [
        (r["rate_hz"], r["noise_m"], r["method"]) for r in whole
    ]
    for got, want in zip(merged, whole):
        assert got.keys() == want.keys(), (want["method"], got.keys() ^ want.keys())
        differ = [k for k in want if not same(got[k], want[k])]
        assert not differ, f"{want['rate_hz']} Hz, {want['noise_m']} m, {want['method']}: {differ} differ"


def test_noisy_levels_differ_and_the_estimate_is_where_asked(whole):
    by = {(r["rate_hz"], r["noise_m"], r["method"]): r for r in whole}
    # the levels are real noise draws: the timing error grows with the noise
    assert by[(2000.0, 2e-5, "hysteresis")]["timing_rms_s"] > by[(2000.0, 1e-6, "hysteresis")]["timing_rms_s"]
    assert "x_impact_err_m" in by[(1000.0, 2e-5, "hysteresis")]
    assert "x_impact_err_m" not in by[(1000.0, 1e-6, "hysteresis")]
