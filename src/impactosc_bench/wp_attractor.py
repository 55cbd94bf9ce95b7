"""The 500 s attractor check of the work-precision sweep: does a contestant's run from rest at
the scene's w stay on the chaotic attractor, or stop early?

Why a module: an error over 1.5 s says nothing of a run that, later, leaves the attractor or
stops at a step-size underflow; the core and the compiled peers therefore also run the
benchmark scene's length (100 s + 400 s) untimed, and their rows say whether they stayed
(:func:`attractor_columns`). Runs the core-speed benchmark already made are reused
(:func:`known_long_runs`).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.core.simulation import StallError, simulate
from impactosc_bench import cyrk_runs
from impactosc_bench.scene import DURATION, TRANSIENT
from impactosc_bench.timing_rounds import on_attractor
from impactosc_bench.wp_solvers import CORE, PEER_PREFIX

__all__ = ["long_run", "known_long_runs", "attractor_columns"]


def long_run(solver, omega, params, rtol, atol) -> dict:
    """Impacts in 100-500 s of a run from rest (the benchmark scene's length) by the core or a
    peer, untimed: n_impacts_500s, t_reached_500s and why it stopped (empty if it did not)."""
    t_end = TRANSIENT + DURATION
    if solver == CORE:
        try:
            res = simulate(omega, TRANSIENT, DURATION, params=params, rtol=rtol, atol=atol, record=("impacts",))
        except StallError as e:
            return {"n_impacts_500s": math.nan, "t_reached_500s": float(e.state.get("t", math.nan)), "stop": str(e)}
        return {"n_impacts_500s": len(res.events["impacts"]["t"]), "t_reached_500s": t_end, "stop": ""}
    run = cyrk_runs.run_cyrk(solver[len(PEER_PREFIX) :], t_end, rtol, atol, params=params, omega=omega)
    return {
        "n_impacts_500s": int(np.count_nonzero(run.impacts_t >= TRANSIENT)),
        "t_reached_500s": run.t_reached,
        "stop": "" if run.success else run.message,
    }


def known_long_runs(benchmark_rows: list[dict]) -> dict:
    """The 500 s runs from rest of the core-speed benchmark (impactosc_bench.core_speed,
    the same scene, solvers and atol = rtol/100) as {(solver, rtol): long_run()-style dict},
    so that the work-precision sweep does not run them again."""
    out = {}
    for r in benchmark_rows:
        status = str(r.get("status", ""))
        if r.get("kind") != "scene" or not (status == "ok" or status.startswith("stopped")):
            continue
        out[(str(r["solver"]), float(r["rtol"]))] = {
            "n_impacts_500s": r["n_impacts"],
            "t_reached_500s": float(r["t_reached"]),
            "stop": "" if status == "ok" else status.split(": ", 1)[-1],
        }
    return out


def attractor_columns(run: dict, reference: int) -> dict:
    """Columns of a row from :func:`long_run`: the count, where it stopped, on_attractor and a
    note for a run that is not on the attractor."""
    ok = not run["stop"] and on_attractor(run["n_impacts_500s"], reference)
    out = {
        "n_impacts_500s": run["n_impacts_500s"],
        "t_reached_500s": run["t_reached_500s"],
        "reference_impacts_500s": reference,
        "on_attractor": ok,
    }
    if run["stop"]:
        out["attractor_note"] = f"500 s run stopped at t = {run['t_reached_500s']:.6g} s: {run['stop']}"
    elif not ok:
        out["attractor_note"] = (
            f"500 s run: {run['n_impacts_500s']} impacts in 100-500 s against {reference}: left the attractor"
        )
    return out
