"""The peer-solver benchmark (benchmarks/peers.py and the modules it runs): its selection logic,
the timing rounds' rows and table, and CyRK and heyoka on model BC.

The CyRK and heyoka tests skip when the package is not installed (the ``peers`` extra), or
when the CyRK shim cannot be built here (no C++ compiler): the benchmark itself skips the
peer then. The first CyRK test of a machine compiles the shim (about 13 s, cached after).
"""

import math
import sys

import numpy as np
import pytest

from impactosc_bench import cyrk_runs, cyrk_shim, free_flight, peers, timing_rounds
from impactosc_bench.scene import ERR_HORIZON, OMEGA
from impactosc_bench.scipy_reference import solve_reference


def _row(rtol, wall, error, on, solver="CyRK DOP853", kind="scene"):
    return dict(solver=solver, kind=kind, rtol=rtol, wall_time=wall, impact_time_error_1p5s=error, on_attractor=on)


def test_best_peer_is_the_fastest_accurate_row_on_the_attractor():
    rows = [
        _row(1e-9, 0.5, 3e-7, True),  # fastest, too inaccurate
        _row(1e-10, 0.6, 1e-9, False),  # accurate enough but left the attractor
        _row(1e-11, 0.9, 2e-9, True),  # the answer
        _row(1e-12, 1.2, 3e-11, True),  # accurate, slower
        _row(1e-11, 0.7, math.inf, True, solver="CyRK Vern8"),  # impact count differs
        _row(1e-10, 0.01, None, None, solver="heyoka free flight", kind="floor"),  # no contact
    ]
    best = peers.best_peer(rows, max_error=2.5e-9)
    assert (best["solver"], best["rtol"]) == ("CyRK DOP853", 1e-11)
    assert peers.best_peer(rows, max_error=1e-10)["rtol"] == 1e-12
    assert peers.best_peer(rows, max_error=1e-12) is None
    assert peers.best_peer([]) is None


def test_on_attractor_is_within_ten_percent_of_the_core():
    assert timing_rounds.on_attractor(2898, 2898)
    assert timing_rounds.on_attractor(2882, 2898)
    assert timing_rounds.on_attractor(2610, 2900) and not timing_rounds.on_attractor(2609, 2900)
    assert not timing_rounds.on_attractor(1177, 2898)  # a run that settled on another orbit


def test_table_marks_what_does_not_apply():
    rows = [
        dict(
            solver="CyRK DOP853",
            rtol=1e-10,
            wall_time=0.8,
            steps_per_period=150.0,
            impact_time_error_1p5s=6e-8,
            n_impacts=2882,
            on_attractor=True,
            status="ok",
        ),
        dict(solver="heyoka free flight", rtol=1e-10, wall_time=0.02, steps_per_period=15.5, status="ok"),
    ]
    lines = timing_rounds.format_table(rows).splitlines()
    assert lines[0].split()[:2] == ["solver", "rtol"]
    assert lines[1].split()[-2:] == ["2882", "yes"]
    assert lines[2].split()[-3:] == ["-", "-", "-"]


def test_missing_cyrk_is_reported(monkeypatch):
    monkeypatch.setitem(sys.modules, "CyRK", None)  # import CyRK now raises ImportError
    with pytest.raises(cyrk_shim.PeerUnavailable, match=r"CyRK is not installed.*\[peers\]"):
        cyrk_shim.load_cyrk_shim()


def test_a_shim_that_does_not_build_is_reported(monkeypatch, tmp_path):
    pytest.importorskip("CyRK")
    pytest.importorskip("Cython")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(cyrk_shim, "SHIM_SOURCE", "this is not Cython\n")
    with pytest.raises(cyrk_shim.PeerUnavailable, match="the CyRK shim could not be built"):
        cyrk_shim.load_cyrk_shim()


def test_cyrk_dop853_reproduces_the_reference_impact_times(cyrk):
    """DOP853 in one right-hand side, impacts located by CyRK's events on its dense output.

    Bound 1e-9 s: CyRK's root finder stops at 4 machine epsilons, so the error is the
    trajectory's; at rtol 1e-12 it was 2.9e-11 s (the reference, split at contacts at
    rtol 1e-13, is good to ~1e-12 s). 1e-9 leaves a factor 30 for other compilers and CPUs,
    and still fails an event put at a step end (steps here are ~1e-4 s), a wrong interpolant
    (~1e-7 s at this rtol) or a parameter passed wrongly.
    """
    ref = solve_reference(OMEGA, ERR_HORIZON, rtol=timing_rounds.REF_RTOL, atol=timing_rounds.REF_ATOL)["impacts_t"]
    run = cyrk.run_cyrk("DOP853", ERR_HORIZON, 1e-12, 1e-14)
    assert run.success, run.message
    assert len(run.impacts_t) == len(ref) == 10  # direction +1: onsets only, none missed
    assert np.abs(run.impacts_t - ref).max() < 1e-9
    assert run.steps > 0 and run.wall_time > 0


def test_a_run_that_stops_early_says_where(cyrk, monkeypatch):
    monkeypatch.setattr(cyrk_runs, "MAX_STEPS", 200)  # deterministic stand-in for a step-size underflow
    run = cyrk.run_cyrk("DOP853", ERR_HORIZON, 1e-10, 1e-12)
    assert not run.success and 0 < run.t_reached < ERR_HORIZON
    row = timing_rounds._row("CyRK DOP853", "scene", 1e-10, 1e-12, [run])
    assert row["status"].startswith(f"stopped at t = {run.t_reached:.6g} s: ")
    assert row["steps_per_period"] == pytest.approx(200 / (run.t_reached / timing_rounds.PERIOD), rel=0.01)


def test_heyoka_floor_integrates_the_model_without_contact(cyrk):
    """heyoka's hand-written expression is the model: its free flight ends where CyRK's
    DOP853 running model.accel (obstacle out of reach) ends. After 5 s of forcing and
    friction-band crossings both are good to ~1e-11 m at these tolerances; 1e-8 fails any
    wrong coefficient."""
    pytest.importorskip("heyoka")
    t_end = 5.0
    taylor = free_flight.run_heyoka(free_flight.heyoka_free_flight(tol=1e-13), t_end)
    dop = cyrk.run_cyrk("DOP853", t_end, 1e-12, 1e-14, params=free_flight.FREE_FLIGHT, impacts=False)
    assert taylor.success and dop.success, (taylor.message, dop.message)
    assert np.abs(taylor.state_end - dop.state_end).max() < 1e-8
    assert np.abs(dop.state_end).max() > 1e-4  # it did move


@pytest.mark.slow
def test_measure_builds_complete_rows(cyrk):
    rows = peers.measure_peers(
        ("DOP853",), (1e-9,), repeats=1, reference_impacts=2898, heyoka=False, log=lambda _: None
    )
    scene, floor = rows
    assert scene["kind"] == "scene" and floor["kind"] == "floor"
    assert scene["on_attractor"] and 2600 < scene["n_impacts"] < 3200
    assert scene["steps_per_period"] > floor["steps_per_period"] > 0
    assert peers.best_peer(rows, max_error=1e-3) is scene
