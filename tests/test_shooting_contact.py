"""Shooting and Lyapunov exponents of a restitution law's orbit whose stroboscopic point lies
inside a contact: the map's state is (x, v, v0) there, and its multipliers must be those of an
independent SciPy integration of the law, at that section and at one in free flight."""

import dataclasses
import math

import numpy as np
import pytest

from impactosc.dynamics.arclength import continue_branch
from impactosc.dynamics.lyapunov import lyapunov_spectrum
from impactosc.dynamics.orbit_sensitivity import orbit_sensitivities
from impactosc.dynamics.point_sensitivity import point_sensitivities
from impactosc.dynamics.shooting import SCALE, SCALE_V0, central_difference, monodromy, reduced, shoot
from impactosc.model.parameters import ModelParams
from impactosc_bench.scipy_reference import solve_reference

# Flores' law (e = 0.6) on a soft obstacle without dry friction: at w = 13.5 rad/s the period-1
# orbit hits the obstacle at phase 0.97 and stays in contact until phase 0.69 of the next period,
# so its phase-0 point lies inside a contact (onset velocity 7.3 mm/s) and phase 0.83 in free flight.
FLORES = dataclasses.replace(ModelParams(), law="flores", e=0.6, kI=1e7, T=0.0)
OMEGA = 13.5
PERIOD = 2 * math.pi / OMEGA
GUESS = [-2.0051e-3, 1.4437e-3, 7.2537e-3]  # (x, v, v0) after 300 periods from rest, rounded
FREE_PHASE = 0.83
# Tolerance on a multiplier against the SciPy reference: differences of step 1e-4 of SCALE
# (1e-7 m) over the solvers' errors (rtol 1e-12 here, 1e-13 there) leave ~1e-8 in M's entries;
# measured: 2.6e-8 on mu1 = -1.3e-2 and 5e-10 on mu2 = 5.0e-6. 1e-6 is 40 times that, and 1e4
# times below the error of holding v0 fixed (test_holding_v0_fixed_gives_other_multipliers).
MU_TOL = 1e-6


@pytest.fixture(scope="module")
def orbit():
    return shoot(GUESS, OMEGA, 1, FLORES)


def reference_map(y, t0):
    """One forcing period of the SciPy integration of the law from y at time t0."""
    run = solve_reference(
        OMEGA, t0 + PERIOD, x0=y[0], v0=y[1], contact_v0=y[2] if len(y) > 2 else None, params=FLORES, t0=t0,
        rtol=1e-13, atol=1e-15,
    )  # fmt: skip
    return run["final"][: len(y)]


def reference_jacobian(y, t0, step=1e-4):
    scale = np.append(SCALE, SCALE_V0)[: len(y)]
    M = np.empty((len(y), len(y)))
    for j in range(len(y)):
        unit = np.eye(len(y))[j]
        M[:, j] = central_difference(lambda s, unit=unit: reference_map(y + s * unit, t0), step * scale[j])
    return M


def by_value(mu):
    return np.sort_complex(np.asarray(mu, complex))


def test_orbit_inside_a_contact_is_a_fixed_point_of_the_reference_map(orbit):
    assert math.isfinite(orbit.contact_v0) and orbit.x0 > FLORES.xI
    assert orbit.residual < 1e-10
    # the SciPy integration from (x, v, v0) returns to it: the orbit and its v0 are the law's,
    # to the solvers' tolerance (states of mm and mm/s, rtol 1e-12 / 1e-13)
    np.testing.assert_allclose(reference_map(orbit.state, 0.0), orbit.state, rtol=0, atol=1e-11)


def test_multipliers_match_the_reference_at_both_sections(orbit):
    # the reference at the same section, in (x, v, v0), reduced as the shooting reduces
    at_contact = np.linalg.eigvals(reduced(reference_jacobian(orbit.state, 0.0)))
    np.testing.assert_allclose(by_value(orbit.multipliers), by_value(at_contact), rtol=0, atol=MU_TOL)
    # a section in free flight (phase 0.83) has the conjugate map in (x, v) alone: same multipliers
    y = reference_map(orbit.state, 0.0)
    free = solve_reference(OMEGA, FREE_PHASE * PERIOD, x0=y[0], v0=y[1], contact_v0=y[2], params=FLORES,
                           rtol=1e-13, atol=1e-15)["final"]  # fmt: skip
    assert math.isnan(free[2]) and free[0] < FLORES.xI
    in_flight = np.linalg.eigvals(reference_jacobian(free[:2], FREE_PHASE * PERIOD))
    np.testing.assert_allclose(by_value(orbit.multipliers), by_value(in_flight), rtol=0, atol=MU_TOL)


