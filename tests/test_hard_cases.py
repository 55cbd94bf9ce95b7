"""Hard cases for the core, at reduced size; rule hard_cases runs them in full.

Each case function of impactosc_bench.hardcases measures a figure against an
independent reference and states its bound (the reasons are in the function docstrings);
these tests assert every such check. Row bounds are not re-derived here: a test fails when
the core stops meeting a bound, and prints the offending rows.
"""

import dataclasses
import math

import numpy as np
import pytest

from impactosc.model.parameters import ModelParams
from impactosc_bench import hardcases as hc


def quiet(*args):
    """Silence the cases' progress log."""


def assert_passed(rows):
    failed = [r for r in rows if r["passed"] is False]
    assert not failed, "\n".join(
        f"{r['check']}: {r['measured']:.4g} > {r['bound']} {r['unit']} ({r['detail']})" for r in failed
    )
    assert any(r["passed"] is True for r in rows)


def test_grazing_contacts_and_near_misses_of_1e_9_m():
    rows = hc.grazing_case(depths=(1e-8, 1e-9), gaps=(1e-6, 1e-9), fine_points=3, fine_halfwidth=2e-6, log=quiet)
    assert_passed(rows)
    by = {r["check"].split(" (")[0]: r for r in rows}
    assert by["shallowest contact detected"]["measured"] <= 1.5e-9
    assert by["smallest near-miss gap resolved"]["measured"] <= 1.5e-9


def test_chattering_sequences_match_scipy():
    p = ModelParams()
    assert_passed(hc.chattering_case(p, 40.86, 1.1, "chaos", log=quiet))
    bounce = dataclasses.replace(p, b=0.1)
    rows = hc.chattering_case(bounce, 8.0, 5.1, "bounce", min_len=10, log=quiet)
    assert_passed(rows)
    assert rows[1]["measured"] >= 25  # the bouncing sequence is long: 29 impacts down to ~1.6e-3 m/s
    assert_passed(hc.bounce_to_rest_case(bounce, 8.0, 20.0, log=quiet))


def test_sticking_converges_to_coulomb_without_step_collapse():
    rows = hc.stick_slip_case(ratios=(0.6, 0.95), eps_values=(1e-6, 1e-7, 1e-9), periods=6, log=quiet)
    assert_passed(rows)


def test_sticking_on_the_obstacle_is_fast_and_physical():
    assert_passed(hc.stick_on_obstacle_case(t_end=12.0, log=quiet))


def test_impact_on_a_poincare_time_and_events_at_the_end():
    assert_passed(hc.coincidence_case(log=quiet))


def test_long_run_rate_and_memory_short():
    # The speed ratio is reported here, not bounded: a speed bound belongs to the benchmarks
    # (rule hard_cases and the slow test below), not to a test that shares its cores.
    rows = hc.long_run_case(duration=1000.0, block=100.0, chunk_steps=50_000, speed_bound=None, log=quiet)
    assert_passed(rows)
    assert [r["passed"] for r in rows] == [True, True, "n.a."]


@pytest.mark.slow
def test_long_run_1e4_s():
    assert_passed(hc.long_run_case(duration=1e4, block=1000.0, log=quiet))


def test_regularisation_eps_and_stiffer_contact():
    rows = hc.regularisation_case(
        eps_values=(1e-9,),
        ensemble_x0=(1e-4, -1e-4, 2e-4, -2e-4, 5e-4, -5e-4, 1e-3, -1e-3),  # the configured 8: bound 7.1
        approach_speeds=(0.1, 1.5),
        log=quiet,
    )
    assert_passed(rows)
    info = [r for r in rows if r["passed"] == "n.a."]
    assert len(info) == 1 and "kI" in info[0]["check"]


@pytest.mark.slow
def test_all_cases_full_size():
    from impactosc_study.config import load_config

    cfg = load_config("config/config.yaml", "workflow/schemas/config.schema.yaml")
    assert_passed(hc.run_all(cfg["hard_cases"], log=quiet))


# ----------------------------------------------------------- the Coulomb reference itself


def test_coulomb_reference_without_friction_is_the_linear_oscillator():
    """T = 0: one slip piece per half swing; the closed form must match SciPy to 1e-10 m."""
    from scipy.integrate import solve_ivp

    p = dataclasses.replace(ModelParams(), T=0.0, xI=1.0)
    w = 23.03
    ref = hc.CoulombOscillator(p, w).solve(1.0, x0=1e-3, v0=0.0)
    sol = solve_ivp(
        lambda t, y: [y[1], (p.m0e * w * w * math.sin(w * t) - p.k * y[0] - p.c * y[1]) / p.m],
        (0, 1.0),
        [1e-3, 0.0],
        rtol=1e-12,
        atol=1e-15,
        dense_output=True,
        method="DOP853",
    )
    ts = np.linspace(0, 1.0, 501)
    x, v = ref.state(ts)
    np.testing.assert_allclose(x, sol.sol(ts)[0], atol=1e-10, rtol=0)
    np.testing.assert_allclose(v, sol.sol(ts)[1], atol=1e-9, rtol=0)
    assert ref.n_sticks == 0


def test_coulomb_reference_sticks_forever_when_friction_exceeds_every_force():
    p = dataclasses.replace(ModelParams(), T=50.0, xI=1.0)  # forcing amplitude at w = 23: 9.6 N
    ref = hc.CoulombOscillator(p, 23.03).solve(2.0, x0=1e-3)
    assert ref.n_sticks == 1 and ref.stick_time == pytest.approx(2.0)
    x, v = ref.state([0.5, 1.5])
    assert np.all(x == 1e-3) and np.all(v == 0)


def test_coulomb_reference_breakaway_is_where_the_net_force_reaches_T():
    p = dataclasses.replace(ModelParams(), T=5.0, xI=1.0)
    w = 23.03
    ref = hc.CoulombOscillator(p, w).solve(0.3)
    t0, t1, kind, _ = ref.pieces[0]
    assert kind == "stick" and t0 == 0.0
    assert abs(p.m0e * w * w * math.sin(w * t1)) == pytest.approx(p.T, rel=1e-12)


@pytest.mark.filterwarnings("ignore::impactosc.model.parameters.UntestedParameterWarning")  # c = 500 on purpose
def test_coulomb_reference_rejects_overdamped():
    with pytest.raises(ValueError, match="underdamped"):
        hc.CoulombOscillator(dataclasses.replace(ModelParams(), c=500.0), 23.03)


def test_row_defaults_and_info():
    assert hc.row("c", "x", 1.0, 2.0, "s")["passed"] is True
    assert hc.row("c", "x", 3.0, 2.0, "s")["passed"] is False
    r = hc.row("c", "x", 3.0, "n.a.", "s", info=True)
    assert r["passed"] == "n.a." and r["bound"] == "n.a."


def test_shrinking_runs():
    v = np.array([1.0, 0.5, 0.2, 0.3, 0.1, 0.05, 0.01, 0.02])
    assert hc._shrinking_runs(np.arange(v.size), v, 3) == [(0, 3), (3, 7)]
