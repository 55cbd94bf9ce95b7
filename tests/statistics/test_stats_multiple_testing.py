"""Holm's step-down and the two-sided p-values of z-scores, against their definitions."""

import math

import numpy as np
import pytest

from impactosc.statistics import THREE_SD_LEVEL, holm, largest_z_bound, two_sided_p


def _holm_by_definition(p, alpha):
    """Holm 1979 as written: walk the sorted p-values, reject while p_(i) < alpha / (N - i + 1)."""
    order = np.argsort(p, kind="stable")
    rejected = np.zeros(p.size, bool)
    for i, j in enumerate(order):
        if p[j] >= alpha / (p.size - i):
            break
        rejected[j] = True
    return rejected


def test_holm_matches_its_definition_on_random_families():
    rng = np.random.default_rng(0)
    for _ in range(300):
        n = int(rng.integers(1, 40))
        # a mixture of nulls (uniform) and strong effects, so both outcomes occur
        p = np.where(rng.random(n) < 0.3, rng.random(n) * 1e-4, rng.random(n))
        alpha = float(rng.choice([0.05, THREE_SD_LEVEL]))
        v = holm(p, alpha)
        np.testing.assert_array_equal(v.rejected, _holm_by_definition(p, alpha))
        assert np.all(v.adjusted >= p) and np.all(v.adjusted <= 1)


def test_holm_known_example():
    # p = 0.01, 0.04, 0.03 at alpha 0.05: 0.01 < 0.05/3 rejected; 0.03 >= 0.05/2 stops the walk.
    # adjusted: 3 x 0.01 = 0.03, max(0.03, 2 x 0.03) = 0.06, max(0.06, 1 x 0.04) = 0.06
    v = holm([0.01, 0.04, 0.03], 0.05)
    np.testing.assert_array_equal(v.rejected, [True, False, False])
    np.testing.assert_allclose(v.adjusted, [0.03, 0.06, 0.06], rtol=1e-14)
    assert v.n_tests == 3 and v.any_rejected


def test_two_sided_p_and_the_three_sd_level():
    # P(|Z| >= 3) = erfc(3 / sqrt 2) = 0.0026998 (normal tables); one test at that level is the 3-sd rule
    assert abs(THREE_SD_LEVEL - 0.0026998) < 1e-7
    np.testing.assert_allclose(two_sided_p([0.0, 1.959963984540054, -3.0]), [1.0, 0.05, THREE_SD_LEVEL], rtol=1e-12)
    assert holm(two_sided_p([3.01]), THREE_SD_LEVEL).any_rejected
    assert not holm(two_sided_p([2.99]), THREE_SD_LEVEL).any_rejected
    # a z of 3.02 among 60 z-scores is not rejected; Bonferroni's bound is |z| > 4.0 there
    z = np.zeros(60)
    z[17] = 3.02
    assert not holm(two_sided_p(z)).any_rejected
    z[17] = 4.2  # p = 2.7e-5 < 0.0027 / 60 = 4.5e-5
    assert holm(two_sided_p(z)).rejected[17]
    assert math.erfc(4.2 / math.sqrt(2)) < THREE_SD_LEVEL / 60


def test_largest_z_bound_is_holms_first_step():
    assert largest_z_bound(1) == pytest.approx(3.0, rel=1e-12)  # one test: the 3-sd rule itself
    for n in (2, 10, 120):
        bound = largest_z_bound(n)
        z = np.zeros(n)
        z[0] = bound * (1 + 1e-9)
        assert holm(two_sided_p(z)).any_rejected
        z[0] = bound * (1 - 1e-9)
        assert not holm(two_sided_p(z)).any_rejected
    # 0.0027 / 10 two-sided: 3.64 (normal tables: P(|Z| > 3.64) = 2.7e-4)
    assert largest_z_bound(10) == pytest.approx(3.64, abs=0.01)


@pytest.mark.parametrize("size", [5, 8])
def test_bound_against_a_small_reference_holds_its_level(size):
    """A new normal value against the mean and sample sd of `size` others: the bound with
    reference_size rejects at its level (Monte Carlo, 40000 draws); the normal quantile does not."""
    rng = np.random.default_rng(size)
    draws = rng.standard_normal((40_000, size + 1))
    ref = draws[:, :size]
    z = np.abs(draws[:, size] - ref.mean(axis=1)) / ref.std(axis=1, ddof=1)
    alpha = 0.05
    rate = np.mean(z > largest_z_bound(1, alpha, reference_size=size))
    se = math.sqrt(alpha * (1 - alpha) / z.size)  # binomial standard error of the rate: 0.0011
    assert abs(rate - alpha) < 4 * se, rate
    assert np.mean(z > largest_z_bound(1, alpha)) > alpha + 10 * se  # 0.10 at 5, 0.08 at 8


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: holm([0.1, 1.2]), r"\[0, 1\]"),
        (lambda: holm([0.1], 1.5), "alpha"),
        (lambda: holm([]), "empty"),
        (lambda: two_sided_p([np.nan]), "non-finite"),
        (lambda: largest_z_bound(0), "n_tests"),
        (lambda: largest_z_bound(3, reference_size=1), "reference_size"),
    ],
)
def test_bad_input_names_the_problem(call, match):
    with pytest.raises(ValueError, match=match):
        call()
