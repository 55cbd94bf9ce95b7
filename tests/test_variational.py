"""The monodromy from the variational equations (impactosc.dynamics.variational): against the
closed form of the forced linear oscillator, against the finite-difference monodromy of
shooting.monodromy on model BC's impacting orbits, its convergence in rtol and in the window of
the variable u = sgn(v)|v|^n3, and its image against the core's stroboscopic map."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.linalg import expm

from impactosc.core.simulation import simulate
from impactosc.dynamics import shoot, stroboscopic_map
from impactosc.dynamics.shooting import SCALE
from impactosc.dynamics.variational import (
    V_WINDOW,
    UnsupportedTrajectory,
    _integrate,
    _Model,
    variational_monodromy,
)
from impactosc.model.parameters import ModelParams, UntestedParameterWarning

# Impacting orbits without sticking (the period-1 orbit near w = 24.5 sticks: see the last tests).
# name: (omega, forcing periods N, Newton guess (None: the attractor reached from rest), impacts)
ORBITS = {
    "period-1 w=30": (30.0, 1, [-0.0135, -0.115], 1),
    # the attractor just after the grazing at w = 23.03 has period 3 (4 impacts per period, one
    # of them slow, 1.4 cm/s): the paper's 4 inter-impact levels add up to 3 forcing periods
    "period-3 w=23.03": (23.03, 3, None, 4),
    "period-2 w=38": (38.0, 2, None, 2),  # after the doubling at w = 37.2843, stable up to 39.0363
}
_cache = {}


def orbit(name):
    """(PeriodicOrbit by shooting, image and M from the variational equations at rtol 1e-12)."""
    if name not in _cache:
        omega, n, guess, _ = ORBITS[name]
        if guess is None:
            run = simulate(omega, 200.0, 4 * n * 2 * math.pi / omega, record=("poincare",), rtol=1e-12, atol=1e-14)
            guess = [run.events["poincare"]["x"][-1], run.events["poincare"]["v"][-1]]
        o = shoot(guess, omega, n)
        _cache[name] = (o, *variational_monodromy([o.x0, o.v0], omega, n))
    return _cache[name]


def rel(a, b):
    """max |a - b| relative to max |b|."""
    return np.abs(a - b).max() / np.abs(b).max()


@pytest.mark.parametrize("omega", [8.0, 23.03, 40.86])
@pytest.mark.parametrize("n_periods", [1, 3])
def test_linear_oscillator_monodromy_is_the_matrix_exponential(linear_params, omega, n_periods):
    """m x'' + c x' + k x = m0e w^2 sin(w t): Phi(t) = exp(A t) whatever the state and forcing."""
    p = linear_params
    A = np.array([[0.0, 1.0], [-p.k / p.m, -p.c / p.m]])
    exact = expm(A * 2 * math.pi * n_periods / omega)
    for y in ([0.0, 0.0], [2e-3, -0.05]):  # from rest (a reversal at t = 0) and from a moving state
        _, M = variational_monodromy(y, omega, n_periods, p)
        # measured: <= 5.6e-12 of max|M| (w = 8, the longest run, ~100 steps per period at rtol
        # 1e-12); 1e-10 leaves a factor 20 for the accumulation of the local errors
        assert rel(M, exact) < 1e-10


# Measured max|M_var - M_FD| / max|M| (FD of shooting.monodromy, its default step 1e-4 of SCALE):
# 4.6e-10, 1.0e-9 and 3.5e-9. The variational M is converged far below that (7.7e-12, 1.3e-10 and
# 8.2e-12 between rtol 1e-12 and 1e-13), so this is the FD's own error: it falls as the step
# grows (step 1e-3: 7e-11, 9e-9, 1.5e-10; 1e-5: 9e-10, 8e-9, 1.3e-8; 1e-6: 3e-8 to 2e-7), the
# signature of the solver's noise divided by the step, and FD steps 1e-3 and 1e-5 differ by up to
# 1.3e-8 on these orbits (2e-8 in shooting.py's analysis). Each tolerance is ~10x the measured
# disagreement, capped at that 2e-8 the FD analysis allows.
FD_TOL = {"period-1 w=30": 5e-9, "period-3 w=23.03": 1e-8, "period-2 w=38": 2e-8}


