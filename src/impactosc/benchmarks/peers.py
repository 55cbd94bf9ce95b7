"""Compiled peer solvers on the paper's chaotic scene: CyRK's C++ Runge-Kutta methods, heyoka's floor.

Why: SciPy (core_speed.py) is an interpreted yardstick; these peers are compiled, so they
tell how fast a general-purpose solver gets on model BC when it sees the whole model as ONE
right-hand side (contact included; the project's core splits at contact onset and exit, a
peer does not) and finds the impacts with its own event machinery.

The scene (as core_speed.py): w = 40.86 rad/s, model BC defaults, rest at t = 0 (x = v = 0),
500 s = 100 s transient + 400 s. Impacts are the upward crossings of x = xI (event function
x - xI, direction +1, non-terminal). Per solver and rtol (atol = rtol * 1e-2):

  * wall time of the 500 s run: median of `repeats` runs, taken round-robin over the rows,
    compilation excluded (the numba cfuncs and the CyRK shim are built, and one short run
    made, before any timing);
  * accepted steps of that run and steps per forcing period (period 2 pi / w);
  * impacts in 100-500 s and ``on_attractor`` (below);
  * impact-time error over the first 1.5 s (a separate run, before chaos amplifies
    differences): max |t - t_ref| against SciPy DOP853 split at contacts
    (integration.reference) at rtol 1e-13 / atol 1e-15; inf when the counts differ.

On the attractor: the chaotic attractor has about 2900 impacts in 100-500 s. A row is on the
attractor when its run reached 500 s and its count is within ATTRACTOR_TOLERANCE (10 %) of
the count of the project's core at rtol 1e-10 / atol 1e-12 on the same scene (computed by
:func:`reference_impact_count`; 2898 when written). Chaos makes two accurate runs differ in
their counts by a few per cent at most (2878-2914 measured); a run that settles on another
orbit differs by tens of per cent. A run that stops early is not on the attractor either: its
row gives the time it reached, its count and steps up to there, and the solver's message.
The 1177 impacts of CyRK DOP853 at rtol 1e-12 are such a stop, not another orbit: at
t = 263.8 s, at the velocity reversal inside a contact (x - xI = 1.8e-4 m, v = -2e-11 m/s),
where |v|^n3 makes the contact force's slope in v infinite, its step size underflows
(Vern7 at rtol 1e-12 likewise, at t = 262.3 s).

:func:`best_peer` picks the fastest (solver, rtol) whose 1.5 s error is <= max_error and that
stays on the attractor.

How CyRK is driven (CyRK 0.20)
------------------------------
CyRK's integrators are C++ (CyRK.cy.cysolver_api). Its Python-level entries do not combine a
compiled right-hand side with events:

  * ``pysolve_ivp`` takes events but calls the right-hand side and the events as Python
    callables (a call into the interpreter per evaluation);
  * ``nbsolve2_ivp`` takes the address of a numba cfunc right-hand side but no events (its
    documentation: "does not currently support events"; it passes a null event pointer to
    the C++ entry, and an ``Event`` is a C++ class with std::function and std::vector
    members that cannot be built from Python).

So a Cython shim (SHIM_SOURCE, about 40 lines) builds a C++ ``Event`` around each numba cfunc
event function and calls ``cysolve_ivp_noreturn``, which Cython imports from CyRK's own
binary through its C-API capsule: the integration loop, the dense output and the Brent root
finding of the events (on the dense output of each step, to 4 machine epsilons) all run in
the binary shipped on PyPI. The shim is compiled on first use into
$XDG_CACHE_HOME/impactosc/cyrk-shim-<hash> (default ~/.cache; the hash covers the shim, the
CyRK, Cython and numpy versions and the Python ABI), under a file lock, in a subprocess; it
needs Cython and setuptools (the ``peers`` extra) and a C++20 compiler. If it cannot be
built the CyRK rows are skipped with the compiler's message.
It is compiled with -O0 (about 13 s instead of 17-25 s): cimporting cysolver_api pulls
CyRK's C++ sources into the shim's translation unit, but the shim only uses them to build
its arguments; the 500 s run measured the same wall time (0.84 s vs 0.87 s, DOP853 at
rtol 1e-10) with the shim at -O0 and at -O2.
run_cyrk passes t_eval = [t_end], so CyRK stores the impacts and the final state but not
every step (the project's core, too, keeps only what it is asked to record).
:func:`cyrk_events` (the work-precision contestant, workprecision.py) asks for what the other
contestants there give: impacts, penetrations (a second event, v = 0 crossed downwards, kept
at x > xI) and Poincare points (t_eval at 2 pi i / w, CyRK's dense output).

The timing rounds (:func:`measure_contestants`) take any :class:`Contestant`, so that
core_speed.py times the core in the same rounds as the peers.

heyoka (7.13.2 installs from PyPI here) gives a floor, not a peer: a Taylor method expands
its right-hand side to high order, and the contact law switches (x >= xI, max(., 0)) and
has |v|^n3, so a heyoka peer would have to split at contacts as the core does. The floor is
the same oscillator without contact (xI = 1 m, out of reach) but with the regularised
friction, from rest, 500 s at tol 1e-10 (relative and absolute). The row ``CyRK DOP853 free
flight`` is the same floor for CyRK (rtol 1e-10, atol 1e-12): what the contacts cost a peer.

Command line: python -m impactosc.benchmarks.peers [--rtols ...] [--repeats N] [--out table.csv]
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import carray, cfunc, types

from ..integration.layout import CONTACT, N_PARAMS, P_XI
from ..integration.model import ModelParams, accel
from .scene import DURATION, ERR_HORIZON, OMEGA, TRANSIENT, impact_error

T_END = TRANSIENT + DURATION
PERIOD = 2 * math.pi / OMEGA
REF_RTOL, REF_ATOL = 1e-13, 1e-15
RTOLS = (1e-9, 1e-10, 1e-11, 1e-12)
METHODS = ("DOP853", "Vern8", "Vern7")  # CyRK's high-order explicit methods
CORE_RTOL, CORE_ATOL = 1e-10, 1e-12  # the core's run that defines the attractor's impact count
ATTRACTOR_TOLERANCE = 0.10
FLOOR_TOL = 1e-10
FREE_FLIGHT = dataclasses.replace(ModelParams(), xI=1.0)  # obstacle out of reach
# A cap so that a solver pinned by the stiff contact reports failure instead of running for
# minutes: the 500 s scene takes under 1e6 steps (Vern8 at rtol 1e-12: 8.9e5).
MAX_STEPS = 50_000_000
from .cyrk_shim import INSTALL_HINT, PeerUnavailable, cyrk_method, load_cyrk_shim

_DBL_PTR = types.CPointer(types.float64)
_EVENT_SIGNATURE = types.float64(types.float64, _DBL_PTR, _DBL_PTR)


def _rhs(dy, t, y, p_ptr, pre_eval):
    # CONTACT adds the Hunt-Crossley force, which contact_force makes 0 for x < xI: the whole
    # model in one right-hand side, as a solver that does not split sees it.
    p = carray(p_ptr, N_PARAMS)
    dy[0] = y[1]
    dy[1] = accel(p, CONTACT, t, y[0], y[1])


def _impact_event(t, y, p_ptr):
    return y[0] - p_ptr[P_XI]


def _velocity_event(t, y, p_ptr):
    return y[1]


@functools.cache
def model_cfuncs():
    """numba cfuncs (right-hand side, impact event) with CyRK's C signatures, compiled once.

    DiffeqFuncType is void(double* dy, double t, double* y, char* args, PreEvalFunc) and
    EventFunc double(double t, double* y, char* args); the parameter array of
    ModelParams.as_array travels as CyRK's args and is read back as double*.
    """
    rhs = cfunc(types.void(_DBL_PTR, types.float64, _DBL_PTR, _DBL_PTR, types.voidptr), cache=True)(_rhs)
    event = cfunc(_EVENT_SIGNATURE, cache=True)(_impact_event)
    return rhs, event


@functools.cache
def velocity_cfunc():
    """numba cfunc of the event v = 0 (EventFunc signature). Crossed downwards (direction -1)
    at x > xI it is a deepest penetration, as the reference's v = 0 event inside contact."""
    return cfunc(_EVENT_SIGNATURE, cache=True)(_velocity_event)


