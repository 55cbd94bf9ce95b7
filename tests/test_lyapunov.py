"""Lyapunov exponents of the stroboscopic map (impactosc.dynamics.lyapunov) against closed forms
and independent references."""

import math

import numpy as np
import pytest

from impactosc.dynamics import shoot
from impactosc.dynamics.lyapunov import kaplan_yorke, largest_exponent, lyapunov_spectrum, settle
from impactosc.dynamics.lyapunov_reading import sign_agreement, summarise_agreement
from impactosc.dynamics.variational import variational_monodromy


@pytest.mark.parametrize("omega", [23.03, 40.86])
def test_linear_oscillator_exponents_are_minus_c_over_2m(linear_params, omega):
    """Without friction and contact the map is affine with a complex pair of multipliers of
    modulus exp(-c/(2m) T): both exponents are -c/(2m) per second. QR on a rotating pair
    converges as log(condition of the eigenvectors) / n, a bounded term over the run's length:
    ~1.5 / n per period in scaled units (measured 1e-3 to 1.5e-3 at n = 1000), hence 3e-3."""
    p = linear_params
    run = lyapunov_spectrum([1e-3, 0.0], omega, 1000, p)
    np.testing.assert_allclose(run.exponents, -p.c / (2 * p.m) * 2 * math.pi / omega, rtol=0, atol=3e-3)
    assert np.all(np.sign(run.per_second) == -1)
    # log det J of each period is -c T / m exactly; the differences carry the core's error over
    # the step (1e-14 m / 1e-8 m = 1e-6 per entry): measured 1.2e-7, hence 1e-6
    np.testing.assert_allclose(run.log_det, -p.c / p.m * 2 * math.pi / omega, rtol=0, atol=1e-6)


def test_periodic_orbit_exponents_are_the_logs_of_its_multipliers():
    """On model BC's period-1 orbit at w = 37 (two real multipliers) the exponents are log|mu|,
    with mu from the variational equations (SciPy, independent of the core): 300 periods from
    the orbit's point, to 2e-3 per period (the QR's convergence, 1/n)."""
    orbit = shoot([-0.0088, -0.13], 37.0)
    _, M = variational_monodromy([orbit.x0, orbit.v0], 37.0, 1)
    mu = np.sort(np.log(np.abs(np.linalg.eigvals(M))))[::-1]
    assert np.all(np.abs(np.linalg.eigvals(M).imag) == 0)  # real pair: the case stated above
    run = lyapunov_spectrum([orbit.x0, orbit.v0], 37.0, 300)
    np.testing.assert_allclose(run.exponents, mu, rtol=0, atol=2e-3)
    lam1 = largest_exponent([orbit.x0, orbit.v0], 37.0, 100, n_discard=20)
    assert abs(lam1 - mu[0]) < 2e-3


def test_sum_of_exponents_is_the_mean_divergence_on_the_chaotic_attractor():
    """Sum of the exponents (mean log|det J| of the core's one-period Jacobians) against the
    integral of the divergence -(c + friction slope + contact damping slope)/m over the same
    periods, from the variational equations (det Phi = exp of that integral; SciPy). Measured
    over 50 periods of the workflow: 5e-7 per period of a sum of -1.38, single periods 2e-5;
    here 8 periods, to 1e-5 per period (the difference Jacobian's error at step 1e-5)."""
    y = settle([1e-4, 0.0], 40.86, 50.0)
    run = lyapunov_spectrum(y, 40.86, 8)
    div = [math.log(abs(np.linalg.det(variational_monodromy(p, 40.86, 1)[1]))) for p in run.points]
    assert abs(run.log_det.mean() - np.mean(div)) < 1e-5
    assert abs(run.exponents.sum() - run.log_det.mean()) < 1e-12  # QR keeps the determinant exactly


def test_kaplan_yorke():
    assert kaplan_yorke([-0.1, -0.5]) == 0.0
    assert kaplan_yorke([0.4, -1.8]) == pytest.approx(1 + 0.4 / 1.8)
    assert kaplan_yorke([0.3, -0.1]) == 2.0


def test_sign_agreement_verdicts():
    per_w = [{"omega": w, "period": p} for w, p in [(1.0, 1), (1.1, 1), (1.2, 0), (1.3, 0), (1.4, 2)]]
    lam = {1.0: -0.5, 1.1: 0.01, 1.2: 0.3, 1.3: -0.2, 1.4: math.nan}
    rows = sign_agreement(per_w, lam, transitions=[1.15], grid_step=0.1)
    assert [r["verdict"] for r in rows] == ["agrees", "near a transition", "agrees", "disagrees", "no exponent"]
    summary = summarise_agreement(rows)
    assert summary["counts"]["agrees"] == 2 and summary["disagree_at"] == [1.3]


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="n_periods"):
        lyapunov_spectrum([0.0, 0.0], 30.0, 0)
    with pytest.raises(ValueError, match="finite"):
        lyapunov_spectrum([math.nan, 0.0], 30.0, 10)