@pytest.mark.parametrize("name", ORBITS)
def test_variational_monodromy_agrees_with_finite_differences(name):
    o, _, M = orbit(name)
    assert rel(o.monodromy, M) < FD_TOL[name]
    # the multipliers follow: all of modulus < 1 (these orbits are stable) on both sides
    mu = np.linalg.eigvals(M)
    np.testing.assert_allclose(np.sort_complex(mu), np.sort_complex(o.multipliers), rtol=0, atol=1e-7)
    assert np.all(np.abs(mu) < 1)


@pytest.mark.parametrize("name", ORBITS)
def test_variational_monodromy_converges_in_rtol(name):
    """Measured (relative to max|M|): rtol 1e-10 vs 1e-13 7.6e-10, 1.8e-8, 1.1e-8; 1e-12 vs 1e-13
    7.7e-12, 1.3e-10, 8.2e-12 (and 1e-11 vs 1e-12 1.5e-11, 5.0e-10, 1.5e-10): the error falls with
    the tolerance through the windows of u around every deepest penetration, so the singular
    dF_I/dv is integrated consistently. Bounds ~10x the largest measured value."""
    o, _, M12 = orbit(name)
    omega, n, *_ = ORBITS[name]
    y = [o.x0, o.v0]
    M10 = variational_monodromy(y, omega, n, rtol=1e-10)[1]
    M13 = variational_monodromy(y, omega, n, rtol=1e-13)[1]
    assert rel(M10, M13) < 2e-7
    assert rel(M12, M13) < 1e-9
    assert rel(M12, M13) < rel(M10, M13) / 10


@pytest.mark.parametrize("name", ORBITS)
def test_variational_monodromy_does_not_depend_on_the_window(name):
    """The border of the u window is a choice, not an approximation: windows of 1 mm/s and 10 cm/s
    (this one above the slow impact's 1.4 cm/s at w = 23.03, so there u starts at half the impact
    velocity) agree with the default 1 cm/s to 1.7e-10 (measured), i.e. to the solver's tolerance."""
    o, _, M = orbit(name)
    omega, n, *_ = ORBITS[name]
    for v_window in (1e-3, 1e-1):
        assert rel(variational_monodromy([o.x0, o.v0], omega, n, v_window=v_window)[1], M) < 2e-9


def test_the_right_hand_side_in_u_is_bounded_where_the_one_in_t_is_not():
    """At the deepest penetration of the w = 30 orbit (h = 0.289 mm, a = -136 m/s^2): over the
    whole window, including u = 0 itself, the derivatives in u stay below their value at the
    window's border (measured: 0.84 at u = 0, 650 at the border), while the entry da/dv of the
    Jacobian in time grows like |v|^(n3 - 1) without bound (1e245 at the smallest |v|)."""
    p = ModelParams()
    model = _Model(p, 30.0)
    rhs_u, rhs_t = model.u_rhs(), model.time_rhs(True)
    t, x = 0.12489617, p.xI + 2.8913e-4
    border = V_WINDOW**p.n3
    us = np.concatenate([np.linspace(-border, border, 2001), [0.0, 1e-300, -1e-300, 1e-12, -1e-12]])
    sizes = np.array([np.abs(rhs_u(u, [t, x, 1.0, 0.0, 0.0, 1.0])).max() for u in us])
    assert np.all(np.isfinite(sizes))
    edge = max(np.abs(rhs_u(s * border, [t, x, 1.0, 0.0, 0.0, 1.0])).max() for s in (-1, 1))
    assert sizes.max() <= edge
    tiny_v = 1e-300 ** (1 / p.n3)  # underflows to 0: the time Jacobian's |v|^(n3-1) is capped at 1e-300
    assert abs(rhs_t(t, [x, tiny_v, 1.0, 0.0, 0.0, 1.0])[5]) > 1e200