@dataclass
class PeerRun:
    """One integration by a peer: wall time, accepted steps, impact times, final state, how it ended."""

    wall_time: float
    steps: int
    impacts_t: np.ndarray
    t_reached: float  # where it stopped: the requested end unless it failed
    state_end: np.ndarray  # (x, v) there
    success: bool
    message: str
    extra: dict = dataclasses.field(default_factory=dict)  # solver-specific counters for the row (e.g. RHS calls)


def _solve_cyrk(method: str, t_end: float, rtol: float, atol: float, p: np.ndarray, y0, t_eval, events):
    """(wall time, CyRK result, t reached, state there) of one shim call; events: (cfunc, direction) pairs."""
    shim = load_cyrk_shim()
    rhs, _ = model_cfuncs()
    code = cyrk_method(method)
    addresses = [int(e.address) for e, _ in events]
    directions = [int(d) for _, d in events]
    y0 = np.ascontiguousarray(y0, dtype=float)
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    start = time.perf_counter()
    result, t_stop, y_stop = shim.solve(
        rhs.address, addresses, directions, code, 0.0, t_end, y0, p, rtol, atol, t_eval, MAX_STEPS
    )
    wall = time.perf_counter() - start
    return wall, result, t_stop, np.array(y_stop)


def run_cyrk(
    method: str,
    t_end: float,
    rtol: float,
    atol: float,
    *,
    params: ModelParams | None = None,
    impacts: bool = True,
    omega: float = OMEGA,
    y0=(0.0, 0.0),
) -> PeerRun:
    """Integrate model BC from y0 = (x, v) (default rest) with CyRK over [0, t_end] in one right-hand side.

    With `impacts` the event x - xI (direction +1) is located on CyRK's dense output.
    The wall time covers the solver call only (the cfuncs and the shim are built before).
    """
    p = (params or ModelParams()).as_array(omega)
    events = [(model_cfuncs()[1], 1)] if impacts else []
    wall, result, t_stop, y_stop = _solve_cyrk(method, t_end, rtol, atol, p, y0, [t_end], events)
    impacts_t = np.asarray(result.t_events[0], float) if impacts else np.empty(0)
    return PeerRun(wall, int(result.steps_taken), impacts_t, t_stop, y_stop, bool(result.success), str(result.message))


