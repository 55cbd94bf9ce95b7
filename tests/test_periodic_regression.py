"""Regression of the periodic-regime numbers (paper section 2.1, Fig 4c) and of the grazing
bracket, rebuilt from the core on short versions of the scenes.

References are stored in tests/data/periodic_reference.json, written by
tests/data/make_periodic_reference.py with the functions below (so test and reference
compute the same thing). The attractors here are periodic, so unlike a chaotic train they
are reproducible to the integration accuracy on any machine; each tolerance says how much
slack that accuracy needs.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from impactosc.core.simulation import Window, simulate
from impactosc.dynamics.grazing import extrapolate_gap_zero, find_grazing_step, locate_grazing, sweep_summary
from impactosc.dynamics.sweep import SweepSettings, branch_grid, continuation
from impactosc.statistics.periodic_train import branch_state, impact_map_numbers
from impactosc.statistics.periods import poincare_period
from impactosc.statistics.spectral_lines import analyse_spectrum

REF_PATH = Path(__file__).parent / "data" / "periodic_reference.json"
SETTINGS = SweepSettings(n_transient=150, n_record=60, n_initial=1000)  # as config periodic.branch


def period4_short() -> dict:
    """The period-4 scene (w = 23.03 from rest, 200 s + 100 s): section 2.1 numbers and Fig 4c."""
    omega = 23.03
    res = simulate(omega, 200.0, 100.0, window=Window(200.0, 300.0, 1e-3), record=("impacts", "poincare"))
    num = impact_map_numbers(res.events["impacts"]["t"], omega)
    sp = analyse_spectrum(res.trajectory["x"], 1e-3, omega)
    return {
        "n_impacts": num.n_impacts,
        "levels": list(num.levels),
        "counts": list(num.counts),
        "total": num.total,
        "poincare_period": poincare_period(res.events["poincare"]["x"], res.events["poincare"]["v"]),
        "omega1": sp.omega1,
        "labels_found": {k: v["found"] for k, v in sp.labels.items()},
        "resolution": sp.resolution,
    }


def short_branch(tol: float = 1e-4) -> dict:
    """Branch from rest at 23.10 (already on the period-1 orbit) down to 23.040 in steps of
    0.002, grazing bracketed to `tol`; the 23.05 attractor restarted from the branch."""
    grid = branch_grid(23.10, 23.10, 23.040, 0.002, 0.002)
    br = continuation(grid, SETTINGS)
    s = sweep_summary(br)
    i = find_grazing_step(s["omega"], s["min_gap"], s["impacts_per_period"])
    bracket = locate_grazing(br, SETTINGS, tol)
    fit = extrapolate_gap_zero(s["omega"][: i + 1], s["min_gap"][: i + 1], 5)
    x0, v0 = branch_state(br, 23.05)
    res = simulate(23.05, 20.0, 60.0, x0=x0, v0=v0, window=Window(20.0, 80.0, 1e-3))
    sp = analyse_spectrum(res.trajectory["x"], 1e-3, 23.05)
    j = int(np.argmin(np.abs(br.omega - 23.05)))
    return {
        "omega_miss": bracket.omega_miss,
        "omega_contact": bracket.omega_contact,
        "midpoint": bracket.midpoint,
        "n_trials": len(bracket.trials),
        "gap_fit_zero": fit.omega_zero,
        "gap_slope": fit.slope,
        "gap_2305": float(s["min_gap"][j]),
        "harmonics_only_2305": sp.harmonics_only,
        "step": [float(s["omega"][i]), float(s["omega"][i + 1])],
    }


def full_branch() -> dict:
    """The workflow's branch (config periodic.branch, grazing.tol): w = 40.86 down to 22.95."""
    grid = branch_grid(40.86, 23.3, 22.95, 0.05, 0.001)
    br = continuation(grid, SETTINGS)
    bracket = locate_grazing(br, SETTINGS, 1e-5)
    return {"omega_miss": bracket.omega_miss, "omega_contact": bracket.omega_contact, "midpoint": bracket.midpoint}


@pytest.fixture(scope="module")
def ref():
    return json.loads(REF_PATH.read_text())


