"""The period-doubling cascade below the chaos at w = 40.86 (impactosc.dynamics.cascade):
the first two doublings located orbit by orbit, with branch switching, and checked by the time
simulation on both sides of the second."""

import math

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.dynamics import shoot
from impactosc.dynamics.cascade import cascade, feigenbaum_ratios

# Located by cascade() (bisection to 1e-9 rad/s, monodromy steps 1e-3 and 1e-4 of the state's
# scale agree to 4e-10); the sweeps read 37.25 and 38.99-39.01. Tolerance 1e-8 rad/s, the
# required bound; the time simulation below checks the second independently.
PD = (37.2843239, 39.0362941)


@pytest.fixture(scope="module")
def doublings():
    return cascade(shoot([-0.0088, -0.13], 37.0), 2)


def test_first_two_doublings(doublings):
    assert [d.n_periods for d in doublings] == [1, 2]
    for d, w in zip(doublings, PD, strict=True):
        assert abs(d.omega - w) < 1e-8
        assert abs(d.orbit.multipliers[0] + 1) < 1e-6


@pytest.mark.parametrize(("offset", "period"), [(-0.02, 2), (0.02, 4)])
def test_time_simulation_sees_period_two_then_four(doublings, offset, period):
    orbit = doublings[1].orbit
    w = doublings[1].omega + offset
    start = shoot([orbit.x0, orbit.v0], w, 2)  # the period-2 orbit there (stable below, a saddle above)
    run = simulate(w, 2000 * 2 * math.pi / w, 8 * 2 * math.pi / w, x0=start.x0 + 1e-6, v0=start.v0,
                   record=("poincare",), rtol=1e-12, atol=1e-14)  # fmt: skip
    x = run.events["poincare"]["x"]
    assert np.max(np.abs(x[period:] - x[:-period])) < 1e-9  # repeats after `period` ...
    assert abs(x[period // 2] - x[0]) > 1e-7  # ... and not after half of it


def test_feigenbaum_ratio_of_three_points():
    from types import SimpleNamespace

    ds = [SimpleNamespace(omega=w) for w in (0.0, 1.0, 1.25)]
    assert feigenbaum_ratios(ds) == [4.0]
