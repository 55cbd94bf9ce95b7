"""The Taylor stepper of the method benchmark: its recurrences against closed-form series, and
each piece integrated to its end against SciPy DOP853 at rtol 1e-13 (the independent reference
the benchmark compares with)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit
from scipy.special import binom

from impactosc_bench import taylor_series as ts


@njit(cache=True)
def _series(kind, alpha, n):
    """Coefficients 0..n of a composite series of a = 1 + t (u = t for sin/cos)."""
    a = np.zeros(n + 1)
    a[0], a[1] = 1.0, 1.0
    u = np.zeros(n + 1)
    u[1] = 1.0
    out, aux = np.zeros(n + 1), np.zeros(n + 1)
    one = np.zeros(n + 1)
    one[0] = 1.0
    for k in range(n + 1):
        if kind == 0:
            out[k] = ts.real_power(a, out, alpha, k)
        elif kind == 1:
            out[k] = ts.square_root(a, out, k)
        elif kind == 2:
            out[k] = ts.quotient(one, a, out, k)
        elif k == 0:
            out[0], aux[0] = 0.0, 1.0  # sin 0, cos 0
        else:
            out[k], aux[k] = ts.sine_cosine(u, out, aux, k)
    return out


@pytest.mark.parametrize("alpha", [1.5, -0.5, 5.357])
def test_real_power_gives_the_binomial_series(alpha):
    k = np.arange(21)
    np.testing.assert_allclose(_series(0, alpha, 20), binom(alpha, k), rtol=1e-12, atol=1e-15)


def test_sqrt_quotient_and_sine_give_their_closed_forms():
    k = np.arange(21)
    np.testing.assert_allclose(_series(1, 0.0, 20), binom(0.5, k), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(_series(2, 0.0, 20), (-1.0) ** k, rtol=1e-12)
    sine = [0.0 if j % 2 == 0 else (-1.0) ** (j // 2) / math.factorial(j) for j in k]
    np.testing.assert_allclose(_series(3, 0.0, 20), sine, rtol=1e-12, atol=1e-30)


@pytest.fixture(scope="module")
def pieces():
    from impactosc_bench.taylor_pieces import pieces as make

    return make()


@pytest.mark.parametrize("order", [12, 20])
def test_each_piece_reaches_scipys_end(pieces, order):
    """rtol 1e-10: the piece's end within 1e-11 s in time and 1e-11 m in x (a few hundred times
    the tolerance of its 10-20 steps at atol 1e-12, far below a wrong piece's errors: the band
    integrated in time misses by 3e-5 m, see benchmark_taylor)."""
    from impactosc_bench.taylor_pieces import OMEGA

    for name, pc in pieces.items():
        p = pc.params.as_array(OMEGA)
        a, b, steps = ts.integrate_piece(p, pc.kind, pc.s0, pc.s1, pc.sgn, pc.tref, pc.a0, pc.b0, order, 1e-10, 1e-12)
        assert 3 <= steps < 40, (name, steps)
        if pc.kind == ts.TIME_PIECE:  # (x, v)
            assert abs(a - pc.a_end) < 1e-11 and abs(b - pc.b_end) < 1e-9, name
        else:  # (tau, x)
            assert abs(a - pc.a_end) < 1e-11 and abs(b - pc.b_end) < 1e-11, name


def test_the_core_step_on_the_same_pieces_agrees(pieces):
    """The DOP853 side of the comparison runs the same equations to the same ends."""
    from impactosc_bench.taylor_pieces import _DOP853_MODE, OMEGA, _dop853_piece

    for name, pc in pieces.items():
        mode, phase = _DOP853_MODE[pc.kind]
        p = pc.params.as_array(OMEGA)
        a, b, _ = _dop853_piece(p, mode, phase, pc.sgn, pc.s0, pc.s1, pc.tref, pc.a0, pc.b0, pc.v0, 1e-10, 1e-12)
        tol_a = 1e-11
        tol_b = 1e-9 if pc.kind == ts.TIME_PIECE else 1e-11
        assert abs(a - pc.a_end) < tol_a and abs(b - pc.b_end) < tol_b, name
