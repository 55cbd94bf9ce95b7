"""What the explorer's worker processes compute: each function one call of the library.

Why module-level functions returning plain dicts of lists: they run in a process pool (the core
is compiled numba that holds the interpreter lock, so threads would share one core) and their
arguments and results cross the process boundary by pickling. Nothing here knows of Bokeh.

- :func:`diagram_batch`: a few consecutive columns of a continuation
  (:func:`impactosc.dynamics.sweep.continuation`), with the end state that seeds the next batch;
- :func:`attractor`: one w simulated onto its attractor (:func:`impactosc.core.simulate`): time
  series, Poincare points, intervals and the period of the Poincare sequence;
- :func:`periodic_orbit`: that orbit shot and its Floquet multipliers
  (:func:`impactosc.dynamics.shooting.shoot`, :func:`impactosc.dynamics.branch_segments.orbit_sample`);
- :func:`located_points`: the grazings, period doublings and folds of the period-1 branch in a
  window (:func:`impactosc.dynamics.branch_segments.trace_segment`), on demand (seconds to tens of
  seconds: a continuation with every point shot);
- :func:`record_points`: a rig record's Poincare points (:func:`impactosc.records.extract_events`).

Every error they raise reaches the server: one whose class would not survive pickling (the pool
would take it for a dead worker and break) is handed back as a :class:`WorkerError` with its text.
"""

from __future__ import annotations

import functools
import math
import pickle

import numpy as np

from impactosc.core.simulation import Window, end_state, simulate, start_of, warm_up
from impactosc.dynamics.branch_segments import orbit_sample
from impactosc.dynamics.shooting import ShootingError, shoot
from impactosc.dynamics.sweep import OK, SweepSettings, continuation
from impactosc.model.parameters import ModelParams
from impactosc.statistics.periods import detect_period

__all__ = ["WorkerError", "warm", "diagram_batch", "attractor", "periodic_orbit", "located_points", "record_points"]

#: Poincare repetition tolerances of the period reading (those of the workflow's diagram reading)
PERIOD_TOL = (1e-6, 1e-4)
#: Longest period whose orbit is shot (a longer one is read, not continued)
MAX_SHOT_PERIOD = 16
#: Forcing periods of the time series and phase portrait, and samples per period
WINDOW_PERIODS, SAMPLES_PER_PERIOD = 8, 200


class WorkerError(RuntimeError):
    """An error raised in a worker whose own class would not cross back by pickling: its text."""