@pytest.mark.parametrize("name", ORBITS)
def test_friction_band_is_resolved_explicit_and_implicit_agree(name):
    """The friction band at each free-flight reversal (slope T/eps = 6e5 N s/m) met by DOP853 at rtol
    1e-12 and by SciPy's implicit Radau at rtol 1e-10 (stiff-stable, so it cannot be misled by
    stiffness): measured 2.3e-12, 1.7e-9 and 3.4e-10 of max|M| apart; the bound is ~10x the
    largest (DOP853 itself at rtol 1e-10 is 1e-9 .. 2e-8 off on these orbits). 1 to 5 s each."""
    o, _, M = orbit(name)
    omega, n, *_ = ORBITS[name]
    _, M_radau, log = _integrate([o.x0, o.v0], omega, n, method="Radau", rtol=1e-10)
    assert rel(M_radau, M) < 2e-8
    # every deepest penetration is integrated in u, in two halves split at u = 0
    assert sum(var == "u" for _, var, *_ in log) == 2 * ORBITS[name][3]


@pytest.mark.parametrize("name", ORBITS)
def test_image_agrees_with_the_core_stroboscopic_map(name):
    """P^N(y) by SciPy against the numba core, both at rtol 1e-12: measured 6.4e-11 of SCALE
    (1 mm, 0.1 m/s) at most; bound 1e-9, ~15x that (each solver's global error after up to
    three periods is some 10-100 local tolerances)."""
    o, image, _ = orbit(name)
    omega, n, *_ = ORBITS[name]
    core = stroboscopic_map([o.x0, o.v0], omega, n)
    assert np.all(np.abs(image - core) / SCALE < 1e-9)
    # and it is the fixed point: the orbit closes to the same level
    assert np.all(np.abs(image - [o.x0, o.v0]) / SCALE < 1e-9)


def test_sticking_orbit_is_refused():
    """The period-1 attractor at w = 24.5 sticks at a reversal (net force 0.53 N < T = 0.63 N)."""
    with pytest.raises(UnsupportedTrajectory, match=r"sticks at t = .*needs \|F\| > 2 T"):
        variational_monodromy([-0.0052111, -0.01514325], 24.5)


def test_bad_input_is_named():
    y = [-0.0135, -0.115]
    cases = [
        (dict(y=[math.nan, 0.0]), "y must be a finite state"),
        (dict(y=[0.0, 0.0, 0.0]), "y must be a finite state"),
        (dict(omega=0.0), "omega must be a finite number > 0"),
        (dict(omega=math.inf), "omega must be a finite number > 0"),
        (dict(n_periods=0), "n_periods must be an integer >= 1"),
        (dict(n_periods=1.5), "n_periods must be an integer >= 1"),
        (dict(params={"m": 1.0}), "params must be a ModelParams"),
        (dict(rtol=1e-15), "rtol must be in"),
        (dict(rtol=1.0), "rtol must be in"),
        (dict(atol=0.0), "atol must be a finite number > 0"),
        (dict(v_window=-1.0), "v_window must be a finite number > 0"),
    ]
    for change, message in cases:
        args = dict(y=y, omega=30.0, n_periods=1, params=None) | change
        kw = {k: args.pop(k) for k in ("rtol", "atol", "v_window") if k in args}
        with pytest.raises(ValueError, match=message):
            variational_monodromy(args["y"], args["omega"], args["n_periods"], args["params"], **kw)
    with pytest.warns(UntestedParameterWarning):
        soft = dataclasses.replace(ModelParams(), n1=0.5)
    with pytest.raises(ValueError, match="n1 and n2 must be >= 1"):
        variational_monodromy(y, 30.0, params=soft)
