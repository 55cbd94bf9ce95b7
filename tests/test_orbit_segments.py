"""Branch segments (impactosc.dynamics.branch_segments): a continued piece of model BC's
period-1 branch finds its period doubling and its grazing as continuation events, at the
values located independently (tests/test_bifurcation_points.py, test_orbit_grazing.py), and
the monodromy of every continued orbit obeys Liouville's bound."""

import numpy as np
import pytest

from impactosc.dynamics import shoot
from impactosc.dynamics.branch_segments import trace_segment

# Located by bisection of det(M + I) on orbits shot at fixed w (test_bifurcation_points.py,
# 1e-9 rad/s) and by secant steps on the near-miss gap (test_orbit_grazing.py, 1e-9).
PD1 = 37.2843239
GRAZING = 23.044122336


def _liouville_holds(segment):
    # det M = exp(-int damping / m) <= exp(-c T / m): a finite-difference monodromy that broke
    # it would be wrong by more than its own error (measured ratio <= 0.36 on the branch)
    return all(p["det"] <= p["det_bound"] * (1 + 1e-6) for p in segment["points"])


def test_segment_through_a_period_doubling():
    seg = trace_segment(seed=shoot([-0.0088, -0.13], 37.0), ds=0.05, w_range=(36.9, 37.6), max_points=60)
    kinds = [p["kind"] for p in seg["special_points"]]
    assert kinds == ["period_doubling"], kinds  # no spurious fold where the two directions meet
    pd = seg["special_points"][0]
    assert pd["located"] and abs(pd["omega"] - PD1) < 1e-8
    # stable below, unstable above, and the points in increasing w
    w = np.array([p["omega"] for p in seg["points"]])
    assert np.all(np.diff(w) > 0)
    stable = np.array([p["stable"] for p in seg["points"]])
    assert stable[w < PD1 - 1e-3].all() and not stable[w > PD1 + 1e-3].any()
    assert _liouville_holds(seg)
    assert seg["stops"]["start"].startswith("w left") and seg["stops"]["end"].startswith("w left")


@pytest.mark.parametrize("ds", [0.02, 0.05])
def test_grazing_is_a_continuation_event(ds):
    """Past the grazing (lower w) the orbit has a second impact and a multiplier beyond -1;
    before it a stable complex pair: the grazing makes it lose stability at once."""
    seg = trace_segment(seed=shoot([-0.00394, -0.0203], 23.1), ds=ds, w_range=(22.98, 23.12), max_points=40)
    graz = [p for p in seg["special_points"] if p["kind"] == "grazing"]
    assert len(graz) == 1 and graz[0]["located"]
    assert abs(graz[0]["omega"] - GRAZING) < 1e-9
    assert graz[0]["impacts"] == [2, 1]  # in the order of the branch: increasing w
    past = np.array(graz[0]["mu_before_re"]) + 1j * np.array(graz[0]["mu_before_im"])
    before = np.array(graz[0]["mu_after_re"]) + 1j * np.array(graz[0]["mu_after_im"])
    assert np.abs(past).max() > 1 and np.abs(before).max() < 1
    assert _liouville_holds(seg)
