"""KS test of intervals against the exponential law with estimated mean."""

import numpy as np
import pytest
from scipy import stats

from impactosc.statistics import exponential_ks_test, inter_impact_intervals, poisson


def test_poisson_train_is_not_rejected(poisson_train, poisson_params):
    rate, _ = poisson_params
    res = exponential_ks_test(inter_impact_intervals(poisson_train))
    assert not res.rejected
    assert res.pvalue_bootstrap is not None and res.pvalue == res.pvalue_bootstrap
    # unchanged by the move to goodness_of_fit (n = 7076: four batches): old D and p = 0.49,
    # MC tolerance as in test_goodness_of_fit_matches_old_bootstrap
    assert res.statistic == pytest.approx(0.008486749770190372, rel=1e-14, abs=0)
    assert abs(res.pvalue_bootstrap - 0.49) <= 4 * np.sqrt(2 * 0.49 * 0.51 / 999) + 1 / 1000
    # estimated mean ISI is 1/rate; exponential: relative SE 1/sqrt(n) ~ 1.2 %, allow 4 %
    assert abs(res.mean * rate - 1.0) < 0.04
    # with the mean estimated, the classical KS p-value is conservative (larger)
    assert res.pvalue_ks >= res.pvalue - 0.05
    assert "consistent with exponential" in res.conclusion


def test_bimodal_intervals_are_rejected(gamma_mixture_sample):
    res = exponential_ks_test(gamma_mixture_sample, n_bootstrap=199)
    assert res.rejected
    assert res.pvalue == 1 / 200  # no bootstrap replicate is as extreme
    assert "rejected" in res.conclusion


def test_bootstrap_pvalue_is_calibrated_where_classical_ks_is_not():
    # 300 exponential samples of n=50: the bootstrap test rejects ~5 % (binomial SE 1.3 %),
    # the classical KS test with an estimated mean rejects far less (~0.2 %).
    rng = np.random.default_rng(123)
    boot, classical = [], []
    for i in range(300):
        res = exponential_ks_test(rng.exponential(0.14, 50), n_bootstrap=199, seed=i)
        boot.append(res.pvalue_bootstrap < 0.05)
        classical.append(res.pvalue_ks < 0.05)
    assert 0.05 - 3 * 0.013 < np.mean(boot) < 0.05 + 3 * 0.013
    assert np.mean(classical) < 0.02


def test_bootstrap_is_reproducible():
    s = np.random.default_rng(0).exponential(1.0, 200)
    a = exponential_ks_test(s, seed=42)
    b = exponential_ks_test(s, seed=42)
    assert a == b


# Values of the hand-written bootstrap this replaced (commit 29f74da), per input:
# (sample, n_bootstrap, seed, D, bootstrap p).  goodness_of_fit reproduces them exactly
# today (expon.rvs draws the same standard-exponential stream), but only D is guaranteed.
def _old_cases():
    rng = np.random.default_rng(11)
    first = rng.random(3000) < 0.4
    mix = np.where(first, rng.gamma(6.0, 0.01, 3000), rng.gamma(21.0, 0.01, 3000))
    return [
        (mix, 199, 0, 0.1800223282191773, 0.005),
        (np.random.default_rng(0).exponential(1.0, 200), 999, 42, 0.057846958455542274, 0.287),
        (np.random.default_rng(3).gamma(2.0, 0.07, 50), 999, 3, 0.20460348583800833, 0.002),
        (np.random.default_rng(4).weibull(1.3, 30), 999, 1, 0.1646015889275343, 0.147),
        (np.random.default_rng(5).exponential(2.0, 5), 999, 0, 0.23771201197547215, 0.759),
    ]


@pytest.mark.parametrize("case", range(5))
def test_goodness_of_fit_matches_old_bootstrap(case):
    s, nb, seed, d_old, p_old = _old_cases()[case]
    res = exponential_ks_test(s, n_bootstrap=nb, seed=seed)
    # D is the same scipy.stats.kstest value as before: bit-identical here, 1e-14 leaves
    # room for another libm only
    assert res.statistic == pytest.approx(d_old, rel=1e-14, abs=0)
    # two independent MC p-values of N replicates differ by sqrt(2 p (1-p) / N) (binomial
    # SE); allow 4 of those plus one count 1/(N+1)
    tol = 4 * np.sqrt(2 * p_old * (1 - p_old) / nb) + 1 / (nb + 1)
    assert abs(res.pvalue_bootstrap - p_old) <= tol
    assert res.pvalue == res.pvalue_bootstrap
    # the statistic the null distribution is compared with is goodness_of_fit's own
    gof = stats.goodness_of_fit(
        stats.expon, s, known_params={"loc": 0.0}, statistic="ks", n_mc_samples=nb, rng=np.random.default_rng(seed)
    )
    assert gof.statistic == res.statistic
    assert gof.pvalue == pytest.approx(res.pvalue_bootstrap, abs=1e-15)


def test_bootstrap_does_not_depend_on_batch_size(monkeypatch):
    s = np.random.default_rng(2).gamma(1.2, 0.1, 200)
    whole = exponential_ks_test(s, n_bootstrap=999, seed=5)  # one batch
    monkeypatch.setattr(poisson, "_CHUNK_ELEMENTS", 37 * s.size)  # 27 batches of <= 37
    batched = exponential_ks_test(s, n_bootstrap=999, seed=5)
    assert batched == whole
