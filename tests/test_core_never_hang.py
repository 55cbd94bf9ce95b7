"""The core never hangs: the stiff creep that stalled it, the watchdog, and
randomized differential testing against an independent SciPy reference.

The stall: inside the contact the Hunt-Crossley damping ~ |v|^n3 with n3 << 1 balances the
other forces at a creep velocity of 1e-11 .. 1e-18 m/s, where -da/dv ~ |v|^(n3 - 1) is huge;
explicit steps were pinned by stability (1e-9 s and shrinking), and v = 0 crossings made of
round-off were recorded as penetrations. The creep now goes to the implicit solver.
"""

import math

import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.core.simulation import StallError, simulate
from impactosc.dynamics.sweep import STALLED, SweepSettings, continuation
from impactosc.model.parameters import ModelParams, UntestedParameterWarning
from impactosc_bench.random_scenes import (
    agreement_horizon,
    compare_scene,
    draw_scene,
    impacts_agree,
    run_scenes,
    summarise_scenes,
)
from impactosc_bench.scipy_reference import solve_reference

# A parameter set found by a random draw, on which the core once stalled in a stiff creep, and its initial state.
CREEP_SCENE = dict(
    m=9.47198865593737,
    m0e=0.02989581054918677,
    k=2183.3658042200877,
    c=8.01647194477097,
    T=0.0,
    eps=1.247542664427076e-06,
    kI=94356327.33635227,
    b=1.0982245961648749,
    n1=1.5,
    n2=1.5,
    n3=0.12296037781037601,
    xI=-0.0032254345695398715,
)
CREEP_W, CREEP_X0, CREEP_V0 = 49.9632209280299, -0.003609070093814087, 0.05478655884924266


def _creep_scene(duration, **kw):
    return simulate(
        CREEP_W,
        0.0,
        duration,
        x0=CREEP_X0,
        v0=CREEP_V0,
        params=ModelParams(**CREEP_SCENE),
        rtol=1e-11,
        atol=1e-13,
        **kw,
    )


def test_creep_scene_scene_ends_in_bounded_work():
    # Before the fix: no end (4e5 steps reached t = 0.0318 s). After: 5294 attempts for 3 s.
    # Bound 10x that: generous for platform differences, four orders below a stall.
    res = _creep_scene(3.0)
    assert res.attrs["n_attempts"] < 60_000
    assert res.attrs["n_stiff"] >= 1  # the creep went to the implicit solver
    assert res.events["impacts"]["t"].size > 0


def test_creep_scene_scene_agrees_with_an_independent_reference():
    # LSODA (ODEPACK, stiffness switching) split at contact onset and exit, at two tolerances;
    # the core must match the tighter one wherever the two agree with each other. 0.5 s holds
    # the creep (0.02-0.03 s) and four impacts; past 0.53 s every SciPy method we tried gives
    # up on this scene (LSODA: convergence failures, Radau: step size underflow, DOP853:
    # pinned by the creep at 0.027 s), so the core, which does not, is compared up to there.
    horizon = 0.5
    res = _creep_scene(horizon, record=("impacts", "penetrations"))
    refs = [
        solve_reference(
            CREEP_W,
            horizon,
            x0=CREEP_X0,
            v0=CREEP_V0,
            params=ModelParams(**CREEP_SCENE),
            method="LSODA",
            rtol=rtol,
            atol=atol,
        )
        for rtol, atol in ((1e-11, 1e-14), (1e-12, 1e-15))
    ]
    h = agreement_horizon(refs[0]["impacts_t"], refs[1]["impacts_t"], horizon) - 1e-3
    tc = res.events["impacts"]["t"]
    tr = refs[1]["impacts_t"]
    tc, tr = tc[tc < h], tr[tr < h]
    assert h > 0.4 and tr.size >= 3
    assert tc.size == tr.size  # no impact missed or invented
    # 1e-8 s: the randomized tests' bound; the two references differ by ~1e-11 s here
    assert np.max(np.abs(tc - tr)) < 1e-8
    # no penetrations invented by round-off reversals (before the fix: one every 5 steps)
    pc = res.events["penetrations"]["t"]
    pr = refs[1]["penetrations_t"]
    assert pc[pc < h].size == pr[pr < h].size


def test_watchdog_names_where_it_stuck():
    # The chaotic scene takes ~130 step attempts per forcing period: with a budget of 100
    # the watchdog must stop it and say where.
    with pytest.raises(StallError) as info:
        simulate(40.86, 0.0, 5.0, step_budget=100)
    msg = str(info.value)
    for word in ("stalled", "t = ", "x = ", "v = ", "step", "attempts"):
        assert word in msg
    st = info.value.state
    assert st["status"] == "stalled" and 0.0 <= st["t"] < 5.0 and st["attempts"] >= 100
    assert st["piece"].split(",")[0] in ("free flight", "contact", "contact past the Hunt-Crossley cut")


