"""Bifurcation points of periodic orbits (impactosc.dynamics.bifurcation_points): the
test functions on families of matrices with a known answer, and model BC's first period
doubling of the period-1 orbit, checked by the time simulation on both sides."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.dynamics import shoot
from impactosc.dynamics.bifurcation_points import crossings, follow, locate


def rotation(angle):
    return np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])


# families M(w) whose bifurcation is at a known w
FAMILIES = {
    "period_doubling": (lambda w: np.diag([-0.8 * w, 0.3]), 1.25),  # mu = -0.8 w through -1
    "fold": (lambda w: np.diag([w * w, 0.5]), 1.0),  # mu = w^2 through +1
    "neimark_sacker": (lambda w: (0.5 + 0.25 * w) * rotation(1.0), 2.0),  # |mu| = 0.5 + w/4
}


@pytest.mark.parametrize("kind", sorted(FAMILIES))
def test_each_test_function_locates_its_known_bifurcation(kind):
    family, exact = FAMILIES[kind]

    def solve(w, near):
        return SimpleNamespace(omega=w, monodromy=family(w))

    w, _ = locate(kind, solve(exact - 0.3, None), solve(exact + 0.45, None), solve=solve, tol=1e-10)
    assert abs(w - exact) < 1e-10


def test_no_sign_change_and_real_pair_are_refused():
    pd, _ = FAMILIES["period_doubling"]
    a, b = (SimpleNamespace(omega=w, monodromy=pd(w)) for w in (0.1, 0.2))
    with pytest.raises(ValueError, match="no sign change"):
        locate("period_doubling", a, b, solve=lambda w, near: near)
    real = {w: SimpleNamespace(omega=w, monodromy=np.diag([w, 0.5])) for w in (1.5, 2.5)}
    with pytest.raises(ValueError, match=r"multipliers at .* are real"):
        locate(
            "neimark_sacker",
            real[1.5],
            real[2.5],
            solve=lambda w, near: SimpleNamespace(omega=w, monodromy=np.diag([w, 0.5])),
        )


# model BC's period-1 orbit loses stability by period doubling at this w (rad/s), located by
# locate() with difference steps 1e-3 and 1e-4 of the state's scale: 37.2843239004 and
# 37.2843239001 (brute-force sweeps read 37.25: near the bifurcation the multiplier is close
# to -1 and their 200-period transients have not decayed). Tolerance 1e-8 rad/s, the required
# bound; an independent check of the bracket is the time simulation below.
PD1 = 37.2843239


def test_model_bc_period_doubling_of_the_period_one_orbit():
    orbits = follow(np.arange(37.0, 37.51, 0.1), [-0.0088, -0.13])
    ((lo, hi),) = crossings(orbits, "period_doubling")
    w, orbit = locate("period_doubling", lo, hi, tol=1e-9)
    assert abs(w - PD1) < 1e-8
    assert abs(orbit.multipliers[0] + 1) < 1e-6  # one multiplier at -1 ...
    assert abs(orbit.multipliers[1]) < 0.5  # ... and the other well inside the circle


@pytest.mark.parametrize(("omega", "period"), [(PD1 - 0.02, 1), (PD1 + 0.02, 2)])
def test_time_simulation_agrees_on_each_side_of_the_period_doubling(omega, period):
    """From the shot period-1 orbit displaced by 1 um, the simulation returns to it below the
    bifurcation (|mu| < 1) and leaves it for a period-2 orbit above (mu < -1)."""
    orbit = shoot([-0.0088, -0.13], omega)
    run = simulate(omega, 1500 * 2 * math.pi / omega, 8 * 2 * math.pi / omega, x0=orbit.x0 + 1e-6, v0=orbit.v0,
                   record=("poincare",), rtol=1e-12, atol=1e-14)  # fmt: skip
    x = run.events["poincare"]["x"]
    if period == 1:
        assert np.ptp(x) < 1e-9 and abs(x[-1] - orbit.x0) < 1e-9
    else:
        assert abs(x[-1] - x[-3]) < 1e-9 and abs(x[-1] - x[-2]) > 1e-6  # alternates: period 2