def _event_columns(result, k: int) -> tuple[np.ndarray, np.ndarray]:
    """(times, states (2, n)) of CyRK's event k; an event that never fired comes back 1-D empty."""
    t = np.asarray(result.t_events[k], float)
    y = np.asarray(result.y_events[k], float)
    return t, (y if t.size else np.empty((2, 0)))


def cyrk_events(
    method: str, omega: float, t_end: float, x0: float, v0: float, params: ModelParams, rtol: float, atol: float
) -> dict:
    """Impacts, penetrations and Poincare points on (0, t_end] from (x0, v0), as
    workprecision.run_core returns them, by CyRK in one right-hand side.

    Impacts: x - xI crossed upwards; penetrations: v = 0 crossed downwards at x > xI (depth
    x - xI); Poincare points: CyRK's dense output at t_i = 2 pi i / w (t_eval). Besides the
    events: ``steps``, ``success``, ``t_reached`` and ``message`` (a run that stops early has
    the events up to where it stopped); ``rhs_evals`` is NaN (CyRK does not count them).
    """
    p = params.as_array(omega)
    period = 2 * math.pi / omega
    sections = period * np.arange(1, int(math.floor(t_end / period * (1 + 1e-14))) + 1)
    t_eval = sections if sections.size and sections[-1] >= t_end else np.append(sections, t_end)
    events = [(model_cfuncs()[1], 1), (velocity_cfunc(), -1)]
    _, result, t_stop, _ = _solve_cyrk(method, t_end, rtol, atol, p, (x0, v0), t_eval, events)
    imp_t, imp_y = _event_columns(result, 0)
    pen_t, pen_y = _event_columns(result, 1)
    inside = (pen_y[0] > params.xI) & (pen_t > 0.0)  # (a start at rest reports v = 0 at t = 0, as SciPy does)
    t_out, y_out = np.asarray(result.t, float), np.asarray(result.y, float)
    at_section = np.isin(t_out, sections)
    return {
        "impacts_t": imp_t,
        "impacts_v": imp_y[1],
        "penetrations_t": pen_t[inside],
        "penetrations_h": pen_y[0][inside] - params.xI,
        "poincare_t": t_out[at_section],
        "poincare_x": y_out[0][at_section],
        "poincare_v": y_out[1][at_section],
        "rhs_evals": math.nan,
        "steps": int(result.steps_taken),
        "success": bool(result.success),
        "t_reached": float(t_stop),
        "message": str(result.message),
    }


# --- heyoka: the free-flight floor ----------------------------------------------------------