def _plain_errors(fn):
    """`fn`, whose errors all cross the process boundary: those that would not unpickle as
    they are become WorkerError with the same text."""

    @functools.wraps(fn)
    def run(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except Exception as exc:
            try:
                pickle.loads(pickle.dumps(exc))
            except Exception:  # any failure to round-trip is what would break the pool
                raise WorkerError(f"{type(exc).__name__}: {exc}") from None
            raise

    return run


def warm() -> float:
    """Load the compiled core in this worker (from numba's disk cache): the first real request
    then pays nothing for it."""
    return warm_up()


@_plain_errors
def diagram_batch(omegas, settings: SweepSettings, state, first_transient: int) -> dict:
    """The columns of `omegas` (in sweep order) by continuation from `state` (x, v, contact_v0;
    contact_v0 NaN outside a restitution law's contact), the first w discarding
    `first_transient` periods: per column the Poincare x and the intervals S_j, and the end
    state the next batch starts from."""
    start = start_of(state)
    res = continuation(
        np.asarray(omegas, float), settings, x0=start["x0"], v0=start["v0"], contact_v0=start["contact_v0"],
        first_transient=first_transient,
    )  # fmt: skip
    cols = []
    for i in range(len(res)):
        ok = bool(res.status[i] == OK)
        cols.append(
            {
                "omega": float(res.omega[i]),
                "x": res.poincare_x[i].tolist() if ok else [],
                "isi": res.isi(i).tolist(),
                "state_end": (float(res.x_end[i]), float(res.v_end[i]), float(res.contact_v0_end[i])),
                "cpu": float(res.cpu_time[i]),  # s of the worker's CPU: the cost without other load
            }
        )
    return {"columns": cols, "state_end": cols[-1]["state_end"]}


@_plain_errors
def attractor(omega: float, params: ModelParams, state, n_transient: int, n_record: int) -> dict:
    """One w from `state` (x, v, contact_v0): `n_transient` periods discarded, `n_record`
    recorded. Returns the last WINDOW_PERIODS periods as a time series, the Poincare points
    (x, v), the impact times and their intervals, the period p of the Poincare sequence (0: none
    within the record) and the end state, the last Poincare point with its contact's v0."""
    period = 2 * math.pi / omega
    transient, duration = n_transient * period, n_record * period
    t_end = transient + duration
    shown = min(WINDOW_PERIODS, n_record) * period
    window = Window(t_end - shown, t_end, period / SAMPLES_PER_PERIOD)
    run = simulate(
        omega, transient, duration, params=params, window=window, record=("impacts", "poincare", "near_misses"),
        **start_of(state),
    )  # fmt: skip
    px, pv = run.events["poincare"]["x"], run.events["poincare"]["v"]
    t_imp = run.events["impacts"]["t"]
    isi = np.diff(t_imp)
    pts = np.column_stack([px, pv])
    p = detect_period(pts, PERIOD_TOL) if pts.shape[0] >= 6 else 0
    traj = run.trajectory
    return {
        "omega": float(omega),
        "t": traj["t"].tolist(),
        "x": traj["x"].tolist(),
        "v": traj["v"].tolist(),
        "poincare_x": px.tolist(),
        "poincare_v": pv.tolist(),
        "impact_t": t_imp.tolist(),
        "isi": isi.tolist(),
        "period": int(p),
        "state_end": tuple(float(c) for c in end_state(run)),
        "gap": float(run.events["near_misses"]["gap"].min()) if run.events["near_misses"]["gap"].size else math.inf,
    }


@_plain_errors
def periodic_orbit(omega: float, params: ModelParams, y, n_periods: int) -> dict:
    """The period-N orbit through `y` shot to the solver's tolerance, its Floquet multipliers,
    impacts per orbit and smallest near-miss gap (how close it is to grazing); or the reason
    shooting failed."""
    try:
        orbit = shoot(y, omega, n_periods, params)
    except ShootingError as exc:
        return {"omega": float(omega), "error": str(exc)}
    sample = orbit_sample(orbit, params)
    return {
        "omega": float(omega),
        "n_periods": int(n_periods),
        "x0": orbit.x0,
        "v0": orbit.v0,
        "mu_re": sample["mu_re"],
        "mu_im": sample["mu_im"],
        "stable": bool(sample["stable"]),
        "impacts": sample["impacts"],
        "min_gap": sample["min_gap"],
        "newton_steps": orbit.newton_steps,
    }


@_plain_errors
def located_points(params: ModelParams, w_lo: float, w_hi: float, ds: float = 0.05) -> list[dict]:
    """The located special points (kind, w) of the period-1 branch over [w_lo, w_hi], continued
    both ways from the orbit the simulation from rest settles on at the window's middle."""
    from impactosc.dynamics.branch_segments import seed_from_rest, trace_segment

    seed = seed_from_rest(0.5 * (w_lo + w_hi), 1, params)
    segment = trace_segment(seed=seed, ds=ds, w_range=(w_lo, w_hi), max_points=4000, params=params)
    points = [
        {"kind": p["kind"].replace("_", " "), "omega": float(p["omega"])}
        for p in segment["special_points"]
        if p["located"] and w_lo <= p["omega"] <= w_hi
    ]
    return sorted(points, key=lambda p: p["omega"])


@_plain_errors
def record_points(path: str, omega: float | None = None) -> dict:
    """A record's Poincare points (the measured w of each when an encoder gives the phase,
    else the record's nominal w). Raises ValueError/OSError when the record does not parse or
    has no forcing phase to cut it with."""
    from impactosc.records.extract import extract_events
    from impactosc.records.formats import read_record

    rec = read_record(path, omega=omega)
    events, attrs = extract_events(rec)
    if "poincare" not in events:
        raise ValueError(f"{path}: no Poincare points (the record states neither omega nor a phase channel)")
    pts = events["poincare"]
    x = np.asarray(pts["x"], float)
    w = np.asarray(pts["omega"], float) if "omega" in pts else np.full(x.size, float(attrs.get("omega", rec.omega)))
    return {"omega": w.tolist(), "x": x.tolist(), "label": rec.label, "x_impact": float(attrs["x_impact"])}