def test_the_third_multiplier_is_zero_and_v0_matters(orbit):
    _, M = monodromy(orbit.state, OMEGA, 1, FLORES)
    assert M.shape == (3, 3)
    mu = np.sort(np.abs(np.linalg.eigvals(M)))
    # v0 is forgotten at the contact's exit: M has rank 2 (its smallest eigenvalue is the
    # differences' noise, ~1e-12), and the other two are the orbit's
    assert mu[0] < 1e-9
    np.testing.assert_allclose(mu[1:], np.sort(np.abs(orbit.multipliers)), rtol=0, atol=MU_TOL)


def test_holding_v0_fixed_gives_other_multipliers(orbit):
    """Why the v0 column: the (x, v) block alone (v0 held at the orbit's) misses mu1 entirely."""
    _, M = monodromy(orbit.state, OMEGA, 1, FLORES)
    frozen = np.sort(np.abs(np.linalg.eigvals(M[:2, :2])))
    assert abs(frozen[-1] - abs(orbit.multipliers[0])) > 1e4 * MU_TOL


def test_lyapunov_spectrum_from_a_point_inside_a_contact(orbit):
    run = lyapunov_spectrum(orbit.state, OMEGA, 12, FLORES)
    assert run.points.shape == (12, 3) and np.all(np.isfinite(run.points))
    # On a periodic orbit the area's growth per period is |det M| once the tangent vectors lie in
    # the surface of reachable states (from the second period: they start with v0 held). The
    # second-order differences of step 1e-5 of SCALE resolve the direction that contracts by
    # mu2 = 5e-6 to ~1e-3 (its image, 5e-11 of SCALE, is 50 times the solver's error): measured
    # spread 1.5e-3 of log |det| = -16.5, hence 5e-3.
    np.testing.assert_allclose(run.log_det[1:], math.log(abs(np.prod(orbit.multipliers))), rtol=0, atol=5e-3)
    # each period's growth along the two vectors is log |mu1|, log |mu2| once the first has turned
    # to mu1's eigenvector (by mu2 / mu1 = 4e-4 a period): from the third period on, to the same 5e-3
    sums = run.running * np.arange(1, 13)[:, None]
    np.testing.assert_allclose(np.diff(sums, axis=0)[2:], np.log(np.abs(orbit.multipliers))[None, :].repeat(9, 0),
                               rtol=0, atol=5e-3)  # fmt: skip


def test_arclength_continuation_carries_v0_along_the_branch(orbit):
    branch = continue_branch(orbit, 0.05, 4, FLORES)
    assert branch[-1].orbit.omega > OMEGA + 0.1  # it moved along the branch
    for point in branch:
        o = point.orbit
        assert math.isfinite(o.contact_v0) and o.residual < 1e-10 and point.tangent.shape == (3,)
        # the corrector's orbit is the shooting's at its w (an independent Newton in (x, v, v0)):
        # both converge to 1e-10 of SCALE, and their multipliers to the differences' 1e-7
        again = shoot(o.state, o.omega, 1, FLORES)
        np.testing.assert_allclose(again.state, o.state, rtol=0, atol=1e-11)
        np.testing.assert_allclose(by_value(again.multipliers), by_value(o.multipliers), rtol=0, atol=MU_TOL)


def test_the_constructions_in_x_v_alone_refuse_a_section_inside_a_contact(orbit):
    with pytest.raises(ValueError, match="inside a flores contact"):
        orbit_sensitivities(orbit, FLORES, fields=("m",))
    with pytest.raises(ValueError, match="inside a flores contact"):
        point_sensitivities("period_doubling", OMEGA, orbit, FLORES, fields=("m",))
