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

Compiled peers (impactosc.benchmarks.cyrk_runs, the ``peers`` extra): CyRK's DOP853, Vern8 and
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
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np

from ..integration.model import ModelParams
from ..integration.reference import solve_reference
from ..integration.simulate import StallError, simulate, warm_up
from . import cyrk_runs, cyrk_shim, free_flight
from .event_errors import METRICS, event_errors, worst_errors
from .scene import DURATION, TRANSIENT
from .timing_rounds import CORE_ATOL, CORE_RTOL, on_attractor

CORE = "impactosc core"
SCIPY_METHODS = ("RK45", "DOP853", "Radau", "LSODA")
METRIC_LABELS = {
    "impact_time_error": "impact-time error (s)",
    "penetration_error": "penetration error (m)",
    "poincare_x_error": "Poincare-point error in x (m)",
}
_EVENT_KEYS = ("impacts_t", "impacts_v", "penetrations_t", "penetrations_h", "poincare_t", "poincare_x", "poincare_v")


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


# ------------------------------------------------------------------------ the contestants


def run_core(omega, t_end, x0, v0, params, rtol, atol) -> dict:
    """Impacts, penetrations and Poincare points on (0, t_end] with the numba core."""
    res = simulate(
        omega,
        0.0,
        t_end,
        x0=x0,
        v0=v0,
        params=params,
        rtol=rtol,
        atol=atol,
        record=("impacts", "penetrations", "poincare"),
    )
    e = res.events
    return {
        "impacts_t": e["impacts"]["t"],
        "impacts_v": e["impacts"]["v"],
        "penetrations_t": e["penetrations"]["t"],
        "penetrations_h": e["penetrations"]["h"],
        "poincare_t": e["poincare"]["t"],
        "poincare_x": e["poincare"]["x"],
        "poincare_v": e["poincare"]["v"],
        "rhs_evals": res.attrs["n_rhs"],
    }


def run_scipy(omega, t_end, x0, v0, params, method, rtol, atol, max_pieces=100_000) -> dict:
    """The same events with SciPy ``solve_ivp``: :func:`impactosc.integration.reference.solve_reference`
    (split at contact onset, exit and the Hunt-Crossley cut; penetrations are v = 0 events in
    contact) with Poincare points from SciPy's dense output at t_i = 2 pi i / w.
    """
    if method not in SCIPY_METHODS:
        raise ValueError(f"unknown SciPy method {method!r}; choose from {SCIPY_METHODS}")
    ref = solve_reference(
        omega,
        t_end,
        x0=x0,
        v0=v0,
        params=params,
        method=method,
        rtol=rtol,
        atol=atol,
        max_pieces=max_pieces,
        poincare=True,
    )
    res = {k: np.asarray(ref[k], float) for k in _EVENT_KEYS}
    res["rhs_evals"] = ref["nfev"]
    return res


PEER_PREFIX = "CyRK "


def is_peer(solver: str) -> bool:
    """Whether `solver` names a compiled peer ("CyRK <method>")."""
    return solver.startswith(PEER_PREFIX)


def peer_solvers(methods) -> list[str]:
    """Contestant names of CyRK's methods."""
    return [PEER_PREFIX + m for m in methods]


def run_peer(solver, omega, t_end, x0, v0, params, rtol, atol) -> dict:
    """The same events with a compiled peer (cyrk_runs.cyrk_events); the dict also says whether the
    run reached t_end (success, t_reached, message)."""
    return cyrk_runs.cyrk_events(solver[len(PEER_PREFIX) :], omega, t_end, x0, v0, params, rtol, atol)


def run_solver(solver, omega, t_end, x0, v0, params, rtol, atol) -> dict:
    """Dispatch to the core, a compiled peer or one of SciPy's methods."""
    if solver == CORE:
        return run_core(omega, t_end, x0, v0, params, rtol, atol)
    if is_peer(solver):
        return run_peer(solver, omega, t_end, x0, v0, params, rtol, atol)
    return run_scipy(omega, t_end, x0, v0, params, solver, rtol, atol)


