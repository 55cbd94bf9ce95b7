"""Work-precision: wall time against the errors that matter for this study.

Why: a speed only means something at a stated accuracy. Errors are measured on what the
paper extracts - impact times, penetration depths, Poincare points - against a reference
computed by a *different* method at tighter tolerance, on horizons where trajectories are
still comparable: tens of seconds on a periodic orbit, ~1.5 s on the chaotic attractor
(later, chaos amplifies any difference). For a chaotic train the statistics, not the
trajectory, must converge (tolerance_statistics.py). The speed ratios at equal error are
read from the rows by speed_at_error.py; the error measures are event_errors.py.

Reference: SciPy ``solve_ivp`` DOP853 at rtol 1e-13 / atol 1e-15, split at contact onset and
exit (SciPy's own step control, event location and dense output; no code shared with the
numba core but the model parameters). It is cross-checked by another method (config
work_precision.reference: SciPy RK45 at rtol 1e-13 by default, or Radau, an implicit
collocation method, at rtol 1e-12, atol 1e-14: the same uncertainty, 1e-11 s, at several
times the cost); the difference of the two is the reference's own uncertainty and is
reported beside every error. (Radau at rtol 1e-13 or atol 1e-15, and DOP853 at atol 1e-16,
stall at a v = 0 inside contact, where |v|^n3 is singular.)

Timing follows DiffEqBenchmarks: minimum of several runs, JIT compile time excluded (and
reported apart), the same events requested from every solver.

Compiled peers (impactosc_bench.cyrk_runs, the ``peers`` extra): CyRK's DOP853, Vern8 and
Vern7 ("CyRK <method>") are contestants like SciPy's: the same starts, horizon, events and
errors; they integrate the model in one right-hand side (no splitting at contacts) with
numba cfunc events (impacts; v = 0 inside contact for penetrations) located on their dense
output, and Poincare points from t_eval. A peer that stops early (step-size underflow) is
a row with status "stopped" and infinite errors, not a dropped row. With
``attractor_check`` the core and the peers also run the scene's w from rest for 100 s +
400 s at each rtol (untimed): a run whose impact count in 100-500 s is not within 10 % of
the core's at rtol 1e-10, or that stops, has on_attractor "no" (SciPy is not checked: about
a minute per run). heyoka's free-flight floor (the same starts and horizon without contact)
is a row with status "floor". A peer that is not installed is a row with status
"unavailable" and the reason in its note.

The contestants and their timing are wp_solvers.py, the 500 s attractor check wp_attractor.py;
this module holds the scenes, their references and the sweep.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from impactosc.core.simulation import simulate, warm_up
from impactosc.model.parameters import ModelParams
from impactosc_bench import free_flight
from impactosc_bench.event_errors import METRICS, event_errors, worst_errors
from impactosc_bench.timing_rounds import CORE_ATOL, CORE_RTOL
from impactosc_bench.wp_attractor import attractor_columns, long_run
from impactosc_bench.wp_solvers import (
    CORE,
    EVENT_KEYS,
    SCIPY_METHODS,
    best_time,
    is_peer,
    peer_status,
    run_scipy,
    run_solver,
)

METRIC_LABELS = {
    "impact_time_error": "impact-time error (s)",
    "penetration_error": "penetration error (m)",
    "poincare_x_error": "Poincare-point error in x (m)",
}


@dataclass(frozen=True)
class Case:
    """One work-precision scene: trajectories from ``n_starts`` states on the attractor.

    The starts are Poincare points (phase 0, so a run from them at t = 0 continues the
    attractor exactly) at ``settle``, ``settle + spacing``, ... of a run from rest.
    """

    name: str
    omega: float
    settle: float
    horizon: float
    n_starts: int = 1
    spacing: float = 10.0

    def __post_init__(self):
        for key in ("omega", "horizon", "spacing"):
            if not (math.isfinite(getattr(self, key)) and getattr(self, key) > 0):
                raise ValueError(f"work-precision scene {self.name!r}: {key} must be > 0, got {getattr(self, key)}")
        if not (math.isfinite(self.settle) and self.settle >= 0):
            raise ValueError(f"work-precision scene {self.name!r}: settle must be >= 0 s, got {self.settle}")
        if int(self.n_starts) < 1:
            raise ValueError(f"work-precision scene {self.name!r}: starts must be >= 1, got {self.n_starts}")


def attractor_starts(case: Case, params: ModelParams, rtol: float = 1e-12) -> list[tuple[float, float]]:
    """(x, v) at the first Poincare time after settle + k * spacing, k = 0 .. n_starts-1."""
    period = 2 * math.pi / case.omega
    marks = [case.settle + k * case.spacing for k in range(case.n_starts)]
    res = simulate(
        case.omega,
        max(marks[0] - period, 0.0),
        marks[-1] + 2 * period - max(marks[0] - period, 0.0),
        params=params,
        rtol=rtol,
        atol=rtol * 1e-2,
        record=("poincare",),
    )
    p = res.events["poincare"]
    starts = []
    for mark in marks:
        i = int(np.searchsorted(p["t"], mark - 1e-9))
        starts.append((float(p["x"][i]), float(p["v"][i])))
    return starts


def heyoka_floor(case: Case, starts, params: ModelParams, repeats: int, tol: float = free_flight.FLOOR_TOL) -> dict:
    """heyoka's Taylor integrator over the scene's starts and horizon without contact (obstacle
    out of reach): wall time summed over the starts of the minimum of `repeats` runs."""
    integrator = free_flight.heyoka_free_flight(tol, dataclasses.replace(params, xI=1.0), case.omega)
    free_flight.run_heyoka(integrator, case.horizon)  # outside the timing
    wall = 0.0
    for x0, v0 in starts:
        out, wmin, _, _ = best_time(lambda: free_flight.run_heyoka(integrator, case.horizon, (x0, v0)), repeats)
        if not out.success:
            raise RuntimeError(f"heyoka stopped at t = {out.t_reached:g} s: {out.message}")
        wall += wmin
    return {
        "solver": f"heyoka Taylor (order {integrator.order}) free flight",
        "rtol": tol,
        "atol": tol,
        "status": "floor",
        "wall_time": wall,
        "repeats": repeats,
        "note": "no contact (obstacle out of reach): a floor, not a competitor",
    }


def references(case: Case, starts, params, ref: dict) -> tuple[list[dict], list[dict], dict]:
    """Primary and check reference per start, and the reference uncertainty: the check
    method's deviation from the primary."""
    primary, check, check_errs = [], [], []
    for x0, v0 in starts:
        a = run_scipy(case.omega, case.horizon, x0, v0, params, ref["method"], ref["rtol"], ref["atol"])
        b = run_scipy(
            case.omega, case.horizon, x0, v0, params, ref["check_method"], ref["check_rtol"], ref["check_atol"]
        )
        if a["impacts_t"].size != b["impacts_t"].size:
            raise RuntimeError(
                f"{case.name}: the two references disagree on the impact count "
                f"({a['impacts_t'].size} vs {b['impacts_t'].size}); shorten the horizon"
            )
        primary.append(a)
        check.append(b)
        check_errs.append(event_errors(b, a))
    return primary, check, worst_errors(check_errs)


