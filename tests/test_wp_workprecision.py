"""Work-precision measurement code: error metrics, SciPy contestants, timing,
speed ratio at equal error, statistics against an ensemble, tables and the figure."""

import math

import numpy as np
import pytest

from impactosc.io.files import read_table, write_table
from impactosc.model.parameters import ModelParams
from impactosc_bench import cyrk_shim, wp_attractor, wp_solvers
from impactosc_bench import event_errors as ee
from impactosc_bench import speed_at_error as sae
from impactosc_bench import tolerance_statistics as ts
from impactosc_bench import workprecision as wp
from impactosc_bench.scipy_reference import solve_reference


def quiet(*args):
    """Silence progress logs."""


def _events(impacts=(), pens=(), sections=(1.0, 2.0), x=(0.0, 0.0)):
    imp = np.asarray(impacts, float)
    return {
        "impacts_t": imp,
        "impacts_v": np.ones_like(imp),
        "penetrations_t": imp + 1e-3,
        "penetrations_h": np.asarray(pens, float),
        "poincare_t": np.asarray(sections, float),
        "poincare_x": np.asarray(x, float),
        "poincare_v": np.zeros(len(sections)),
    }


def test_errors_of_matching_runs_are_the_largest_differences():
    ref = _events([0.1, 0.5, 0.9], [1e-4, 2e-4, 3e-4], x=(1e-3, 2e-3))
    run = _events([0.1 + 1e-9, 0.5 - 3e-9, 0.9], [1e-4, 2e-4 + 5e-12, 3e-4], x=(1e-3 + 7e-13, 2e-3))
    e = ee.event_errors(run, ref)
    assert e["impact_time_error"] == pytest.approx(3e-9, rel=1e-6)
    assert e["penetration_error"] == pytest.approx(5e-12, rel=1e-3)
    assert e["poincare_x_error"] == pytest.approx(7e-13, rel=1e-3)
    assert e["n_impacts"] == e["n_impacts_ref"] == 3


def test_a_missed_impact_costs_its_distance_to_the_nearest_other():
    ref = _events([0.1, 0.5, 0.9], [1e-4, 2e-4, 3e-4])
    run = _events([0.1, 0.9], [1e-4, 3e-4])
    e = ee.event_errors(run, ref)
    assert e["impact_time_error"] == pytest.approx(0.4)  # 0.5 has nearest 0.1 or 0.9
    assert e["penetration_error"] == pytest.approx(3e-4)  # counts differ: the deepest unmatched
    invented = ee.event_errors(_events([0.1, 0.5, 0.52, 0.9], [1e-4] * 4), ref)
    assert invented["impact_time_error"] == pytest.approx(0.02)


def test_mismatched_sections_are_an_error():
    with pytest.raises(ValueError, match="Poincare sections differ"):
        ee.event_errors(_events(sections=(1.0,), x=(0.0,)), _events())


def test_best_time_takes_the_minimum_and_stops_for_slow_runs():
    calls = []

    def fn():
        calls.append(1)
        return len(calls)

    out, wmin, wmed, n = wp_solvers.best_time(fn, 5)
    assert n == 5 and out == 5 and wmin <= wmed
    calls.clear()
    _, _, _, n = wp_solvers.best_time(fn, 5, repeat_below=-1.0)  # every run counts as slow
    assert n == 1
    with pytest.raises(ValueError, match="repeats"):
        wp_solvers.best_time(fn, 0)


def test_case_validation():
    with pytest.raises(ValueError, match="horizon"):
        wp.Case("x", 40.86, 100.0, 0.0)
    with pytest.raises(ValueError, match="starts"):
        wp.Case("x", 40.86, 100.0, 1.0, n_starts=0)