# ------------------------------------------------------------ the 500 s attractor check


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
    """The 500 s runs from rest of the core-speed benchmark (impactosc.benchmarks.core_speed,
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


def peer_status(solvers, *, heyoka: bool) -> dict:
    """For each peer in `solvers` (and "heyoka" if asked), None if it can run here, else why not
    (cyrk_shim.PeerUnavailable's message). Builds the CyRK shim and the cfuncs (outside any timing)."""
    out = {}
    cyrk = [s for s in solvers if is_peer(s)]
    if cyrk:
        try:
            cyrk_shim.load_cyrk_shim()
            cyrk_runs.model_cfuncs()
            cyrk_runs.velocity_cfunc()
            cyrk_runs.run_cyrk("DOP853", 0.1, 1e-6, 1e-8)
            reason = None
        except cyrk_shim.PeerUnavailable as e:
            reason = str(e)
        for s in cyrk:
            out[s] = reason
            if reason is None:
                try:
                    cyrk_shim.cyrk_method(s[len(PEER_PREFIX) :])
                except cyrk_shim.PeerUnavailable as e:
                    out[s] = str(e)
    if heyoka:
        try:
            import heyoka

            out["heyoka"] = None
        except ImportError as e:
            out["heyoka"] = f"heyoka is not installed ({e}); {cyrk_shim.INSTALL_HINT}"
    return out


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


def best_time(fn, repeats: int, repeat_below: float = math.inf):
    """(result, min wall, median wall, runs): fn run up to `repeats` times, stopping after
    a run longer than `repeat_below` s (slow solvers are timed fewer times)."""
    if int(repeats) < 1:
        raise ValueError(f"repeats must be >= 1, got {repeats}")
    walls, out = [], None
    for _ in range(int(repeats)):
        t0 = time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
        if walls[-1] > repeat_below:
            break
    return out, min(walls), float(np.median(walls)), len(walls)


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
        return {k: np.asarray(v, float).tolist() if k in _EVENT_KEYS else v for k, v in run.items()}

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
        return {k: np.asarray(v, float) if k in _EVENT_KEYS else v for k, v in run.items()}

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
    scipy_repeats: int = 3,
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
    maps (solver, rtol) to a 500 s run already made elsewhere (:func:`known_long_runs` of the
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
    rows = []
    missing = peer_status(solvers, heyoka=floor)  # (builds the CyRK shim before any timing)
    for solver, reason in missing.items():
        if reason is not None:
            rows.append({**base, "solver": solver, "status": "unavailable", "note": reason})
            log(f"{case.name} {solver}: unavailable ({reason.splitlines()[0]})")
    solvers = [s for s in solvers if missing.get(s) is None]
    reference_500s = None
    if attractor_check and (CORE in solvers or any(is_peer(s) for s in solvers)):
        reference_500s = long_run(CORE, case.omega, params, CORE_RTOL, CORE_ATOL)["n_impacts_500s"]
        log(f"{case.name}: the core at rtol {CORE_RTOL:g} has {reference_500s} impacts in 100-500 s from rest")
    for solver in solvers:
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
            # the primary reference's own method is measured against the check reference,
            # so that no solver is judged by a tighter run of itself
            against = checks if solver == ref["method"] else refs
            reps = core_repeats if solver == CORE else (peer_repeats if is_peer(solver) else scipy_repeats)
            below = repeat_below if solver in SCIPY_METHODS else math.inf
            if reference_500s is not None and (solver == CORE or is_peer(solver)):
                run = known_500s.get((solver, rtol)) or long_run(solver, case.omega, params, rtol, atol)
                row.update(attractor_columns(run, reference_500s))
            try:
                walls, meds, nrep, rhs, errs, stops = 0.0, 0.0, 0, 0, [], []
                for k, ((x0, v0), r) in enumerate(zip(starts, against)):
                    out, wmin, wmed, n = best_time(
                        lambda: run_solver(solver, case.omega, case.horizon, x0, v0, params, rtol, atol), reps, below
                    )
                    walls, meds, nrep, rhs = walls + wmin, meds + wmed, max(nrep, n), rhs + out["rhs_evals"]
                    if not out.get("success", True):
                        stops.append(
                            f"start {k + 1}: stopped at t = {out['t_reached']:.6g} s of {case.horizon:g} s: "
                            f"{out['message']}"
                        )
                        continue
                    errs.append(event_errors(out, r))
            except (RuntimeError, ValueError) as exc:  # a contestant that fails (SciPy's event location
                # can raise brentq's "f(a) and f(b) must have different signs") is a failed row, not a crash
                rows.append({**row, "status": "failed", "note": f"{type(exc).__name__}: {exc}"})
                log(f"{case.name} {solver} rtol {rtol:g}: failed ({exc})")
                continue
            if stops:
                rows.append(
                    {
                        **row,
                        "status": "stopped",
                        "wall_time": walls,
                        "wall_time_median": meds,
                        "repeats": nrep,
                        "rhs_evals": rhs,
                        **dict.fromkeys((*METRICS, "poincare_v_error"), math.inf),
                        "note": "; ".join(stops),
                    }
                )
                log(f"{case.name} {solver} rtol {rtol:g}: {walls:.4g} s, {rows[-1]['note']}")
                continue
            note = f"errors against the {ref['check_method']} reference" if against is checks else ""
            rows.append(
                {
                    **row,
                    "status": "ok",
                    "wall_time": walls,
                    "wall_time_median": meds,
                    "repeats": nrep,
                    "rhs_evals": rhs,
                    **worst_errors(errs),
                    "note": note,
                }
            )
            log(
                f"{case.name} {solver} rtol {rtol:g}: {walls:.4g} s, impact err {rows[-1]['impact_time_error']:.2e}"
                + (f", {rows[-1]['attractor_note']}" if "attractor_note" in rows[-1] else "")
            )
            if solver != CORE and walls > time_cap:
                capped = rtol
    if floor and missing.get("heyoka") is None:
        rows.append({**base, **heyoka_floor(case, starts, params, peer_repeats)})
        log(f"{case.name} {rows[-1]['solver']}: {rows[-1]['wall_time']:.4g} s")
    return rows
