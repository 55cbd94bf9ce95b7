"""The measured forcing phase (encoder) and slow sweeps: chained surrogate runs with varying
w, Poincare points at the encoder's phase against the nominal ones, and one sweep record cut
into the points of the Fig 2 panel."""

import math

import numpy as np
import pytest

from impactosc.measured.surrogate import SurrogateOptions, ramp_omegas, surrogate_driven, surrogate_record

CLEAN = SurrogateOptions(rate=2000, noise=0.0)


def test_driven_at_constant_omega_is_the_plain_run():
    # chaining one-period runs (state and phase handed on) changes nothing at constant w
    w, n0, n = 30.0, 200, 150
    rec, truth = surrogate_driven(np.full(n, w), CLEAN, n_initial=n0)
    P = 2 * math.pi / w
    ref, ref_truth = surrogate_record(w, n0 * P, n * P - 1e-9, CLEAN)
    np.testing.assert_array_equal(rec.t, ref.t)
    np.testing.assert_allclose(rec.x, ref.x, rtol=0, atol=1e-12)  # measured 7e-14 m
    np.testing.assert_allclose(truth["impacts"]["t"], ref_truth["impacts"]["t"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(rec.phase, w * rec.t, rtol=1e-12)


def test_ramp_staircase_and_encoder_counts():
    om = ramp_omegas(30.0, 31.0, 50.0)
    assert om[0] == 30.0 and 30.99 < om[-1] < 31.0 and np.all(np.diff(om) > 0)
    assert np.sum(2 * np.pi / om[:-1]) < 50.0 <= np.sum(2 * np.pi / om)  # periods fill the duration
    rec, truth = surrogate_driven(om[:40], CLEAN, n_initial=10, encoder_counts=4096)
    # the phase is continuous, 2 pi per period, and read within half a count
    assert np.max(np.abs(rec.phase - truth["phase"])) <= np.pi / 4096 + 1e-9
    np.testing.assert_allclose(truth["poincare"]["t"][1:] - truth["poincare"]["t"][:-1], 2 * np.pi / om[:39])
    with pytest.raises(ValueError, match="one per period"):
        surrogate_driven([30.0, -1.0], CLEAN)
