"""CyRK's C++ Runge-Kutta methods on model BC, in one right-hand side, with numba cfunc events.

Why a module: CyRK is the compiled peer of the benchmarks (peers.py for the chaotic scene,
workprecision.py for the work-precision sweep); this is how a run of it is made, and what it
returns: a :class:`impactosc_bench.timing_rounds.PeerRun` (:func:`run_cyrk`) or the
events of a work-precision contestant (:func:`cyrk_events`).

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
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np
from numba import carray, cfunc, types

from impactosc.model.equations import CONTACT, accel
from impactosc.model.parameters import N_PARAMS, P_XI, ModelParams
from impactosc_bench.cyrk_shim import cyrk_method, load_cyrk_shim
from impactosc_bench.scene import OMEGA
from impactosc_bench.timing_rounds import PeerRun

__all__ = ["MAX_STEPS", "model_cfuncs", "velocity_cfunc", "run_cyrk", "cyrk_events"]

# A cap so that a solver pinned by the stiff contact reports failure instead of running for
# minutes: the 500 s scene takes under 1e6 steps (Vern8 at rtol 1e-12: 8.9e5).
MAX_STEPS = 50_000_000

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
    wp_solvers.run_core_events returns them, by CyRK in one right-hand side.

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