def heyoka_free_flight(tol: float = FLOOR_TOL, params: ModelParams = FREE_FLIGHT, omega: float = OMEGA):
    """heyoka's Taylor integrator for model BC without contact, at rest at t = 0 (compiled once).

    The expression is external_force / m of model.py written for heyoka (it needs an
    expression, not a compiled function); tests check it against CyRK running model.accel.
    """
    try:
        import heyoka as hy
    except ImportError as e:
        raise PeerUnavailable(f"heyoka is not installed ({e}); {INSTALL_HINT}") from e
    x, v = hy.make_vars("x", "v")
    friction = params.T * v / hy.sqrt(v * v + params.eps**2)
    force = params.m0e * omega**2 * hy.sin(omega * hy.time) - params.k * x - params.c * v - friction
    return hy.taylor_adaptive([(x, v), (v, force / params.m)], [0.0, 0.0], tol=tol)


def run_heyoka(integrator, t_end: float, y0=(0.0, 0.0)) -> PeerRun:
    """Propagate a heyoka integrator from y0 = (x, v) (default rest) at t = 0 to t_end (no impacts: free flight)."""
    integrator.time = 0.0
    integrator.state[:] = y0
    start = time.perf_counter()
    outcome = integrator.propagate_until(t_end)
    wall = time.perf_counter() - start
    ok = integrator.time == t_end
    return PeerRun(wall, int(outcome[3]), np.empty(0), integrator.time, integrator.state.copy(), ok, str(outcome[0]))


# --- measurement ----------------------------------------------------------------------------


def reference_impact_count(rtol: float = CORE_RTOL, atol: float = CORE_ATOL) -> int:
    """Impacts in 100-500 s of the project's core on the scene: the attractor's count."""
    from ..integration.simulate import simulate

    res = simulate(OMEGA, TRANSIENT, DURATION, rtol=rtol, atol=atol, record=("impacts",))
    return len(res.events["impacts"]["t"])


def on_attractor(n_impacts: float, reference: float, tolerance: float = ATTRACTOR_TOLERANCE) -> bool:
    """Whether an impact count in 100-500 s is within `tolerance` (relative) of the attractor's."""
    return bool(abs(n_impacts - reference) <= tolerance * reference)


def _row(solver: str, kind: str, rtol: float, atol: float, runs: list[PeerRun], **extra) -> dict:
    # The runs are deterministic: the repeats differ in wall time only.
    walls = [r.wall_time for r in runs]
    last = runs[-1]
    status = "ok" if last.success else f"stopped at t = {last.t_reached:.6g} s: {last.message}"
    return dict(
        solver=solver,
        kind=kind,
        rtol=rtol,
        atol=atol,
        wall_time=float(np.median(walls)),
        wall_time_min=min(walls),
        repeats=len(runs),
        t_reached=last.t_reached,
        steps=last.steps,
        steps_per_period=last.steps / (last.t_reached / PERIOD),
        status=status,
        **last.extra,
        **extra,
    )


@dataclass
class Contestant:
    """One row of the scene's table: a timed 500 s run and, for a scene row, the 1.5 s run of its error.

    kind "scene" (model BC with contact: error, impacts, on_attractor) or "floor" (free flight).
    `run` and `short` return a PeerRun; `short` runs from rest to ERR_HORIZON with impacts.
    """

    solver: str
    kind: str
    rtol: float
    atol: float
    run: Callable[[], PeerRun]
    short: Callable[[], PeerRun] | None = None


def serpentine(items: list, round_index: int) -> list:
    """The order of one timing round: forward in even rounds, backward in odd ones, so that
    every item's mean position (and its share of a drift in the machine's load) is alike."""
    return list(items) if round_index % 2 == 0 else list(reversed(items))


def measure_contestants(
    contestants: list[Contestant], repeats: int, *, reference_impacts: int, ref_times: np.ndarray, log=print
) -> list[dict]:
    """Rows of the contestants: errors first (untimed), then `repeats` timing rounds in which
    every contestant runs once (serpentine order), so that a change in the machine's load
    spreads over all rows instead of favouring some; wall_time is the median of the rounds."""
    if int(repeats) < 1:
        raise ValueError(f"repeats must be >= 1, got {repeats}")
    errors = {}
    for i, c in enumerate(contestants):
        if c.short is not None:
            short = c.short()
            errors[i] = impact_error(short.impacts_t, ref_times) if short.success else math.inf
    runs = {i: [] for i in range(len(contestants))}
    for k in range(int(repeats)):
        log(f"round {k + 1} of {repeats}: {len(contestants)} runs of {T_END:g} s")
        for i in serpentine(range(len(contestants)), k):
            runs[i].append(contestants[i].run())
    rows = []
    for i, c in enumerate(contestants):
        done = runs[i]
        if c.kind == "scene":
            n = int(np.count_nonzero(done[-1].impacts_t >= TRANSIENT))
            rows.append(
                _row(
                    c.solver,
                    c.kind,
                    c.rtol,
                    c.atol,
                    done,
                    impact_time_error_1p5s=errors[i],
                    n_impacts=n,
                    on_attractor=done[-1].success and on_attractor(n, reference_impacts),
                )
            )
        else:
            rows.append(_row(c.solver, c.kind, c.rtol, c.atol, done))
        log(_line(rows[-1]))
    return rows


