"""Pseudo-arclength continuation of periodic orbits (impactosc.dynamics.arclength):
model BC's period-1 branch with two impacts per period turns back at a fold near
w = 19.533 rad/s; followed forwards and backwards over it, the same branch comes back."""

import pytest

from impactosc.dynamics import shoot
from impactosc.dynamics.arclength import continue_branch, folds, locate_fold


@pytest.fixture(scope="module")
def forward():
    """From the stable orbit at w = 20 towards lower w, over the fold, up the saddle side."""
    start = shoot([-0.004902, -0.00789], 20.0)
    return start, continue_branch(start, 0.05, 20, direction=-1)


def test_the_fold_is_passed_and_a_multiplier_crosses_plus_one(forward):
    _, branch = forward
    ((a, b),) = folds(branch)
    assert a.orbit.stable != b.orbit.stable  # stable before the fold, a saddle after it
    assert all(p.orbit.residual < 1e-9 for p in branch)  # every point is an orbit: P(y) = y
    fold = locate_fold(a, b, tol=1e-6)
    assert 19.53 < fold.orbit.omega < 19.54
    assert abs(fold.orbit.multipliers[0] - 1) < 1e-6  # a multiplier at +1 there
    assert branch[-1].orbit.multipliers[0].real > 1  # the far side is a saddle


def test_backwards_over_the_fold_returns_to_the_same_branch(forward):
    start, branch = forward
    back = continue_branch(branch[-1].orbit, 0.05, 20, direction=-1)  # back down the saddle side
    ((a, b),) = folds(branch)
    ((a2, b2),) = folds(back)
    # the fold from either side (measured: the same w to 4e-14 rad/s)
    assert abs(locate_fold(a, b, tol=1e-6).orbit.omega - locate_fold(a2, b2, tol=1e-6).orbit.omega) < 1e-9
    end = back[-1].orbit
    assert end.stable and end.omega > 19.9
    # the same stable orbit as shooting there from the start of the forward run finds
    same = shoot([start.x0, start.v0], end.omega)
    assert abs(same.x0 - end.x0) < 1e-10 and abs(same.v0 - end.v0) < 1e-8
