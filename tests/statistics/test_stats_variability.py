"""Running C_V^2 (paper's and dimensionless) and Fano factor on trains with known answers."""

import numpy as np
import pytest

from impactosc.statistics import (
    cv2_paper_running,
    cv2_running,
    fano_curve,
    fano_factor,
    inter_impact_intervals,
)


def test_running_values_match_direct_computation():
    s = np.random.default_rng(0).gamma(3.0, 0.05, 300)
    paper = cv2_paper_running(s)
    dimless = cv2_running(s)
    assert paper.sample_size[0] == 2 and paper.sample_size[-1] == s.size  # ddof=1 starts at 2
    for i in (2, 3, 17, 150, 300):
        ref_var = np.var(s[:i], ddof=1)
        ref_mean = np.mean(s[:i])
        # cumulative sums vs direct: agreement to rounding (relative 1e-10 is generous)
        assert paper.value[i - 2] == pytest.approx(ref_var / ref_mean, rel=1e-10)
        assert dimless.value[i - 2] == pytest.approx(ref_var / ref_mean**2, rel=1e-10)
    pop = cv2_running(s, ddof=0)
    assert pop.sample_size[0] == 1 and pop.value[0] == 0.0
    assert pop.final == pytest.approx(np.var(s) / np.mean(s) ** 2, rel=1e-10)


def test_poisson_train_cv2_is_one(poisson_train, poisson_params):
    rate, _ = poisson_params
    s = inter_impact_intervals(poisson_train)
    n = s.size
    # exponential ISIs: CV^2 = 1, delta-method standard error of the estimate 2/sqrt(n)
    se = 2.0 / np.sqrt(n)
    assert abs(cv2_running(s).final - 1.0) < 3 * se
    # the paper's dimensionful var/mean equals the mean ISI 1/rate (s); relative SE sqrt(5/n)
    expected = 1.0 / rate
    assert abs(cv2_paper_running(s).final - expected) < 3 * np.sqrt(5.0 / n) * expected


def test_poisson_train_fano_is_one(poisson_train, poisson_params):
    _, span = poisson_params
    window = 1.0  # s: 1000 windows with mean count 7
    m = int(span / window)
    # Poisson counts: (m-1) s^2 / mean ~ chi2(m-1), so SE of the Fano factor ~ sqrt(2/(m-1))
    se = np.sqrt(2.0 / (m - 1))
    assert abs(fano_factor(poisson_train, window, 0.0, span) - 1.0) < 3 * se
    curve = fano_curve(poisson_train, [0.2, 1.0, 5.0, 20.0], 0.0, span)
    np.testing.assert_array_equal(curve.n_windows, [5000, 1000, 200, 50])
    se_curve = np.sqrt(2.0 / (curve.n_windows - 1))
    assert np.all(np.abs(curve.fano - 1.0) < 3.5 * se_curve)  # 4 estimates: 3.5 SE each


def test_periodic_train_has_zero_variability(periodic_train):
    s = inter_impact_intervals(periodic_train)
    # intervals agree to rounding (~1e-16 s), so var/mean^2 is ~1e-30
    assert cv2_running(s).final < 1e-24
    assert cv2_paper_running(s).final < 1e-24
    # window = 10 periods: every window holds exactly 10 impacts
    assert fano_factor(periodic_train, 1.0, 0.0, 100.0) == 0.0
    # window of 2.5 periods: counts alternate 2, 3 -> var <= 0.25 * m/(m-1), mean 2.5
    f = fano_factor(periodic_train, 0.25, 0.0, 100.0)
    assert 0.0 < f <= 0.26 / 2.5
