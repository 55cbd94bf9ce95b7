"""The band of a branch: a periodic orbit's sensitivities at fixed w against the orbit re-solved
with the parameter moved, and the delta method over them."""

import dataclasses

import numpy as np
import pytest

from impactosc.dynamics.branch_segments import drawn_values, seed_from_rest
from impactosc.dynamics.orbit_sensitivity import band_standard_errors, orbit_sensitivities
from impactosc.dynamics.shooting import shoot
from impactosc.model.parameters import ModelParams

FIELDS = ("c", "m0e", "xI")
#: Relative agreement with the re-solved orbits. The reference is a second-order central
#: difference with a relative step of 1e-5 over orbits converged to 1e-12: its own error is
#: 1e-8-1e-7 (measured); 1e-5 leaves a margin of 100 and is far below what a band would show.
TOL = 1e-5


@pytest.fixture(scope="module")
def orbit_and_sensitivities():
    params = ModelParams()
    orbit = seed_from_rest(38.0, 2, params)  # period 2, two impacts per orbit
    return params, orbit, orbit_sensitivities(orbit, params, FIELDS)


def _resolved(params, orbit, field, value):
    p = dataclasses.replace(params, **{field: value})
    moved = shoot([orbit.x0, orbit.v0], orbit.omega, orbit.n_periods, p, tol=1e-12)
    d = drawn_values(moved.x0, moved.v0, moved.omega, moved.n_periods, p)
    return np.concatenate([[moved.x0, moved.v0], d["poincare_x"], d["isis"]])


@pytest.mark.parametrize("field", FIELDS)
def test_sensitivities_match_the_orbit_resolved_with_the_parameter_moved(orbit_and_sensitivities, field):
    params, orbit, sens = orbit_and_sensitivities
    base = float(getattr(params, field))
    h = 1e-5 * abs(base)
    reference = (_resolved(params, orbit, field, base + h) - _resolved(params, orbit, field, base - h)) / (2 * h)
    j = FIELDS.index(field)
    ours = np.concatenate([sens["state"][:, j], sens["poincare_x"][:, j], sens["isis"][:, j]])
    assert sens["poincare_x"].shape == (2, 3) and sens["isis"].shape == (2, 3)
    # compared per quantity kind, each relative to its largest entry
    for part in (slice(0, 2), slice(2, 4), slice(4, 6)):
        scale = np.max(np.abs(reference[part]))
        assert np.max(np.abs(ours[part] - reference[part])) <= TOL * scale, (field, ours[part], reference[part])


def test_band_standard_errors_are_the_delta_method(orbit_and_sensitivities):
    _params, _orbit, sens = orbit_and_sensitivities
    var = np.array([1e-4, 1e-12, 1e-12])  # c, m0e, xI
    se = band_standard_errors(sens, ["c", "xI", "m0e"], np.diag(var[[0, 2, 1]]))
    expected = np.sqrt((sens["poincare_x"] ** 2) @ var)
    np.testing.assert_allclose(se["poincare_x"], expected, rtol=1e-12)
    # a parameter the covariance does not name does not vary; one without sensitivities is refused
    only_c = band_standard_errors(sens, ["c"], [[1e-4]])
    np.testing.assert_allclose(only_c["isis"], np.abs(sens["isis"][:, 0]) * 1e-2, rtol=1e-12)
    with pytest.raises(ValueError, match="no sensitivities to \\['k'\\]"):
        band_standard_errors(sens, ["k"], [[1.0]])