@pytest.fixture(scope="module")
def period4():
    return period4_short()


@pytest.fixture(scope="module")
def branch():
    return short_branch()


def test_period4_numbers(period4, ref):
    r = ref["period4"]
    # a periodic orbit with a deterministic phase: the count in the window is exact
    assert period4["n_impacts"] == r["n_impacts"] == 489  # the paper's 489
    assert period4["counts"] == r["counts"] and len(period4["levels"]) == 4
    # ISIs: event times are located to ~1e-12 s, but the slowest (14 mm/s) impact turns a
    # position error ~rtol*|x| into a timing error up to ~5e-9 s; 2e-8 s covers that
    np.testing.assert_allclose(period4["levels"], r["levels"], rtol=0, atol=2e-8)
    assert period4["total"] == pytest.approx(3 * 2 * math.pi / 23.03, abs=1e-7)  # 3 forcing periods
    assert abs(period4["total"] - 0.8184) <= 1e-4  # the paper prints 4 digits (truncated)
    assert period4["poincare_period"] == 3


def test_period4_spectrum(period4, ref):
    r = ref["period4"]
    # w1 from a parabola through three bins of the same 100 s signal: only the integration
    # error (~1e-10 relative) differs between machines; 1e-4 rad/s = 0.2 % of a bin
    assert period4["omega1"] == pytest.approx(r["omega1"], abs=1e-4)
    # the model's w1 is w/3 to within one bin: a subharmonic, not a second frequency
    assert abs(period4["omega1"] - 23.03 / 3) < period4["resolution"]
    assert set(period4["labels_found"]) == {"a", "b", "c", "d", "f"}
    for k, found in period4["labels_found"].items():
        assert found is not None and found == pytest.approx(r["labels_found"][k], abs=1e-3), k


def test_grazing_bracket_short_branch(branch, ref):
    r = ref["short_branch"]
    assert branch["step"] == pytest.approx(r["step"], abs=1e-9)  # same grid step holds the grazing
    # one bisection decision that flipped would move the midpoint by at most the bracket
    # width (1e-4); the decisions are far from ambiguous (gap ~1e-7 m vs errors ~1e-11 m)
    assert branch["midpoint"] == pytest.approx(r["midpoint"], abs=1e-4)
    assert abs(branch["omega_miss"] - branch["omega_contact"]) <= 1e-4
    # required: the grazing w to 1e-4 rad/s, agreeing with the full workflow
    # branch from 40.86 (full_branch(), stored by make_periodic_reference.py --full; the
    # workflow's results/paper/stats/periodic/grazing.json gives the same 23.0441211)
    assert branch["midpoint"] == pytest.approx(ref["full_branch"]["midpoint"], abs=1e-4)
    assert 23.03 < branch["midpoint"] < 23.05  # between the paper's before/after w


def test_grazing_gap_line_short_branch(branch, ref):
    r = ref["short_branch"]
    # converged near-miss gaps carry errors ~1e-10 m; with the slope 1.1e-3 m/(rad/s) the
    # zero moves by ~1e-7 rad/s; 1e-6 leaves a factor 10
    assert branch["gap_fit_zero"] == pytest.approx(r["gap_fit_zero"], abs=1e-6)
    assert branch["gap_fit_zero"] == pytest.approx(ref["full_branch"]["midpoint"], abs=1e-5)
    # the attractor at 23.05 is the same orbit whatever branch history led to it: 6.43 um gap
    # to 1e-9 m (150 periods of transient leave < 1e-11 m of the restart mismatch)
    assert branch["gap_2305"] == pytest.approx(r["gap_2305"], abs=1e-9)
    assert branch["harmonics_only_2305"] is True


@pytest.mark.slow
def test_grazing_full_branch(ref):
    """The workflow's branch from 40.86 (about 40 s): bracket to 1e-5 as in results/paper/stats/periodic/grazing.json."""
    full = full_branch()
    assert full["midpoint"] == pytest.approx(ref["full_branch"]["midpoint"], abs=1e-5)
    assert abs(full["omega_miss"] - full["omega_contact"]) <= 1e-5