def test_scipy_contestant_is_the_reference_algorithm_plus_sections():
    """Same method and tolerances as impactosc_bench.scipy_reference.solve_reference: the same impacts
    and penetrations to rounding (t_eval does not change SciPy's steps), plus Poincare points
    that agree with the core's at tight tolerance."""
    p = ModelParams()
    a = wp_solvers.run_scipy(40.86, 1.0, 0.0, 0.0, p, "DOP853", 1e-10, 1e-12)
    b = solve_reference(40.86, 1.0, params=p, method="DOP853", rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(a["impacts_t"], b["impacts_t"], rtol=0, atol=1e-14)
    np.testing.assert_allclose(a["penetrations_h"], b["penetrations_h"], rtol=0, atol=1e-17)
    core = wp_solvers.run_core_events(40.86, 1.0, 0.0, 0.0, p, 1e-12, 1e-14)
    np.testing.assert_array_equal(core["poincare_t"].size, a["poincare_t"].size)
    # SciPy at rtol 1e-10 against the core at 1e-12 over 1 s: ~1e-9 m (lead's measurements)
    np.testing.assert_allclose(a["poincare_x"], core["poincare_x"], rtol=0, atol=1e-8)
    with pytest.raises(ValueError, match="unknown SciPy method"):
        wp_solvers.run_scipy(40.86, 1.0, 0.0, 0.0, p, "BDF", 1e-6, 1e-8)


def _rows():
    rows = []
    for solver, walls, errs in (
        (wp_solvers.CORE, [0.001, 0.002, 0.004], [1e-5, 1e-8, 1e-11]),
        ("DOP853", [0.1, 0.3, 0.6], [1e-4, 1e-7, 1e-10]),
        ("LSODA", [0.05, 0.2, 0.9], [1e-3, 1e-8, 1e-9]),
    ):
        for rtol, w, e in zip((1e-4, 1e-8, 1e-12), walls, errs):
            rows.append(
                {
                    "scene": "chaotic",
                    "solver": solver,
                    "rtol": rtol,
                    "status": "ok",
                    "wall_time": w,
                    "impact_time_error": e,
                    "reference_impact_time_error": 1e-12,
                }
            )
    rows.append(
        {
            "scene": "chaotic",
            "solver": "RK45",
            "rtol": 1e-4,
            "status": "failed",
            "note": "x",
            "reference_impact_time_error": 1e-12,
        }
    )
    return rows


def test_cost_at_error_is_the_cheapest_run_at_least_that_accurate():
    rows = _rows()
    assert sae.cost_at_error(rows, "chaotic", "DOP853", "impact_time_error", 1e-6) == 0.3
    assert sae.cost_at_error(rows, "chaotic", "LSODA", "impact_time_error", 1e-8) == 0.2
    assert math.isnan(sae.cost_at_error(rows, "chaotic", "LSODA", "impact_time_error", 1e-10))
    assert math.isnan(sae.cost_at_error(rows, "chaotic", "RK45", "impact_time_error", 1.0))


def test_headline_ratio_against_the_fastest_scipy_solver():
    head = sae.speed_at_error_headline(_rows(), {"impact_time_error": [1e-6, 1e-9, 1e-12]})
    h = {r["error_level"]: r for r in head}
    assert h[1e-6]["best_scipy"] == "LSODA" and h[1e-6]["speedup"] == pytest.approx(0.2 / 0.002)
    assert h[1e-9]["best_scipy"] == "DOP853" and h[1e-9]["speedup"] == pytest.approx(0.6 / 0.004)
    assert h[1e-12]["best_scipy"] == "none" and math.isnan(h[1e-12]["speedup"])


def _stat_rows():
    rng = np.random.default_rng(1)
    rows = []
    for _k in range(8):
        rows.append(
            {
                "kind": "ensemble",
                "rtol": 1e-12,
                "n_impacts": 2890 + rng.normal(0, 10),
                "window_counts": list(578 + rng.normal(0, 5, 5)),
                "cv2_paper": 0.0303 + rng.normal(0, 3e-4),
                "cv2": 0.22 + rng.normal(0, 3e-3),
                "isi_first_maximum": 0.056 + rng.normal(0, 5e-4),
                "isi_last_maximum": 0.2 + rng.normal(0, 5e-4),
            }
        )
    good = dict(rows[0], kind="sweep", rtol=1e-6, rhs_evals=900_000)
    bad = dict(rows[0], kind="sweep", rtol=1e-2, rhs_evals=300_000, n_impacts=3100.0)
    return [*rows, good, bad]


def test_statistics_summary_flags_unconverged_tolerances():
    out = {r["rtol"]: r for r in ts.statistics_summary(_stat_rows())}
    assert out[1e-6]["converged"] is True
    assert out[1e-2]["converged"] is False and out[1e-2]["z_n_impacts"] > 3
    with pytest.raises(ValueError, match=">= 3 runs"):
        ts.statistics_summary([r for r in _stat_rows() if r["kind"] == "sweep"])


def test_one_chance_z_among_many_is_not_non_convergence():
    """A |z| of 3.02 among the sweep's tests is chance (Holm allows for their number); a |z| of 20 is not."""
    rows = _stat_rows()
    ens = [r for r in rows if r["kind"] == "ensemble"]
    cv = np.array([r["cv2"] for r in ens])
    # ten more sweep rows at the ensemble's means, then one whose C_V^2 lies 3.02 sd off
    base = dict(ens[0], kind="sweep", rhs_evals=1, **{k: float(np.mean([r[k] for r in ens])) for k in ts.STAT_KEYS})
    base["window_counts"] = [float(np.mean([r["window_counts"] for r in ens]))] * 5
    clean = [dict(base, rtol=10.0**-k) for k in range(3, 13)]
    chance = dict(base, rtol=1e-8 * 1.5, cv2=float(cv.mean() + 3.02 * cv.std(ddof=1)))
    out = {r["rtol"]: r for r in ts.statistics_summary([*rows, *clean, chance])}
    assert out[chance["rtol"]]["z_cv2"] == pytest.approx(3.02)
    assert out[chance["rtol"]]["converged"] is True  # 3.02 is not beyond Holm's 0.0027 / 130 (|z| > 4.1)
    # Holm: the rejected rtol 1e-2 comes first, then 3.02 is second of the 130 tests: 129 x p(3.02) = 0.33
    assert out[chance["rtol"]]["holm_p"] == pytest.approx(129 * math.erfc(3.02 / math.sqrt(2)), rel=1e-9)
    assert out[1e-2]["converged"] is False and out[1e-2]["n_tests"] == 13 * 10
    assert all(out[r["rtol"]]["converged"] for r in clean)


def test_tables_roundtrip_mixed_columns(tmp_path):
    rows = [{"a": 1.0, "b": "x", "c": [1, 2]}, {"a": 2.5e-13, "d": True}]
    path = write_table(tmp_path / "t.csv", rows)
    back = read_table(path)
    assert back[0]["a"] == 1.0 and back[0]["b"] == "x" and back[0]["c"] == "1 2"
    assert back[1]["a"] == 2.5e-13 and back[1]["d"] == "yes" and math.isnan(back[1]["b"])
    with pytest.raises(ValueError, match="no rows"):
        write_table(tmp_path / "e.csv", [])
    with pytest.raises(FileNotFoundError):
        read_table(tmp_path / "missing.csv")


def test_sweep_smoke_core_fastest_and_accurate():
    """A small real sweep (1 start, 1 s): every row measured, the core's error falls with
    tolerance, and at rtol 1e-10 it is at least 10x faster than SciPy LSODA (measured
    ~100x on this machine; the margin absorbs load from parallel jobs)."""
    case = wp.Case("chaotic", 40.86, 100.0, 1.0)
    ref = {
        "method": "DOP853",
        "rtol": 1e-13,
        "atol": 1e-15,
        "check_method": "LSODA",
        "check_rtol": 1e-12,
        "check_atol": 1e-15,
    }
    rows = wp.sweep_case(
        case,
        ModelParams(),
        [1e-6, 1e-10],
        1e-2,
        [wp_solvers.CORE, "LSODA"],
        ref,
        core_repeats=3,
        scipy_repeats=1,
        log=quiet,
    )
    assert all(r["status"] == "ok" for r in rows)
    core = {r["rtol"]: r for r in rows if r["solver"] == wp_solvers.CORE}
    lsoda = {r["rtol"]: r for r in rows if r["solver"] == "LSODA"}
    assert core[1e-10]["impact_time_error"] < core[1e-6]["impact_time_error"]
    assert core[1e-10]["impact_time_error"] < 1e-8
    assert lsoda[1e-10]["wall_time"] > 10 * core[1e-10]["wall_time"]


def test_a_contestant_that_raises_is_a_failed_row(monkeypatch):
    """SciPy's event location can raise ValueError (brentq: "f(a) and f(b) must have different
    signs"; LSODA at rtol 1e-13 on the periodic scene did): that point is a failed row with the
    message, and the sweep goes on."""
    case = wp.Case("chaotic", 40.86, 100.0, 0.3)
    ref = {
        "method": "DOP853",
        "rtol": 1e-12,
        "atol": 1e-14,
        "check_method": "LSODA",
        "check_rtol": 1e-11,
        "check_atol": 1e-14,
    }
    real = wp_solvers.run_solver

    def run_solver(solver, *args):
        if solver == "LSODA":
            raise ValueError("f(a) and f(b) must have different signs")
        return real(solver, *args)

    monkeypatch.setattr(wp, "run_solver", run_solver)  # the name the sweep calls
    rows = wp.sweep_case(
        case, ModelParams(), [1e-8], 1e-2, [wp_solvers.CORE, "LSODA"], ref, core_repeats=1, scipy_repeats=1, log=quiet
    )
    status = {r["solver"]: (r["status"], r.get("note", "")) for r in rows}
    assert status[wp_solvers.CORE][0] == "ok"
    assert status["LSODA"] == ("failed", "ValueError: f(a) and f(b) must have different signs")


def _with_every_metric(rows):
    """Rows as the figure reads them: the horizon and every error metric (penetration and
    Poincare errors scaled from the impact-time error), with their reference uncertainties."""
    return [
        dict(
            r,
            horizon=1.5,
            reference_penetration_error=1e-15,
            reference_poincare_x_error=1e-13,
            penetration_error=r.get("impact_time_error", math.nan) * 1e-3,
            poincare_x_error=r.get("impact_time_error", math.nan) * 1e-2,
        )
        for r in rows
    ]


def test_figure_from_synthetic_rows(tmp_path):
    from impactosc_bench.work_precision_figure import plot_work_precision
    from impactosc_study.figures import save_figure

    rows = _with_every_metric(_rows())
    stats = _stat_rows()
    fig = plot_work_precision(rows, stats, jit={"cold": 27.0, "cached": 0.8})
    save_figure(fig, tmp_path / "wp.png", tmp_path / "wp.pdf")
    assert (tmp_path / "wp.png").stat().st_size > 10_000 and (tmp_path / "wp.pdf").stat().st_size > 5_000


# ------------------------------------------------------------------ the compiled peers


def _peer_rows():
    rows = _rows()
    for rtol, w, e, on in ((1e-4, 0.0008, 1e-5, "yes"), (1e-8, 0.0015, 1e-8, "yes"), (1e-12, 0.0019, 1e-11, "no")):
        rows.append(
            {
                "scene": "chaotic",
                "solver": "CyRK DOP853",
                "rtol": rtol,
                "status": "ok",
                "wall_time": w,
                "impact_time_error": e,
                "reference_impact_time_error": 1e-12,
                "on_attractor": on,
            }
        )
    rows.append(
        {
            "scene": "chaotic",
            "solver": "CyRK Vern8",
            "rtol": 1e-13,
            "status": "stopped",
            "wall_time": 0.003,
            "impact_time_error": math.inf,
            "reference_impact_time_error": 1e-12,
            "note": "start 1: stopped",
        }
    )
    rows.append(
        {
            "scene": "chaotic",
            "solver": "heyoka Taylor (order 13) free flight",
            "rtol": 1e-10,
            "status": "floor",
            "wall_time": 1e-4,
            "reference_impact_time_error": 1e-12,
        }
    )
    return rows


def test_headline_names_the_fastest_compiled_peer_apart_from_scipy():
    head = {
        r["error_level"]: r
        for r in sae.speed_at_error_headline(_peer_rows(), {"impact_time_error": [1e-6, 1e-9, 1e-11]})
    }
    # SciPy's columns are as without peers
    assert head[1e-6]["best_scipy"] == "LSODA" and head[1e-6]["speedup"] == pytest.approx(0.2 / 0.002)
    assert head[1e-6]["best_peer"] == "CyRK DOP853" and head[1e-6]["peer_over_core"] == pytest.approx(0.0015 / 0.002)
    # the rtol 1e-12 run is accurate over 1.5 s but leaves the attractor in 500 s: it does not count
    assert head[1e-11]["best_peer"] == "none" and math.isnan(head[1e-11]["peer_over_core"])
    assert "best_peer" not in sae.speed_at_error_headline(_rows(), {"impact_time_error": [1e-6]})[0]


def test_attractor_columns_flag_a_run_that_stops_or_leaves():
    on = wp_attractor.attractor_columns({"n_impacts_500s": 2890, "t_reached_500s": 500.0, "stop": ""}, 2898)
    assert on["on_attractor"] is True and "attractor_note" not in on
    off = wp_attractor.attractor_columns({"n_impacts_500s": 520, "t_reached_500s": 500.0, "stop": ""}, 2898)
    assert off["on_attractor"] is False and "left the attractor" in off["attractor_note"]
    stop = wp_attractor.attractor_columns({"n_impacts_500s": 1177, "t_reached_500s": 263.8, "stop": "step size"}, 2898)
    assert stop["on_attractor"] is False and stop["attractor_note"].startswith("500 s run stopped at t = 263.8 s")


def test_a_peer_that_is_not_installed_is_a_row_and_a_note(monkeypatch):
    import sys

    from impactosc_bench.work_precision_figure import unavailable_notes

    monkeypatch.setitem(sys.modules, "CyRK", None)  # import CyRK now raises ImportError
    monkeypatch.setitem(sys.modules, "heyoka", None)
    status = wp_solvers.peer_status([wp_solvers.CORE, "DOP853", "CyRK DOP853", "CyRK Vern8"], heyoka=True)
    assert set(status) == {"CyRK DOP853", "CyRK Vern8", "heyoka"}
    assert all("not installed" in why for why in status.values())
    rows = [{"scene": "chaotic", "solver": s, "status": "unavailable", "note": why} for s, why in status.items()]
    assert unavailable_notes(rows, "chaotic") == ["CyRK not installed", "heyoka not installed"]
    assert unavailable_notes(rows, "periodic") == []


def test_figure_draws_peers_floors_and_failures(tmp_path):
    from impactosc_bench.work_precision_figure import plot_work_precision
    from impactosc_study.figures import save_figure

    rows = _with_every_metric(_peer_rows())
    rows.append(dict(rows[0], solver="CyRK Vern7", status="unavailable", note="CyRK is not installed"))
    fig = plot_work_precision(rows, _stat_rows(), jit={"cold": 27.0, "cached": 0.8})
    labels = fig.subfigs[0].legends[0].get_texts()
    assert {"CyRK DOP853", "open: off the attractor or stopped (labelled)"} <= {t.get_text() for t in labels}
    assert any(t.get_text().startswith("floor: heyoka") for t in labels)
    save_figure(fig, tmp_path / "wp.png", tmp_path / "wp.pdf")
    assert (tmp_path / "wp.png").stat().st_size > 10_000


def test_peer_contestant_gives_the_events_of_the_others(cyrk):
    """CyRK DOP853 at rtol 1e-12 in one right-hand side finds the reference's impacts,
    penetrations and Poincare points over 1.5 s from rest (measured: 2.9e-11 s, 7e-14 m,
    1.5e-12 m; the bounds leave a factor ~30 for other compilers and CPUs)."""
    p = ModelParams()
    ref = wp_solvers.run_scipy(40.86, 1.5, 0.0, 0.0, p, "DOP853", 1e-13, 1e-15)
    run = wp_solvers.run_solver("CyRK DOP853", 40.86, 1.5, 0.0, 0.0, p, 1e-12, 1e-14)
    assert run["success"] and run["t_reached"] == 1.5
    e = ee.event_errors(run, ref)
    assert e["n_impacts"] == e["n_impacts_ref"] == 10
    assert run["penetrations_h"].size == ref["penetrations_h"].size
    assert e["impact_time_error"] < 1e-9 and e["penetration_error"] < 3e-12 and e["poincare_x_error"] < 5e-11


def test_sweep_with_a_peer_and_a_missing_one(cyrk, monkeypatch):
    """A short sweep: the peer's row is complete, a method CyRK does not have is a row that says so."""
    real = cyrk_shim.cyrk_method

    def method(name):
        if name == "Nope":
            raise cyrk_shim.PeerUnavailable("no " + name)
        return real(name)

    monkeypatch.setattr(cyrk_shim, "cyrk_method", method)
    case = wp.Case("chaotic", 40.86, 100.0, 0.5)
    ref = {
        "method": "DOP853",
        "rtol": 1e-13,
        "atol": 1e-15,
        "check_method": "LSODA",
        "check_rtol": 1e-12,
        "check_atol": 1e-15,
    }
    rows = wp.sweep_case(
        case,
        ModelParams(),
        [1e-9],
        1e-2,
        [wp_solvers.CORE, "CyRK DOP853", "CyRK Nope"],
        ref,
        core_repeats=1,
        peer_repeats=1,
        log=quiet,
    )
    by = {r["solver"]: r for r in rows}
    assert by["CyRK Nope"]["status"] == "unavailable" and by["CyRK Nope"]["note"] == "no Nope"
    peer = by["CyRK DOP853"]
    assert peer["status"] == "ok" and peer["impact_time_error"] < 1e-6 and math.isnan(peer["rhs_evals"])


def test_time_budget_gives_a_lower_bound_where_scipy_stopped():
    """Where the budget stopped every SciPy sweep short of an error level, the headline has no
    ratio but a lower bound: a stopped solver needs at least its last point's time."""
    rows = [r for r in _rows() if not (r["solver"] in ("DOP853", "LSODA") and r["rtol"] == 1e-12)]
    for solver in ("DOP853", "LSODA"):
        rows.append(
            {
                "scene": "chaotic",
                "solver": solver,
                "rtol": 1e-12,
                "status": "skipped",
                "note": "time budget: rtol 1e-08 already took > 0.1 s per point",
                "reference_impact_time_error": 1e-12,
            }
        )
    h = {r["error_level"]: r for r in sae.speed_at_error_headline(rows, {"impact_time_error": [1e-6, 1e-9]})}
    assert h[1e-6]["speedup"] == pytest.approx(0.2 / 0.002) and math.isnan(h[1e-6]["speedup_at_least"])
    assert h[1e-9]["best_scipy"] == "none" and math.isnan(h[1e-9]["speedup"])
    assert h[1e-9]["speedup_at_least"] == pytest.approx(0.2 / 0.004)  # LSODA's last point, 0.2 s
    # without a stopped sweep there is no bound: the full sweeps never reached 1e-12
    full = sae.speed_at_error_headline(_rows(), {"impact_time_error": [1e-12]})[0]
    assert math.isnan(full["speedup_at_least"])


def test_budget_skips_tighter_tolerances_and_says_so(monkeypatch):
    """A SciPy point over the budget stops that solver's sweep: later rtols are skipped rows
    that name the budget (the figure prints them); the core is never stopped."""
    case = wp.Case("chaotic", 40.86, 100.0, 0.3)
    ref = {
        "method": "DOP853",
        "rtol": 1e-12,
        "atol": 1e-14,
        "check_method": "LSODA",
        "check_rtol": 1e-11,
        "check_atol": 1e-14,
    }
    rows = wp.sweep_case(
        case,
        ModelParams(),
        [1e-6, 1e-8, 1e-10],
        1e-2,
        [wp_solvers.CORE, "LSODA"],
        ref,
        core_repeats=1,
        scipy_repeats=1,
        time_cap=1e-9,
        log=quiet,
    )
    status = {(r["solver"], r["rtol"]): r for r in rows}
    assert all(status[(wp_solvers.CORE, rt)]["status"] == "ok" for rt in (1e-6, 1e-8, 1e-10))
    assert status[("LSODA", 1e-6)]["status"] == "ok"
    for rt in (1e-8, 1e-10):
        assert status[("LSODA", rt)]["status"] == "skipped"
        assert status[("LSODA", rt)]["note"].startswith("time budget: rtol 1e-06 already took")
    from impactosc_bench.work_precision_figure import budget_notes

    assert budget_notes(rows, "chaotic") == [f"SciPy LSODA: {status[('LSODA', 1e-8)]['note']}"]


def test_known_long_runs_reuse_the_benchmark_table():
    bench = [
        {
            "solver": wp_solvers.CORE,
            "kind": "scene",
            "rtol": 1e-10,
            "n_impacts": 2888.0,
            "t_reached": 500.0,
            "status": "ok",
        },
        {
            "solver": "CyRK DOP853",
            "kind": "scene",
            "rtol": 1e-12,
            "n_impacts": 1177.0,
            "t_reached": 263.8,
            "status": "stopped at t = 263.8 s: Error in step size calculation",
        },
        {"solver": "CyRK DOP853 free flight", "kind": "floor", "rtol": 1e-10, "status": "ok"},
        {"solver": "SciPy", "kind": "scene", "rtol": 1e-8, "n_impacts": 2896.0, "t_reached": 500.0, "status": "ok"},
    ]
    known = wp_attractor.known_long_runs(bench)
    assert known[(wp_solvers.CORE, 1e-10)] == {"n_impacts_500s": 2888.0, "t_reached_500s": 500.0, "stop": ""}
    assert known[("CyRK DOP853", 1e-12)]["stop"] == "Error in step size calculation"
    assert ("CyRK DOP853 free flight", 1e-10) not in known
    cols = wp_attractor.attractor_columns(known[("CyRK DOP853", 1e-12)], 2888)
    assert cols["on_attractor"] is False and "stopped" in cols["attractor_note"]


def test_references_made_apart_give_the_same_sweep(tmp_path):
    """wp_reference computes the references once, beside other jobs, and wp_measure reads them
    back from JSON: the errors of every row are those of a sweep that made its own."""
    from impactosc.io.files import read_json, write_json

    case = wp.Case("chaotic", 40.86, 100.0, 0.3)
    ref = {
        "method": "DOP853",
        "rtol": 1e-12,
        "atol": 1e-14,
        "check_method": "LSODA",
        "check_rtol": 1e-11,
        "check_atol": 1e-14,
    }
    write_json(tmp_path / "ref.json", wp.reference_set(case, ModelParams(), ref))
    apart = wp.sweep_case(
        case,
        ModelParams(),
        [1e-8],
        1e-2,
        [wp_solvers.CORE],
        ref,
        core_repeats=1,
        log=quiet,
        reference=read_json(tmp_path / "ref.json"),
    )
    inside = wp.sweep_case(case, ModelParams(), [1e-8], 1e-2, [wp_solvers.CORE], ref, core_repeats=1, log=quiet)
    for key in ("impact_time_error", "penetration_error", "poincare_x_error", "reference_impact_time_error"):
        assert apart[0][key] == inside[0][key]
