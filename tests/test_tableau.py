"""The DOP853 coefficients satisfy the order conditions they are supposed to."""

import math

import numpy as np

from impactosc.core import tableau as tab


def test_stage_times_are_row_sums():
    # consistency c_i = sum_j a_ij for all 16 stages (to rounding of the 30-digit constants)
    np.testing.assert_allclose(tab.A.sum(axis=1), tab.C, atol=1e-14)


def test_quadrature_conditions_order_8():
    # sum_i b_i c_i^k = 1/(k+1) for k = 0..7 is necessary for order 8
    b, c = tab.B, tab.C[: tab.N_STAGES]
    for k in range(8):
        assert math.isclose(float(b @ c**k), 1.0 / (k + 1), rel_tol=0, abs_tol=1e-14), k


def test_embedded_error_weights_annihilate_low_orders():
    # the error estimators vanish on polynomials the embedded methods integrate exactly
    c = tab.C[: tab.N_STAGES + 1]
    for k in range(3):
        assert abs(float(tab.E5 @ c**k)) < 1e-13
        assert abs(float(tab.E3 @ c**k)) < 1e-13
