"""The contestants of the work-precision sweep: the core, SciPy's methods and the compiled peers,
each run on the same start, horizon and events, and how they are timed.

Why a module: every contestant must return the same events (impacts, penetrations, Poincare
points) for the errors to compare; :func:`run_solver` dispatches a contestant's name to its
run, :func:`peer_status` says which peers can run here, :func:`best_time` times any of them.
"""

from __future__ import annotations

import math
import time

import numpy as np

from impactosc.core.simulation import simulate
from impactosc_bench import cyrk_runs, cyrk_shim
from impactosc_bench.scipy_reference import solve_reference

__all__ = [
    "CORE",
    "SCIPY_METHODS",
    "EVENT_KEYS",
    "PEER_PREFIX",
    "run_core_events",
    "run_scipy",
    "is_peer",
    "peer_solvers",
    "run_peer",
    "run_solver",
    "peer_status",
    "best_time",
]

CORE = "impactosc core"
SCIPY_METHODS = ("RK45", "DOP853", "Radau", "LSODA")
EVENT_KEYS = ("impacts_t", "impacts_v", "penetrations_t", "penetrations_h", "poincare_t", "poincare_x", "poincare_v")


def run_core_events(omega, t_end, x0, v0, params, rtol, atol) -> dict:
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
    """The same events with SciPy ``solve_ivp``: :func:`impactosc_bench.scipy_reference.solve_reference`
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
    res = {k: np.asarray(ref[k], float) for k in EVENT_KEYS}
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
        return run_core_events(omega, t_end, x0, v0, params, rtol, atol)
    if is_peer(solver):
        return run_peer(solver, omega, t_end, x0, v0, params, rtol, atol)
    return run_scipy(omega, t_end, x0, v0, params, solver, rtol, atol)


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