def cyrk_contestants(methods=METHODS, rtols=RTOLS, log=print) -> list[Contestant]:
    """CyRK per method and rtol on the scene, and its free-flight floor; compiles the cfuncs and
    the shim and makes one short run outside any timing. Raises PeerUnavailable."""
    load_cyrk_shim()
    model_cfuncs()
    run_cyrk("DOP853", 0.1, 1e-6, 1e-8)  # first call of the shim outside any timing
    out = []
    for method in methods:
        try:
            cyrk_method(method)
        except PeerUnavailable as e:
            log(f"skipped: {e}")
            continue
        for rtol in rtols:
            atol = rtol * 1e-2
            out.append(
                Contestant(
                    f"CyRK {method}",
                    "scene",
                    rtol,
                    atol,
                    run=functools.partial(run_cyrk, method, T_END, rtol, atol),
                    short=functools.partial(run_cyrk, method, ERR_HORIZON, rtol, atol),
                )
            )
    out.append(
        Contestant(
            "CyRK DOP853 free flight",
            "floor",
            FLOOR_TOL,
            FLOOR_TOL * 1e-2,
            run=functools.partial(
                run_cyrk, "DOP853", T_END, FLOOR_TOL, FLOOR_TOL * 1e-2, params=FREE_FLIGHT, impacts=False
            ),
        )
    )
    return out


def heyoka_contestants() -> list[Contestant]:
    """heyoka's free-flight floor (500 s at tol 1e-10), compiled and run once before any
    timing. Raises PeerUnavailable."""
    integrator = heyoka_free_flight()
    run_heyoka(integrator, 1.0)
    return [
        Contestant(
            f"heyoka Taylor (order {integrator.order}) free flight",
            "floor",
            FLOOR_TOL,
            FLOOR_TOL,
            run=functools.partial(run_heyoka, integrator, T_END),
        )
    ]


def peer_contestants(
    methods=METHODS, rtols=RTOLS, heyoka: bool = True, log=print
) -> tuple[list[Contestant], list[str]]:
    """The installed peers' contestants, and a message per peer that is skipped (not installed,
    or the CyRK shim cannot be built)."""
    out, skipped = [], []
    try:
        out += cyrk_contestants(methods, rtols, log=log)
    except PeerUnavailable as e:
        skipped.append(f"CyRK skipped: {e}")
    if heyoka:
        try:
            out += heyoka_contestants()
        except PeerUnavailable as e:
            skipped.append(f"heyoka skipped: {e}")
    for message in skipped:
        log(message)
    return out, skipped


def measure_cyrk(
    methods=METHODS, rtols=RTOLS, repeats: int = 3, *, reference_impacts: int, ref_times: np.ndarray, log=print
) -> list[dict]:
    """The scene rows of CyRK (one per method and rtol) and its free-flight floor row, timed
    round-robin (:func:`measure_contestants`)."""
    return measure_contestants(
        cyrk_contestants(methods, rtols, log=log),
        repeats,
        reference_impacts=reference_impacts,
        ref_times=ref_times,
        log=log,
    )


def measure_heyoka(repeats: int = 3, log=print) -> list[dict]:
    """heyoka's free-flight floor row (500 s at tol 1e-10, compilation excluded)."""
    return measure_contestants(heyoka_contestants(), repeats, reference_impacts=0, ref_times=np.empty(0), log=log)


def reference_times() -> np.ndarray:
    """Impact times over the first ERR_HORIZON s from rest: SciPy DOP853 split at contacts at rtol 1e-13."""
    from ..integration.reference import solve_reference

    return solve_reference(OMEGA, ERR_HORIZON, rtol=REF_RTOL, atol=REF_ATOL)["impacts_t"]


