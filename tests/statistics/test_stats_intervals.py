"""Intervals, return maps, distinct levels, window counts and the equal-rate test."""

import numpy as np
import pytest

from impactosc.statistics import (
    counts_in_windows,
    distinct_levels,
    equal_rate_test,
    inter_impact_intervals,
    return_map,
    window_counts,
)


def test_intervals_are_differences():
    t = np.array([1.0, 1.5, 2.25, 4.0])
    np.testing.assert_array_equal(inter_impact_intervals(t), [0.5, 0.75, 1.75])


def test_return_map_pairs_successive_values():
    x, y = return_map([1.0, 2.0, 3.0, 4.0])
    np.testing.assert_array_equal(x, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(y, [2.0, 3.0, 4.0])
    x2, y2 = return_map([1.0, 2.0, 3.0, 4.0], lag=2)
    np.testing.assert_array_equal(x2, [1.0, 2.0])
    np.testing.assert_array_equal(y2, [3.0, 4.0])


def test_period4_train_has_four_equal_levels_summing_to_period(period4_times, period4_levels):
    s = inter_impact_intervals(period4_times)
    levels = distinct_levels(s, rel_tol=1e-3)
    assert levels.n_levels == 4
    np.testing.assert_array_equal(levels.counts, [122, 122, 122, 122])
    assert levels.counts_equal
    # each level is a mean of 122 values with 1e-7 s jitter: error ~1e-8 s, allow 1e-6
    np.testing.assert_allclose(levels.levels, np.sort(period4_levels), atol=1e-6)
    assert levels.total == pytest.approx(0.8184, abs=4e-6)
    # the return map of a period-4 orbit has exactly 4 distinct points
    x, y = return_map(s)
    assert distinct_levels(x + 10 * y, rel_tol=1e-4).n_levels == 4


def test_distinct_levels_of_a_dense_sequence_are_many():
    # a continuous distribution has no repeated levels: nearly every value is its own level
    s = np.random.default_rng(3).uniform(0.05, 0.3, 500)
    assert distinct_levels(s, rel_tol=1e-6).n_levels > 400


def test_window_counts_partition_the_span(poisson_train):
    c = window_counts(poisson_train, 0.0, 1000.0, 5)
    assert c.shape == (5,)
    assert c.sum() == poisson_train.size  # every event is in exactly one window
    # edges are linspace(t_start, t_stop, n+1); half-open except the last window
    np.testing.assert_array_equal(counts_in_windows([0.0, 1.0, 2.0], [0.0, 1.0, 2.0]), [1, 2])


def test_equal_rate_test_accepts_paper_counts():
    # paper Sec. 2.2: {572, 571, 579, 579, 574}; chi2 = 58/575 = 0.1009 on 4 dof
    res = equal_rate_test([572, 571, 579, 579, 574])
    assert res.statistic == pytest.approx(58 / 575, rel=1e-12)
    assert res.dof == 4
    assert res.pvalue > 0.99
    assert not res.rejected
    assert "consistent with equal rates" in res.conclusion


def test_equal_rate_test_rejects_uneven_counts():
    # chi2 = 11700/575 = 20.35 on 4 dof, p = 4.3e-4
    res = equal_rate_test([500, 650, 560, 590, 575])
    assert res.statistic == pytest.approx(11700 / 575, rel=1e-12)
    assert res.pvalue == pytest.approx(4.26e-4, rel=0.01)
    assert res.rejected
    assert "rejected" in res.conclusion


def test_equal_rate_test_on_poisson_windows(poisson_train):
    # under H0 p is uniform; this fixed-seed train is a typical draw, not a tail event
    res = equal_rate_test(window_counts(poisson_train, 0.0, 1000.0, 10))
    assert res.pvalue > 0.01


@pytest.mark.parametrize(
    "counts, statistic, pvalue",
    [
        # (counts, statistic, p) of the hand-written sum + chi2.sf this replaced (commit 29f74da)
        ([572, 571, 579, 579, 574], 0.10086956521739131, 0.9987701314377717),
        ([500, 650, 560, 590, 575], 20.347826086956523, 0.0004263153725191379),
        ([0, 3, 1, 0, 2], 5.666666666666668, 0.22546314129598113),
        ([10, 30], 10.0, 0.001565402258002549),
        ([100000, 100400, 99700, 100050], 2.4678245657878297, 0.48113397810428715),
    ],
)
def test_equal_rate_test_matches_old_hand_written_sum(counts, statistic, pvalue):
    res = equal_rate_test(counts)
    assert res.dof == len(counts) - 1  # chisquare's default ddof=0: k - 1 dof
    # chisquare sums (n_i - nbar)^2 / nbar term by term, the old code divided the sum once:
    # 1 ulp apart (measured <= 2.2e-16); the upper tail multiplies a relative change of the
    # statistic by about chi2/2 (~10 here), measured <= 1.1e-15 on p
    assert res.statistic == pytest.approx(statistic, rel=1e-14, abs=0)
    assert res.pvalue == pytest.approx(pvalue, rel=1e-13, abs=0)