def reference_set(case: Case, params, ref: dict) -> dict:
    """Everything a sweep of `case` measures against, computed once (rule wp_reference, beside
    other jobs: the Radau check of the 20 s periodic horizon alone takes minutes): the start
    states, the primary and check reference events per start, the reference uncertainty.
    JSON-ready (event arrays as lists); :func:`sweep_case` takes it back as `reference`."""
    starts = attractor_starts(case, params)
    primary, check, unc = references(case, starts, params, ref)

    def plain(run):
        return {k: np.asarray(v, float).tolist() if k in EVENT_KEYS else v for k, v in run.items()}

    return {
        "case": case.name,
        "method": ref,
        "starts": [list(s) for s in starts],
        "primary": [plain(r) for r in primary],
        "check": [plain(r) for r in check],
        "uncertainty": unc,
    }


def _from_reference_set(refset: dict) -> tuple[list, list[dict], list[dict], dict]:
    def arrays(run):
        return {k: np.asarray(v, float) if k in EVENT_KEYS else v for k, v in run.items()}

    starts = [tuple(s) for s in refset["starts"]]
    return starts, [arrays(r) for r in refset["primary"]], [arrays(r) for r in refset["check"]], refset["uncertainty"]


def sweep_case(
    case: Case,
    params: ModelParams,
    rtols,
    atol_ratio: float,
    solvers,
    ref: dict,
    core_repeats: int = 7,
    scipy_repeats: int = 2,
    repeat_below: float = 2.0,
    time_cap: float = 60.0,
    peer_repeats: int = 7,
    attractor_check: bool = False,
    floor: bool = False,
    known_500s: dict | None = None,
    log=print,
    reference: dict | None = None,
) -> list[dict]:
    """One row per (solver, rtol): wall time (sum over the starts of the minimum of the
    repeats), RHS evaluations and the errors against the reference.

    A SciPy solver is not run at tighter tolerances once one of its points (summed over the
    starts) took longer than `time_cap` s, the time budget per point (its skipped rows say
    so; math.inf: no budget); a run that fails (step-size collapse) is reported as
    failed with SciPy's message; a peer's run that stops early is a row with status
    "stopped" (wall time measured, errors inf). Peers ("CyRK <method>" in `solvers`) that
    cannot run here get one row with status "unavailable". With `attractor_check` the core's
    and the peers' rows carry their 500 s impact count and on_attractor (:func:`long_run`);
    with `floor` heyoka's free-flight floor is added (:func:`heyoka_floor`). `known_500s`
    maps (solver, rtol) to a 500 s run already made elsewhere
    (:func:`impactosc_bench.wp_attractor.known_long_runs` of the
    core-speed benchmark's table), which is then not run again.
    """
    known_500s = known_500s or {}
    warm_up()  # JIT compile (or cache load) stays out of every timing
    if reference is None:  # (else: made before by reference_set, with the same case and ref)
        reference = reference_set(case, params, ref)
    starts, refs, checks, unc = _from_reference_set(reference)
    log(
        f"{case.name}: {len(starts)} start(s), reference impacts {unc['n_impacts_ref']}, uncertainty "
        + ", ".join(f"{k} {unc[k]:.2e}" for k in METRICS)
    )
    base = {
        "scene": case.name,
        "omega": case.omega,
        "horizon": case.horizon,
        "n_starts": len(starts),
        **{f"reference_{k}": unc[k] for k in METRICS},
    }
    missing = peer_status(solvers, heyoka=floor)  # (builds the CyRK shim before any timing)
    rows = _unavailable_rows(case, base, missing, log)
    solvers = [s for s in solvers if missing.get(s) is None]
    reference_500s = None
    if attractor_check and (CORE in solvers or any(is_peer(s) for s in solvers)):
        reference_500s = long_run(CORE, case.omega, params, CORE_RTOL, CORE_ATOL)["n_impacts_500s"]
        log(f"{case.name}: the core at rtol {CORE_RTOL:g} has {reference_500s} impacts in 100-500 s from rest")
    for solver in solvers:
        # the primary reference's own method is measured against the check reference,
        # so that no solver is judged by a tighter run of itself
        against = checks if solver == ref["method"] else refs
        note = f"errors against the {ref['check_method']} reference" if against is checks else ""
        reps = core_repeats if solver == CORE else (peer_repeats if is_peer(solver) else scipy_repeats)
        below = repeat_below if solver in SCIPY_METHODS else math.inf
        capped = None
        for rtol in rtols:
            atol = rtol * atol_ratio
            row = {**base, "solver": solver, "rtol": rtol, "atol": atol}
            if capped is not None:
                rows.append(
                    {
                        **row,
                        "status": "skipped",
                        "note": f"time budget: rtol {capped:g} already took > {time_cap:g} s per point",
                    }
                )
                continue
            if reference_500s is not None and (solver == CORE or is_peer(solver)):
                run = known_500s.get((solver, rtol)) or long_run(solver, case.omega, params, rtol, atol)
                row.update(attractor_columns(run, reference_500s))
            rows.append(_measured_row(row, case, params, starts, against, reps, below, note, log))
            if rows[-1]["status"] == "ok" and solver != CORE and rows[-1]["wall_time"] > time_cap:
                capped = rtol
    if floor and missing.get("heyoka") is None:
        rows.append({**base, **heyoka_floor(case, starts, params, peer_repeats)})
        log(f"{case.name} {rows[-1]['solver']}: {rows[-1]['wall_time']:.4g} s")
    return rows