def measure(
    methods=METHODS,
    rtols=RTOLS,
    repeats: int = 3,
    *,
    reference_impacts: int | None = None,
    heyoka: bool = True,
    log=print,
) -> list[dict]:
    """All rows: CyRK per method and rtol, then the free-flight floors (CyRK, heyoka), timed
    round-robin together.

    A peer that is not installed (or whose shim cannot be built) is skipped with a message.
    `reference_impacts` (the attractor's count) defaults to :func:`reference_impact_count`.
    """
    if reference_impacts is None:
        reference_impacts = reference_impact_count()
    log(
        f"attractor: the core at rtol {CORE_RTOL:g} has {reference_impacts} impacts in "
        f"{TRANSIENT:g}-{T_END:g} s; on_attractor = within {ATTRACTOR_TOLERANCE:.0%}"
    )
    contestants, _ = peer_contestants(methods, rtols, heyoka, log=log)
    rows = measure_contestants(
        contestants, repeats, reference_impacts=reference_impacts, ref_times=reference_times(), log=log
    )
    for r in rows:
        r["reference_impacts"] = reference_impacts
    return rows


def best_peer(rows: list[dict], max_error: float = 2.5e-9) -> dict | None:
    """The fastest scene row (solver, rtol) with 1.5 s impact-time error <= max_error that stays
    on the attractor; None if there is none. Floor rows (no contact) never qualify.

    Rows read back from a CSV (impactosc.files.read_table) say on_attractor "yes"/"no"."""
    ok = [
        r
        for r in rows
        if r.get("kind", "scene") == "scene"
        and r.get("on_attractor") in (True, "yes")
        and r["impact_time_error_1p5s"] <= max_error
    ]
    return min(ok, key=lambda r: r["wall_time"], default=None)


# --- output ---------------------------------------------------------------------------------

_COLUMNS = (  # key, title, width (negative: left-aligned), format spec
    ("solver", "solver", -40, "s"),
    ("rtol", "rtol", 7, ".0e"),
    ("wall_time", "wall [s]", 9, ".3f"),
    ("steps_per_period", "steps/T", 8, ".1f"),
    ("impact_time_error_1p5s", "err 1.5 s", 10, ".2e"),
    ("n_impacts", "impacts", 8, "d"),
    ("on_attractor", "attractor", 10, "s"),
)


def _cells(row: dict, header: bool = False) -> str:
    cells = []
    for key, title, width, spec in _COLUMNS:
        value = row.get(key)
        if header:
            text = title
        elif value is None:
            text = "-"  # the column does not apply (floor rows: no contact, no impacts)
        elif isinstance(value, bool):
            text = "yes" if value else "no"
        else:
            text = format(value, spec)
        cells.append(text.ljust(-width) if width < 0 else text.rjust(width))
    return " ".join(cells)


def _line(row: dict) -> str:
    status = row.get("status", "ok")
    return _cells(row) + ("" if status == "ok" else f"  ({status})")


def format_table(rows: list[dict]) -> str:
    """The rows as a fixed-width text table, '-' where a column does not apply."""
    return "\n".join([_cells({}, header=True)] + [_line(r) for r in rows])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m impactosc.benchmarks.peers", description=__doc__.split("\n")[0])
    ap.add_argument("--rtols", type=float, nargs="+", default=list(RTOLS), help="relative tolerances (atol = rtol/100)")
    ap.add_argument("--methods", nargs="+", default=list(METHODS), help="CyRK methods")
    ap.add_argument("--repeats", type=int, default=3, help="timed 500 s runs per row; the median is reported")
    ap.add_argument(
        "--reference-impacts",
        type=int,
        default=None,
        help="the attractor's impact count in 100-500 s (default: run the core at rtol 1e-10)",
    )
    ap.add_argument("--max-error", type=float, default=2.5e-9, help="error bound of the best peer")
    ap.add_argument("--no-heyoka", action="store_true", help="skip heyoka's free-flight floor")
    ap.add_argument("--out", help="write the rows to this CSV file")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")
    rows = measure(
        args.methods,
        args.rtols,
        args.repeats,
        reference_impacts=args.reference_impacts,
        heyoka=not args.no_heyoka,
        log=lambda msg: print(msg, file=sys.stderr, flush=True),
    )
    print(format_table(rows))
    best = best_peer(rows, args.max_error)
    print(
        f"best peer (error <= {args.max_error:g}, on the attractor): "
        + (f"{best['solver']} at rtol {best['rtol']:g}, {best['wall_time']:.3f} s" if best else "none")
    )
    if args.out:
        from ..files import write_table

        write_table(args.out, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
