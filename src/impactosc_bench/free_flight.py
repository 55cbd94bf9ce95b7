"""The free-flight floor: model BC without contact, integrated by heyoka's Taylor method.

Why a module: the floor tells what a run costs where the contacts cost nothing. heyoka
(7.13.2 installs from PyPI here) gives a floor, not a peer: a Taylor method expands its
right-hand side to high order, and the contact law switches (x >= xI, max(., 0)) and has
|v|^n3, so a heyoka peer would have to split at contacts as the core does. The floor is the
same oscillator without contact (xI = 1 m, out of reach) but with the regularised friction,
from rest, 500 s at tol 1e-10 (relative and absolute). The row ``CyRK DOP853 free flight``
of peers.py is the same floor for CyRK (rtol 1e-10, atol 1e-12): what the contacts cost a
peer.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from impactosc.model.parameters import ModelParams
from impactosc_bench.cyrk_shim import INSTALL_HINT, PeerUnavailable
from impactosc_bench.scene import OMEGA
from impactosc_bench.timing_rounds import PeerRun

__all__ = ["FLOOR_TOL", "FREE_FLIGHT", "heyoka_free_flight", "run_heyoka"]

FLOOR_TOL = 1e-10
FREE_FLIGHT = dataclasses.replace(ModelParams(), xI=1.0)  # obstacle out of reach


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
