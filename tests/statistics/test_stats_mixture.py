"""Mixture fits: parameter recovery and BIC model selection."""

import numpy as np
import pytest

from impactosc.statistics import fit_mixture, select_mixture


def test_two_gamma_mixture_is_recovered(gamma_mixture_sample):
    fit = fit_mixture(gamma_mixture_sample, "gamma", 2)
    assert fit.converged
    # n=3000: weight SE ~0.009 and component-mean SE ~0.001 s (20-seed study); 4-5 SE
    np.testing.assert_allclose(fit.weights, [0.4, 0.6], atol=0.04)
    np.testing.assert_allclose(fit.means, [0.06, 0.21], atol=0.005)
    np.testing.assert_allclose(fit.modes, [0.05, 0.20], atol=0.01)
    assert fit.weights.sum() == pytest.approx(1.0, abs=1e-12)
    assert fit.n_params == 5
    assert fit.bic == pytest.approx(5 * np.log(3000) - 2 * fit.loglik)
    # pdf is normalised (integral over the support, trapezoid on a fine grid)
    g = np.linspace(1e-6, 1.0, 20001)
    assert np.trapezoid(fit.pdf(g), g) == pytest.approx(1.0, abs=1e-3)


def test_bic_prefers_two_components_for_bimodal_sample(gamma_mixture_sample):
    sel = select_mixture(gamma_mixture_sample)
    assert len(sel.fits) == 6
    assert sel.best.n_components == 2
    for family in ("gaussian", "lognormal", "gamma"):
        b = {f.n_components: f.bic for f in sel.fits if f.family == family}
        # a second mode of 40 % weight gains hundreds of log-likelihood units
        assert b[2] < b[1] - 100
    assert np.all(np.diff([f.bic for f in sel.fits]) >= 0)
    assert "dBIC" in sel.table()


def test_bic_prefers_one_component_for_unimodal_gamma():
    x = np.random.default_rng(2).gamma(5.0, 0.03, 3000)
    sel = select_mixture(x)
    # the 3 extra parameters cost 3 ln(3000) = 24 BIC units; a redundant component cannot
    # gain that much likelihood on data from a single gamma
    assert sel.best.family == "gamma"
    assert sel.best.n_components == 1
    assert sel.best.params["shape"][0] == pytest.approx(5.0, rel=0.1)  # SE of shape ~2.5 %


@pytest.mark.parametrize("family", ["gaussian", "lognormal"])
def test_gaussian_and_lognormal_mixtures_are_recovered(family):
    rng = np.random.default_rng(8)
    n = 3000
    first = rng.random(n) < 0.3
    if family == "gaussian":
        x = np.where(first, rng.normal(0.05, 0.01, n), rng.normal(0.2, 0.03, n))
        mu, sigma = [0.05, 0.2], [0.01, 0.03]
    else:
        x = np.where(first, rng.lognormal(np.log(0.05), 0.2, n), rng.lognormal(np.log(0.2), 0.15, n))
        mu, sigma = np.log([0.05, 0.2]), [0.2, 0.15]
    fit = fit_mixture(x, family, 2)
    # well separated: weight SE ~ sqrt(0.21/3000) = 0.008, allow ~4 SE
    np.testing.assert_allclose(fit.weights, [0.3, 0.7], atol=0.03)
    # component mean SE = sigma/sqrt(n_k) < 0.03 sigma; sigma relative SE ~ 1/sqrt(2 n_k) < 3 %
    assert np.all(np.abs(fit.params["mu"] - mu) < 0.1 * np.array(sigma))
    np.testing.assert_allclose(fit.params["sigma"], sigma, rtol=0.1)
