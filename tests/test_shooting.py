"""Periodic orbits by shooting (impactosc.dynamics): against the closed form of the
forced linear oscillator, and against the time simulation of model BC."""

import math

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.dynamics import ShootingError, monodromy, shoot


def linear_orbit(p, omega):
    """Fixed point (x, v) at phase 0 and the two Floquet multipliers of m x'' + c x' + k x =
    m0e w^2 sin(w t): the particular solution at t = 0 and exp(lambda 2 pi / w) of the roots
    lambda = -c/2m +- i w_d of the homogeneous equation."""
    F = p.m0e * omega**2
    den = (p.k - p.m * omega**2) ** 2 + (p.c * omega) ** 2
    a_s, a_c = F * (p.k - p.m * omega**2) / den, -F * p.c * omega / den
    lam = -p.c / (2 * p.m) + 1j * math.sqrt(p.k / p.m - (p.c / (2 * p.m)) ** 2)
    mu = np.exp(np.array([lam, lam.conjugate()]) * 2 * math.pi / omega)
    return np.array([a_c, a_s * omega]), mu


@pytest.mark.parametrize("omega", [8.0, 23.03, 40.86])
def test_linear_oscillator_orbit_and_multipliers_match_closed_form(linear_params, omega):
    y_exact, mu_exact = linear_orbit(linear_params, omega)
    orbit = shoot([0.0, 0.0], omega, params=linear_params)
    # the map is affine, so one Newton step lands on the fixed point; the rest is the core's
    # tolerance (rtol 1e-12 on mm-sized states: ~1e-14 m) and the differences' rounding
    assert orbit.newton_steps <= 3
    assert abs(orbit.x0 - y_exact[0]) < 1e-12 and abs(orbit.v0 - y_exact[1]) < 1e-10
    # a complex pair: compared as a set, to 1e-7 (differences of step 1e-4 of the state's
    # scale; the map is affine, so only the solver's error enters)
    got = sorted(orbit.multipliers, key=lambda z: z.imag)
    want = sorted(mu_exact, key=lambda z: z.imag)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-7)
    assert orbit.stable


@pytest.mark.parametrize("omega", [25.0, 30.0])
def test_model_bc_orbit_is_the_attractor_the_simulation_lands_on(omega):
    """Period-1 orbits with one impact per period: the time simulation from rest settles on
    them (300 s), and shooting from a guess 0.1 % off lands on the same Poincare point."""
    run = simulate(omega, 300.0, 3 * 2 * math.pi / omega, record=("poincare",), rtol=1e-12, atol=1e-14)
    settled = np.array([run.events["poincare"]["x"][-1], run.events["poincare"]["v"][-1]])
    orbit = shoot(settled * 1.001, omega)
    # the simulated point after 300 s is within ~1e-13 of the orbit (|mu| <= 0.65: the
    # transient has decayed by far more than 1e-13); shooting converges to the solver's tolerance
    assert abs(orbit.x0 - settled[0]) < 1e-11 and abs(orbit.v0 - settled[1]) < 1e-9
    assert orbit.residual < 1e-10
    assert orbit.stable


@pytest.mark.parametrize(("omega", "guess"), [(25.0, [-0.00745, -0.0078]), (30.0, [-0.0135, -0.115])])
def test_monodromy_converges_in_the_difference_step(omega, guess):
    """The finite-difference Jacobian of model BC's map is the same for steps 10x larger and
    10x smaller than the default to 1e-7 of its size (measured: 2e-8 and 2e-9): neither the
    curvature (larger steps) nor the solver's error (smaller ones) shows at the default."""
    orbit = shoot(guess, omega)
    y = [orbit.x0, orbit.v0]
    _, default = monodromy(y, omega)
    for step in (1e-3, 1e-5):
        _, other = monodromy(y, omega, step=step)
        np.testing.assert_allclose(other, default, rtol=0, atol=1e-7 * np.abs(default).max())


def test_bad_guess_and_non_convergence_are_named():
    with pytest.raises(ValueError, match="guess must be a finite"):
        shoot([math.nan, 0.0], 30.0)
    with pytest.raises(ShootingError, match="no convergence in 1 Newton steps"):
        shoot([0.0, 0.0], 30.0, max_steps=1)