def _unavailable_rows(case: Case, base: dict, missing: dict, log) -> list[dict]:
    """One row with status "unavailable" per peer that cannot run here (`missing`: peer_status)."""
    rows = []
    for solver, reason in missing.items():
        if reason is not None:
            rows.append({**base, "solver": solver, "status": "unavailable", "note": reason})
            log(f"{case.name} {solver}: unavailable ({reason.splitlines()[0]})")
    return rows


def _measured_row(row: dict, case: Case, params, starts, against, reps: int, below: float, note: str, log) -> dict:
    """The measurement of one (solver, rtol) of `row` over the starts: wall time (sum of the
    minimum of `reps` runs per start, fewer after a run longer than `below` s), RHS evaluations
    and the worst errors against the reference runs `against` (one per start).

    Status "ok" (with `note`), "stopped" (a run ended early: wall time measured, errors inf)
    or "failed" (the contestant raised).
    """
    solver, rtol, atol = row["solver"], row["rtol"], row["atol"]
    try:
        walls, meds, nrep, rhs, errs, stops = 0.0, 0.0, 0, 0, [], []
        for k, ((x0, v0), r) in enumerate(zip(starts, against)):
            out, wmin, wmed, n = best_time(
                lambda: run_solver(solver, case.omega, case.horizon, x0, v0, params, rtol, atol), reps, below
            )
            walls, meds, nrep, rhs = walls + wmin, meds + wmed, max(nrep, n), rhs + out["rhs_evals"]
            if not out.get("success", True):
                stops.append(
                    f"start {k + 1}: stopped at t = {out['t_reached']:.6g} s of {case.horizon:g} s: {out['message']}"
                )
                continue
            errs.append(event_errors(out, r))
    except (RuntimeError, ValueError) as exc:  # a contestant that fails (SciPy's event location
        # can raise brentq's "f(a) and f(b) must have different signs") is a failed row, not a crash
        log(f"{case.name} {solver} rtol {rtol:g}: failed ({exc})")
        return {**row, "status": "failed", "note": f"{type(exc).__name__}: {exc}"}
    timing = {"wall_time": walls, "wall_time_median": meds, "repeats": nrep, "rhs_evals": rhs}
    if stops:
        out = {
            **row,
            "status": "stopped",
            **timing,
            **dict.fromkeys((*METRICS, "poincare_v_error"), math.inf),
            "note": "; ".join(stops),
        }
        log(f"{case.name} {solver} rtol {rtol:g}: {walls:.4g} s, {out['note']}")
        return out
    out = {**row, "status": "ok", **timing, **worst_errors(errs), "note": note}
    log(
        f"{case.name} {solver} rtol {rtol:g}: {walls:.4g} s, impact err {out['impact_time_error']:.2e}"
        + (f", {out['attractor_note']}" if "attractor_note" in out else "")
    )
    return out
