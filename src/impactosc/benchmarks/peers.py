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

So a Cython shim (SHIM_SOURCE, about 40 lines) builds the C++ ``Event`` around a numba cfunc
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
The shim passes t_eval = [t_end], so CyRK stores the impacts and the final state but not
every step (the project's core, too, keeps only what it is asked to record).

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
import hashlib
import importlib.machinery
import importlib.util
import math
import os
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import carray, cfunc, types

from ..integration.layout import CONTACT, N_PARAMS, P_XI
from ..integration.model import ModelParams, accel
from .core_speed import DURATION, ERR_HORIZON, OMEGA, TRANSIENT, _impact_error

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
INSTALL_HINT = "pip install -e '.[peers]'"


class PeerUnavailable(RuntimeError):
    """A peer solver is not installed or its shim cannot be built; the message says why."""


# --- CyRK: the Cython shim ----------------------------------------------------------------

SHIM_SOURCE = '''\
# distutils: language = c++
# cython: language_level=3, boundscheck=False, wraparound=False
"""impactosc's shim: CyRK's cysolve_ivp_noreturn with a cfunc right-hand side and one cfunc event."""
from libc.stdint cimport uintptr_t
from libcpp.limits cimport numeric_limits
from libcpp.vector cimport vector

from CyRK.cy.common cimport DiffeqFuncType, MAX_STEP
from CyRK.cy.cysolver_api cimport CySolverBase, CySolverResult, ODEMethod, WrapCySolverResult, cysolve_ivp_noreturn
from CyRK.cy.events cimport Event, EventFunc


def solve(uintptr_t diffeq_address, uintptr_t event_address, int event_direction, int method,
          double t_start, double t_end, const double[::1] y0, const double[::1] args,
          double rtol, double atol, const double[::1] t_eval, size_t max_num_steps):
    """Integrate; event_address 0 means no event.

    Returns CyRK's WrapCySolverResult and where the solver stopped (t, [y]): the solver is
    retained for this, so that a run that fails tells how far it got.
    """
    cdef vector[double] y0_vec = vector[double](y0.shape[0])
    cdef vector[double] t_eval_vec = vector[double](t_eval.shape[0])
    cdef vector[char] args_vec = vector[char](args.shape[0] * sizeof(double))
    cdef double* args_ptr = <double*>args_vec.data()
    cdef vector[Event] events_vec = vector[Event]()
    cdef Py_ssize_t i
    for i in range(y0.shape[0]):
        y0_vec[i] = y0[i]
    for i in range(t_eval.shape[0]):
        t_eval_vec[i] = t_eval[i]
    for i in range(args.shape[0]):
        args_ptr[i] = args[i]
    if event_address:
        events_vec.emplace_back(<EventFunc>event_address, numeric_limits[size_t].max(), event_direction)
    cdef WrapCySolverResult result = WrapCySolverResult()
    result.build_cyresult(<ODEMethod>method)
    cdef CySolverResult* result_ptr = result.cyresult_uptr.get()
    with nogil:
        # positionally: with keywords Cython compiles this call as a Python call (not without the GIL)
        cysolve_ivp_noreturn(result_ptr, <DiffeqFuncType>diffeq_address, t_start, t_end, y0_vec,
                             rtol, atol, args_vec, 0, max_num_steps, 2000, False, t_eval_vec, NULL,
                             events_vec, vector[double](), vector[double](), MAX_STEP, 0.0, 0, True, NULL)
    result.finalize()
    cdef CySolverBase* solver = result_ptr.solver_uptr.get()
    if solver == NULL:  # the setup failed; the result's message says why
        return result, float("nan"), [float("nan")] * y0.shape[0]
    return result, solver.t_now, [solver.y_now_ptr[i] for i in range(y0.shape[0])]
'''

_BUILD_SCRIPT = '''\
import sys
import CyRK, numpy
from Cython.Build import cythonize
from setuptools import Extension, setup
name = sys.argv[1]
ext = Extension(name, [name + ".pyx"], language="c++", include_dirs=CyRK.get_include() + [numpy.get_include()],
                extra_compile_args=["-O0", "-std=c++20"],
                define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_9_API_VERSION")])
setup(ext_modules=cythonize([ext], quiet=True), script_args=["build_ext", "--inplace"])
'''


def _import_cyrk():
    try:
        import CyRK
    except ImportError as e:
        raise PeerUnavailable(f"CyRK is not installed ({e}); install the peers extra: {INSTALL_HINT}") from e
    return CyRK


def _shim_key(cyrk_version: str) -> str:
    import Cython

    digest = hashlib.sha256()
    for part in (SHIM_SOURCE, _BUILD_SCRIPT, cyrk_version, Cython.__version__, np.__version__,
                 sys.implementation.cache_tag, importlib.machinery.EXTENSION_SUFFIXES[0]):
        digest.update(part.encode() + b"\0")
    return digest.hexdigest()[:16]


def shim_dir(key: str) -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "impactosc" / f"cyrk-shim-{key}"


def _built(directory: Path, name: str) -> Path | None:
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        if (directory / (name + suffix)).is_file():
            return directory / (name + suffix)
    return None


def _build_shim(directory: Path, name: str) -> Path:
    """Compile the shim into `directory` once; concurrent callers wait on a file lock."""
    import fcntl

    directory.mkdir(parents=True, exist_ok=True)
    with open(directory / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if (path := _built(directory, name)) is not None:
            return path
        with tempfile.TemporaryDirectory(dir=directory) as tmp:
            Path(tmp, name + ".pyx").write_text(SHIM_SOURCE)
            r = subprocess.run([sys.executable, "-c", _BUILD_SCRIPT, name], cwd=tmp, capture_output=True, text=True)
            built = _built(Path(tmp), name)
            if r.returncode != 0 or built is None:
                tail = "\n".join((r.stderr or r.stdout).strip().splitlines()[-15:])
                raise PeerUnavailable(f"the CyRK shim could not be built (needs Cython, setuptools and a C++20 "
                                      f"compiler; {INSTALL_HINT}):\n{tail}")
            os.replace(built, directory / built.name)  # atomic: a reader never sees half a library
        return directory / built.name


def load_cyrk_shim():
    """The compiled shim module (built on first use); raises PeerUnavailable with the reason."""
    cyrk = _import_cyrk()
    try:
        import Cython  # noqa: F401  (the build needs it; say so before starting a compiler)
    except ImportError as e:
        raise PeerUnavailable(f"Cython is needed to build the CyRK shim; {INSTALL_HINT}") from e
    key = _shim_key(cyrk.__version__)
    name = f"_impactosc_cyrk_shim_{key}"
    if name in sys.modules:  # an extension module cannot be initialised twice in a process
        return sys.modules[name]
    directory = shim_dir(key)
    path = _built(directory, name) or _build_shim(directory, name)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[name] = module
    return module


def cyrk_method(name: str) -> int:
    """CyRK's integer code of an integration method (names as in METHODS, any case)."""
    from CyRK import ODEMethod

    try:
        return int(getattr(ODEMethod, name.upper()))
    except AttributeError:
        raise PeerUnavailable(f"CyRK {_import_cyrk().__version__} has no method {name!r}") from None


# --- the model as CyRK sees it --------------------------------------------------------------

_DBL_PTR = types.CPointer(types.float64)


def _rhs(dy, t, y, p_ptr, pre_eval):
    # CONTACT adds the Hunt-Crossley force, which contact_force makes 0 for x < xI: the whole
    # model in one right-hand side, as a solver that does not split sees it.
    p = carray(p_ptr, N_PARAMS)
    dy[0] = y[1]
    dy[1] = accel(p, CONTACT, t, y[0], y[1])


def _impact_event(t, y, p_ptr):
    return y[0] - p_ptr[P_XI]


@functools.cache
def model_cfuncs():
    """numba cfuncs (right-hand side, impact event) with CyRK's C signatures, compiled once.

    DiffeqFuncType is void(double* dy, double t, double* y, char* args, PreEvalFunc) and
    EventFunc double(double t, double* y, char* args); the parameter array of
    ModelParams.as_array travels as CyRK's args and is read back as double*.
    """
    rhs = cfunc(types.void(_DBL_PTR, types.float64, _DBL_PTR, _DBL_PTR, types.voidptr), cache=True)(_rhs)
    event = cfunc(types.float64(types.float64, _DBL_PTR, _DBL_PTR), cache=True)(_impact_event)
    return rhs, event


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


def run_cyrk(method: str, t_end: float, rtol: float, atol: float, *, params: ModelParams | None = None,
             impacts: bool = True, omega: float = OMEGA) -> PeerRun:
    """Integrate model BC from rest with CyRK over [0, t_end] in one right-hand side.

    With `impacts` the event x - xI (direction +1) is located on CyRK's dense output.
    The wall time covers the solver call only (the cfuncs and the shim are built before).
    """
    shim = load_cyrk_shim()
    rhs, event = model_cfuncs()
    p = (params or ModelParams()).as_array(omega)
    code = cyrk_method(method)
    start = time.perf_counter()
    result, t_stop, y_stop = shim.solve(rhs.address, event.address if impacts else 0, 1, code, 0.0, t_end,
                                        np.zeros(2), p, rtol, atol, np.array([t_end]), MAX_STEPS)
    wall = time.perf_counter() - start
    impacts_t = np.asarray(result.t_events[0], float) if impacts else np.empty(0)
    return PeerRun(wall, int(result.steps_taken), impacts_t, t_stop, np.array(y_stop), bool(result.success),
                   str(result.message))


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


def run_heyoka(integrator, t_end: float) -> PeerRun:
    """Propagate a heyoka integrator from rest at t = 0 to t_end (no impacts: free flight)."""
    integrator.time = 0.0
    integrator.state[:] = 0.0
    start = time.perf_counter()
    outcome = integrator.propagate_until(t_end)
    wall = time.perf_counter() - start
    ok = integrator.time == t_end
    return PeerRun(wall, int(outcome[3]), np.empty(0), integrator.time, integrator.state.copy(), ok,
                   str(outcome[0]))


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
    return dict(solver=solver, kind=kind, rtol=rtol, atol=atol, wall_time=float(np.median(walls)),
                wall_time_min=min(walls), repeats=len(runs), t_reached=last.t_reached, steps=last.steps,
                steps_per_period=last.steps / (last.t_reached / PERIOD), status=status, **extra)


def _repeat(run, repeats: int) -> list[PeerRun]:
    return [run() for _ in range(repeats)]


def measure_cyrk(methods=METHODS, rtols=RTOLS, repeats: int = 3, *, reference_impacts: int,
                 ref_times: np.ndarray, log=print) -> list[dict]:
    """The scene rows of CyRK (one per method and rtol) and its free-flight floor row.

    The timed runs go round-robin over the rows (`repeats` rounds), so that a change in the
    machine's load during the measurement spreads over all rows instead of favouring some.
    """
    load_cyrk_shim()
    model_cfuncs()
    run_cyrk("DOP853", 0.1, 1e-6, 1e-8)  # first call of the shim outside any timing
    configs = []
    for method in methods:
        try:
            cyrk_method(method)
        except PeerUnavailable as e:
            log(f"skipped: {e}")
            continue
        configs += [(method, rtol) for rtol in rtols]
    errors = {}
    for method, rtol in configs:
        short = run_cyrk(method, ERR_HORIZON, rtol, rtol * 1e-2)
        errors[method, rtol] = _impact_error(short.impacts_t, ref_times) if short.success else math.inf
    runs = {config: [] for config in configs}
    for i in range(repeats):
        log(f"round {i + 1} of {repeats}: {len(configs)} runs of {T_END:g} s")
        for method, rtol in configs:
            runs[method, rtol].append(run_cyrk(method, T_END, rtol, rtol * 1e-2))
    rows = []
    for (method, rtol), done in runs.items():
        n = int(np.count_nonzero(done[-1].impacts_t >= TRANSIENT))
        rows.append(_row(f"CyRK {method}", "scene", rtol, rtol * 1e-2, done,
                         impact_time_error_1p5s=errors[method, rtol], n_impacts=n,
                         on_attractor=done[-1].success and on_attractor(n, reference_impacts)))
        log(_line(rows[-1]))
    floor = _repeat(lambda: run_cyrk("DOP853", T_END, FLOOR_TOL, FLOOR_TOL * 1e-2, params=FREE_FLIGHT,
                                     impacts=False), repeats)
    rows.append(_row("CyRK DOP853 free flight", "floor", FLOOR_TOL, FLOOR_TOL * 1e-2, floor))
    log(_line(rows[-1]))
    return rows


def measure_heyoka(repeats: int = 3, log=print) -> list[dict]:
    """heyoka's free-flight floor row (500 s at tol 1e-10, compilation excluded)."""
    integrator = heyoka_free_flight()
    run_heyoka(integrator, 1.0)
    runs = _repeat(lambda: run_heyoka(integrator, T_END), repeats)
    row = _row(f"heyoka Taylor (order {integrator.order}) free flight", "floor", FLOOR_TOL, FLOOR_TOL, runs)
    log(_line(row))
    return [row]


def measure(methods=METHODS, rtols=RTOLS, repeats: int = 3, *, reference_impacts: int | None = None,
            heyoka: bool = True, log=print) -> list[dict]:
    """All rows: CyRK per method and rtol, then the free-flight floors (CyRK, heyoka).

    A peer that is not installed (or whose shim cannot be built) is skipped with a message.
    `reference_impacts` (the attractor's count) defaults to :func:`reference_impact_count`.
    """
    from ..integration.reference import solve_reference

    if reference_impacts is None:
        reference_impacts = reference_impact_count()
    log(f"attractor: the core at rtol {CORE_RTOL:g} has {reference_impacts} impacts in "
        f"{TRANSIENT:g}-{T_END:g} s; on_attractor = within {ATTRACTOR_TOLERANCE:.0%}")
    ref_times = solve_reference(OMEGA, ERR_HORIZON, rtol=REF_RTOL, atol=REF_ATOL)["impacts_t"]
    rows = []
    try:
        rows += measure_cyrk(methods, rtols, repeats, reference_impacts=reference_impacts, ref_times=ref_times,
                             log=log)
    except PeerUnavailable as e:
        log(f"CyRK skipped: {e}")
    if heyoka:
        try:
            rows += measure_heyoka(repeats, log=log)
        except PeerUnavailable as e:
            log(f"heyoka skipped: {e}")
    for r in rows:
        r["reference_impacts"] = reference_impacts
    return rows


def best_peer(rows: list[dict], max_error: float = 2.5e-9) -> dict | None:
    """The fastest scene row (solver, rtol) with 1.5 s impact-time error <= max_error that stays
    on the attractor; None if there is none. Floor rows (no contact) never qualify."""
    ok = [r for r in rows if r.get("kind", "scene") == "scene" and r.get("on_attractor")
          and r["impact_time_error_1p5s"] <= max_error]
    return min(ok, key=lambda r: r["wall_time"], default=None)


# --- output ---------------------------------------------------------------------------------

_COLUMNS = (  # key, title, width (negative: left-aligned), format spec
    ("solver", "solver", -40, "s"), ("rtol", "rtol", 7, ".0e"), ("wall_time", "wall [s]", 9, ".3f"),
    ("steps_per_period", "steps/T", 8, ".1f"), ("impact_time_error_1p5s", "err 1.5 s", 10, ".2e"),
    ("n_impacts", "impacts", 8, "d"), ("on_attractor", "attractor", 10, "s"))


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
    ap.add_argument("--reference-impacts", type=int, default=None,
                    help="the attractor's impact count in 100-500 s (default: run the core at rtol 1e-10)")
    ap.add_argument("--max-error", type=float, default=2.5e-9, help="error bound of the best peer")
    ap.add_argument("--no-heyoka", action="store_true", help="skip heyoka's free-flight floor")
    ap.add_argument("--out", help="write the rows to this CSV file")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats must be >= 1")
    rows = measure(args.methods, args.rtols, args.repeats, reference_impacts=args.reference_impacts,
                   heyoka=not args.no_heyoka, log=lambda msg: print(msg, file=sys.stderr, flush=True))
    print(format_table(rows))
    best = best_peer(rows, args.max_error)
    print(f"best peer (error <= {args.max_error:g}, on the attractor): "
          + (f"{best['solver']} at rtol {best['rtol']:g}, {best['wall_time']:.3f} s" if best else "none"))
    if args.out:
        from ..files import write_table

        write_table(args.out, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
