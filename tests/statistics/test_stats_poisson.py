"""KS test of intervals against the exponential law with estimated mean."""

import numpy as np

from impactosc.statistics import exponential_ks_test, inter_impact_intervals


def test_poisson_train_is_not_rejected(poisson_train, poisson_params):
    rate, _ = poisson_params
    res = exponential_ks_test(inter_impact_intervals(poisson_train))
    assert not res.rejected
    assert res.pvalue_bootstrap is not None and res.pvalue == res.pvalue_bootstrap
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
