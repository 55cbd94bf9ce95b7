"""Speed of the core against SciPy on the paper's chaotic scene (issue: foundation).

What it measures, per tolerance:
  * wall time, steps and RHS evaluations of the full chaotic scene (w = 40.86, 100 s +
    400 s) with our core (minimum of several repeats, JIT excluded) and with SciPy
    solve_ivp DOP853 with events (split at contact onset/exit; one run: it is slow);
  * impact-time error of both over the first 1.5 s (before chaos amplifies differences)
    against SciPy DOP853 at rtol 1e-13 / atol 1e-15;
  * RHS evaluations per forcing period, beside the same figure for the smooth linear
    oscillator (T = 0, no contact) at the same tolerance: the method's floor;
  * JIT compile time, cold (empty cache) and cached, in fresh processes.
"""

from __future__ import annotations

import dataclasses
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from ..integration.model import ModelParams
from ..integration.reference import solve_reference
from ..integration.simulate import simulate, warm_up

OMEGA, TRANSIENT, DURATION, ERR_HORIZON = 40.86, 100.0, 400.0, 1.5


def jit_times() -> dict:
    """Seconds to compile the core into an empty cache, and to load it from that cache."""
    code = "import time; t=time.perf_counter(); from impactosc.integration.simulate import warm_up; warm_up(); print(time.perf_counter()-t)"
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        out = {}
        for label in ("cold", "cached"):
            r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
            out[label] = float(r.stdout.strip().splitlines()[-1])
    return out


def _impact_error(times, ref_times) -> float:
    n = min(len(times), len(ref_times))
    if n == 0 or len(times) != len(ref_times):
        return math.inf
    return float(np.abs(np.asarray(times[:n]) - ref_times[:n]).max())


def measure(rtols=(1e-8, 1e-10), repeats=5, scipy_full=True, log=print) -> list[dict]:
    warm_up()
    period = 2 * math.pi / OMEGA
    n_periods = (TRANSIENT + DURATION) / period
    ref = solve_reference(OMEGA, ERR_HORIZON, rtol=1e-13, atol=1e-15)["impacts_t"]
    linear = dataclasses.replace(ModelParams(), T=0.0, xI=1.0)
    rows = []
    for rtol in rtols:
        atol = rtol * 1e-2
        walls = []
        for _ in range(repeats):
            res = simulate(OMEGA, TRANSIENT, DURATION, rtol=rtol, atol=atol, record=("impacts",))
            walls.append(res.attrs["wall_time"])
        short = simulate(OMEGA, 0.0, ERR_HORIZON, rtol=rtol, atol=atol, record=("impacts",))
        lin = simulate(OMEGA, TRANSIENT, DURATION, params=linear, rtol=rtol, atol=atol, x0=1e-3, record=("poincare",))
        row = dict(solver="impactosc core", rtol=rtol, atol=atol, wall_time=min(walls),
                   wall_time_median=float(np.median(walls)), n_impacts=len(res.events["impacts"]["t"]),
                   steps=res.attrs["n_steps"] + res.attrs["n_implicit_steps"], rejected=res.attrs["n_rejected"],
                   rhs=res.attrs["n_rhs"], rhs_per_period=res.attrs["n_rhs"] / n_periods,
                   rhs_per_period_linear=lin.attrs["n_rhs"] / n_periods,
                   impact_time_error_1p5s=_impact_error(short.events["impacts"]["t"], ref))
        rows.append(row)
        log(f"core rtol={rtol:g}: {row['wall_time']:.3f} s, {row['n_impacts']} impacts, err {row['impact_time_error_1p5s']:.2e}")
        if scipy_full:
            t0 = time.perf_counter()
            sp = solve_reference(OMEGA, TRANSIENT + DURATION, rtol=rtol, atol=atol)
            wall = time.perf_counter() - t0
            sp_short = solve_reference(OMEGA, ERR_HORIZON, rtol=rtol, atol=atol)
            n_imp = int(np.count_nonzero(sp["impacts_t"] >= TRANSIENT))
            rows.append(dict(solver="SciPy solve_ivp DOP853 + events", rtol=rtol, atol=atol, wall_time=wall,
                             wall_time_median=wall, n_impacts=n_imp, steps=math.nan, rejected=math.nan,
                             rhs=sp["nfev"], rhs_per_period=sp["nfev"] / n_periods, rhs_per_period_linear=math.nan,
                             impact_time_error_1p5s=_impact_error(sp_short["impacts_t"], ref)))
            log(f"scipy rtol={rtol:g}: {wall:.1f} s, {n_imp} impacts, err {rows[-1]['impact_time_error_1p5s']:.2e}")
    return rows