def test_step_budget_is_validated():
    with pytest.raises(ValueError, match="step_budget"):
        simulate(40.86, 0.0, 1.0, step_budget=10)


def test_cli_reports_a_stall_in_one_line_and_writes_nothing(tmp_path, capsys):
    out = tmp_path / "run.h5"
    code = main(
        [
            "simulate",
            "--omega",
            "40.86",
            "--transient",
            "0",
            "--duration",
            "5",
            "--step-budget",
            "100",
            "--output",
            str(out),
            "--quiet",
        ]
    )
    err = capsys.readouterr().err.strip()
    assert code == 3
    assert not out.exists()
    assert len(err.splitlines()) == 1 and "stalled" in err and "nothing written" in err


def test_sweep_marks_a_core_stall_and_goes_on(monkeypatch):
    # The sweeps hand their pace limit to the core's watchdog: with a pace of one budget
    # per period (100 attempts) every w of the chaotic range stalls, is marked, and the
    # sweep returns instead of hanging.
    import impactosc.dynamics.sweep as cont

    monkeypatch.setattr(cont, "_STALL_PACE", 1)
    settings = SweepSettings(n_transient=5, n_record=5, n_initial=5, max_steps_per_period=100)
    failures = []
    res = continuation([40.86, 40.80], settings, on_failure=lambda i, w, msg: failures.append(msg))
    assert list(res.status) == [STALLED, STALLED]
    assert all("stalled" in m for m in failures)


def test_untested_parameters_are_warned_about():
    with pytest.warns(UntestedParameterWarning, match="n3 = 1.5 is outside the tested range"):
        ModelParams(n3=1.5)
    with pytest.raises(ValueError, match="kI must be > 0"):
        ModelParams(kI=-1.0)


def test_draws_are_reproducible_and_inside_the_box():
    a, b = draw_scene(7, 3), draw_scene(7, 3)
    assert a == b
    s = draw_scene(7, 4)
    assert 10 <= s.omega <= 60 and 0 <= s.params.T <= s.params.m0e * s.omega**2
    assert 1e-7 <= s.params.eps <= 1e-5 and 1e7 <= s.params.kI <= 1e10


def test_agreement_horizon():
    t = np.array([0.1, 0.2, 0.3])
    assert agreement_horizon(t, t, 1.0) == 1.0
    assert agreement_horizon(t, t + np.array([0, 0, 1e-3]), 1.0) == pytest.approx(0.3)
    assert agreement_horizon(t, t[:2], 1.0) == pytest.approx(0.3)


# A fixed-seed sample of the random box (seed 2026, scenes 0-7, 1 s each). The large run
# (hundreds of scenes) is the workflow target random_scenes and the slow test below.
def test_random_scenes_match_scipy():
    rows = run_scenes(2026, 8, horizon=1.0, log=lambda *a: None)
    s = summarise_scenes(rows)
    assert s["stalls"] == 0, [r["message"] for r in rows if r["status"] == "stall"]
    assert s["failures"] == 0, [
        (r["scene"], r["status"], r["message"]) for r in rows if r["status"] not in ("ok", "no reference")
    ]
    assert s["impacts_compared"] >= 10  # the sample exercises contacts, not only free flight
    assert s["worst_dt_s"] < 1e-8


@pytest.mark.slow
def test_random_scenes_large():
    rows = run_scenes(2026, 200, horizon=1.5, log=lambda *a: None)
    s = summarise_scenes(rows)
    assert s["stalls"] == 0 and s["failures"] == 0  # each impact within 1e-8 s, or 1e-9 m for slow ones
    assert s["worst_dt_s"] < 1e-7  # measured 5.3e-9 s (2.4e-8 s before the step controller was reworked)
    assert s["no_reference"] <= 0.1 * s["scenes"]  # measured 11 of 200


def test_a_slow_impact_is_judged_by_its_position_error():
    # Scene 112 of seed 2026 once had its last impact (v = 7 mm/s) 2.4e-8 s off at rtol 1e-11:
    # 1.7e-10 m in position, which the position bound accepts; the same time error on a
    # 0.1 m/s impact (2.4e-9 m) it does not.
    assert impacts_agree([2.4e-8, 2.4e-8, 5e-9], [0.007, 0.1, 1.0]).tolist() == [True, False, True]
    # the scene itself (1.3e-9 s since the core's step controller was reworked)
    row = compare_scene(draw_scene(2026, 112), horizon=1.5)
    assert row["status"] == "ok" and row["worst_dx"] < 1e-9


def test_compare_scene_reports_a_row_for_a_plain_scene():
    row = compare_scene(draw_scene(2026, 0), horizon=0.5)
    assert row["status"] in ("ok", "no reference")
    assert math.isfinite(row["core_time"])
