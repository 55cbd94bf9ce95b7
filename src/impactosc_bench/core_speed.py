"""Speed of the core against SciPy and the compiled peers on the paper's chaotic scene.

What it measures (``snakemake -j1 benchmark_core``), with the same columns for every
contestant (solver, rtol, wall time, steps per forcing period, impact-time error over the
first 1.5 s, impacts in 100-500 s, on the attractor):

  * the full chaotic scene (w = 40.86, from rest, 100 s + 400 s) with our core at each of
    its tolerances and with the compiled peers of :mod:`impactosc_bench.peers` (CyRK
    DOP853 / Vern8 / Vern7 with numba cfunc right-hand side and events, and the free-flight
    floors of CyRK and heyoka): `repeats` timing rounds in which every one of them runs
    once (:func:`impactosc_bench.timing_rounds.measure_contestants`, serpentine order), so that a change in the
    machine's load spreads over all rows; the wall time reported is the median of the
    rounds (and its minimum beside it), JIT compilation and the shim's build excluded;
  * SciPy solve_ivp DOP853 with events (split at contact onset/exit) at `scipy_rtols`,
    one run each (about a minute) outside the rounds;
  * impact-time error over the first 1.5 s (before chaos amplifies differences) against
    SciPy DOP853 at rtol 1e-13 / atol 1e-15, the same for every contestant;
  * on the attractor: the run reached 500 s and its impact count in 100-500 s is within
    10 % of the core's at rtol 1e-10 (timing_rounds.on_attractor);
  * RHS evaluations per forcing period of the core and SciPy (CyRK does not count them),
    beside the same figure of the core for the smooth linear oscillator (T = 0, no
    contact) at the same tolerance: the method's floor;
  * JIT compile time, cold (empty cache) and cached, in fresh processes.

:func:`core_speed_headline` gives the numbers docs/performance.md leads with: the core's fastest run with
error <= max_error, the fastest compiled peer at the same bound and their time ratio, then
SciPy.
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

from impactosc.core.simulation import StallError, simulate, warm_up
from impactosc.model.parameters import ModelParams
from impactosc_bench.scene import DURATION, ERR_HORIZON, OMEGA, TRANSIENT, impact_error
from impactosc_bench.scipy_reference import solve_reference
from impactosc_bench.timing_rounds import (
    ATTRACTOR_TOLERANCE,
    CORE_ATOL,
    CORE_RTOL,
    Contestant,
    PeerRun,
    measure_contestants,
    on_attractor,
    reference_impact_count,
    reference_times,
)

CORE = "impactosc core"
SCIPY = "SciPy solve_ivp DOP853 + events"
MAX_ERROR = 2.5e-9  # s: impact-time error over 1.5 s at which the headline compares solvers


JIT_PROBE = (
    "import time; t=time.perf_counter(); from impactosc.core.simulation import warm_up; "
    "warm_up(); print(time.perf_counter()-t)"
)


def _fresh_process_seconds(env: dict) -> float:
    """Seconds of JIT_PROBE (import and compile or cache load of the core) in a new process."""
    r = subprocess.run([sys.executable, "-c", JIT_PROBE], env=env, capture_output=True, text=True, check=True)
    return float(r.stdout.strip().splitlines()[-1])


def jit_times(cold: bool = True, cold_seconds: float | None = None) -> dict:
    """Seconds to compile the core into an empty cache, and to load it from that cache, each in
    a fresh process (JIT_PROBE). cold=False: the load from the cache only (the cold compile,
    about 40 s, is then None: not measured). `cold_seconds`: a cold compile already measured
    the same way (the workflow's numba_cache job, when it found the cache empty), taken
    instead of compiling again."""
    if cold_seconds is not None:
        return {"cold": float(cold_seconds), "cached": _fresh_process_seconds(dict(os.environ))}
    out = {"cold": None}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache) if cold else dict(os.environ)
        for label in ("cold", "cached") if cold else ("cached",):
            out[label] = _fresh_process_seconds(env)
    return out


def _n_periods(t: float) -> float:
    return t / (2 * math.pi / OMEGA)


# ------------------------------------------------------------------------------ the core


def run_core_from_rest(rtol: float, atol: float, transient: float = TRANSIENT, duration: float = DURATION):
    """One run of the core from rest as a timing_rounds.PeerRun (impacts with t >= transient). The wall
    time is the whole simulate() call, as a peer's is its whole solver call; a run that stalls
    is reported (success False, StallError's message), not raised."""
    t0 = time.perf_counter()
    try:
        res = simulate(OMEGA, transient, duration, rtol=rtol, atol=atol, record=("impacts",))
    except StallError as e:
        return PeerRun(
            time.perf_counter() - t0,
            0,
            np.empty(0),
            float(e.state.get("t", math.nan)),
            np.full(2, math.nan),
            False,
            str(e),
        )
    wall = time.perf_counter() - t0
    a = res.attrs
    n_rhs = a["n_rhs"]
    return PeerRun(
        wall,
        a["n_steps"] + a["n_implicit_steps"],
        res.events["impacts"]["t"],
        transient + duration,
        np.asarray(res.final_state[1:3], float),  # (x, v): the state starts with t
        True,
        "",
        extra=dict(rejected=a["n_rejected"], rhs=n_rhs, rhs_per_period=n_rhs / _n_periods(transient + duration)),
    )


def core_contestants(rtols):
    """The core at each rtol (atol = rtol/100) as timing_rounds.Contestant rows of the scene."""
    out = []
    for rtol in rtols:
        atol = rtol * 1e-2
        out.append(
            Contestant(
                CORE,
                "scene",
                rtol,
                atol,
                run=lambda r=rtol, a=atol: run_core_from_rest(r, a),
                short=lambda r=rtol, a=atol: run_core_from_rest(r, a, 0.0, ERR_HORIZON),
            )
        )
    return out


def linear_rhs_per_period(rtol: float) -> float:
    """RHS evaluations per forcing period of the core on the smooth linear oscillator (T = 0,
    obstacle out of reach, from x = 1 mm): the method's floor at this tolerance."""
    linear = dataclasses.replace(ModelParams(), T=0.0, xI=1.0)
    lin = simulate(
        OMEGA, TRANSIENT, DURATION, params=linear, rtol=rtol, atol=rtol * 1e-2, x0=1e-3, record=("poincare",)
    )
    return lin.attrs["n_rhs"] / _n_periods(TRANSIENT + DURATION)


def scipy_row(rtol: float, ref_times, reference_impacts: int, log=print) -> dict:
    """SciPy solve_ivp DOP853 with events over the scene (one run) and over 1.5 s (its error)."""
    atol = rtol * 1e-2
    t0 = time.perf_counter()
    sp = solve_reference(OMEGA, TRANSIENT + DURATION, rtol=rtol, atol=atol)
    wall = time.perf_counter() - t0
    short = solve_reference(OMEGA, ERR_HORIZON, rtol=rtol, atol=atol)
    n_imp = int(np.count_nonzero(sp["impacts_t"] >= TRANSIENT))
    row = dict(
        solver=SCIPY,
        kind="scene",
        rtol=rtol,
        atol=atol,
        wall_time=wall,
        wall_time_min=wall,
        repeats=1,
        t_reached=TRANSIENT + DURATION,
        steps=math.nan,
        steps_per_period=math.nan,
        status="ok",
        rhs=sp["nfev"],
        rhs_per_period=sp["nfev"] / _n_periods(TRANSIENT + DURATION),
        impact_time_error_1p5s=impact_error(short["impacts_t"], ref_times),
        n_impacts=n_imp,
        on_attractor=on_attractor(n_imp, reference_impacts),
    )
    log(f"scipy rtol={rtol:g}: {wall:.1f} s, {n_imp} impacts, err {row['impact_time_error_1p5s']:.2e}")
    return row


# ------------------------------------------------------------------------ the measurement

COLUMNS = (
    "solver",
    "kind",
    "rtol",
    "atol",
    "wall_time",
    "wall_time_min",
    "repeats",
    "steps",
    "steps_per_period",
    "rhs",
    "rhs_per_period",
    "rhs_per_period_linear",
    "impact_time_error_1p5s",
    "n_impacts",
    "on_attractor",
    "t_reached",
    "status",
    "rejected",
    "reference_impacts",
    "bit_for_bit",
)


def measure_core_speed(
    rtols=(1e-8, 1e-9, 1e-10, 1e-11),
    repeats: int = 3,
    *,
    scipy_rtols=(1e-8, 1e-10),
    peer_methods=None,
    peer_rtols=None,
    heyoka: bool = True,
    against: str | None = None,
    log=print,
) -> tuple[list[dict], list[str]]:
    """Rows of the core at `rtols`, the compiled peers (None: peers.METHODS / peers.RTOLS; an
    empty `peer_methods` and heyoka=False: no peers) and SciPy at `scipy_rtols`, every row
    with the columns of COLUMNS (NaN / None where one does not apply); and a message per peer
    that was skipped (not installed, shim not built).

    The attractor's impact count is the core's at rtol 1e-10 (measured here if that is one of
    `rtols`, else by timing_rounds.reference_impact_count).

    `against`: a git revision whose core is timed in the same rounds at `rtols`
    (:mod:`impactosc_bench.core_revision`); its rows say whether its impacts are this core's
    bit for bit.
    """
    from impactosc_bench import peers
    from impactosc_bench.core_revision import RevisionCore, revision_contestants, same_impacts

    revision = None if against is None else RevisionCore(against)  # a wrong revision fails first
    warm_up()
    methods = peers.METHODS if peer_methods is None else tuple(peer_methods)
    p_rtols = peers.RTOLS if peer_rtols is None else tuple(peer_rtols)
    ref_times = reference_times()
    core = core_contestants(rtols)
    if methods or heyoka:
        others, skipped = peers.peer_contestants(methods, p_rtols, heyoka=heyoka, log=log)
    else:
        others, skipped = [], []
    reference = None
    if CORE_RTOL in rtols:
        reference = len(run_core_from_rest(CORE_RTOL, CORE_ATOL).impacts_t)
    if reference is None:
        reference = reference_impact_count()
    log(
        f"attractor: the core at rtol {CORE_RTOL:g} has {reference} impacts in {TRANSIENT:g}-"
        f"{TRANSIENT + DURATION:g} s; on_attractor = within {ATTRACTOR_TOLERANCE:.0%}"
    )
    if revision is not None:
        others += revision_contestants(revision, rtols, TRANSIENT, DURATION)
    rows = measure_contestants(core + others, repeats, reference_impacts=reference, ref_times=ref_times, log=log)
    if revision is not None:
        for r in rows:
            if r["solver"] == revision.label:
                r["bit_for_bit"] = same_impacts(revision, run_core_from_rest, r["rtol"], TRANSIENT, DURATION)
        revision.close()
    for r in rows:
        if r["solver"] == CORE:
            r["rhs_per_period_linear"] = linear_rhs_per_period(r["rtol"])
    rows += [scipy_row(rtol, ref_times, reference, log=log) for rtol in scipy_rtols]
    rows = [{c: r.get(c) for c in COLUMNS} | {"reference_impacts": reference} for r in rows]
    return rows, skipped


# ------------------------------------------------------------------------------ summary


def core_speed_headline(rows: list[dict], max_error: float = MAX_ERROR) -> list[dict]:
    """The comparison docs/performance.md leads with, one row per contestant (role):

    * core: the core's fastest run on the attractor with impact-time error <= max_error;
    * compiled peer: the fastest compiled peer under the same condition (peers.best_peer);
    * SciPy: the fastest SciPy run under the same condition, else (as before) SciPy at the
      core's rtol, with its error beside it (the note says which);
    * floors: the free-flight rows (no contact; not a competitor).

    time_over_core = the row's wall time (median) / the core's. Roles without a qualifying
    row are listed with solver "none".
    """
    from impactosc_bench.peers import best_peer

    core_rows = [r for r in rows if r["solver"] == CORE]
    scipy_rows = [r for r in rows if r["solver"] == SCIPY]
    peer_rows = [r for r in rows if r["solver"] not in (CORE, SCIPY) and not r["solver"].startswith(CORE)]
    core = best_peer(core_rows, max_error)
    peer = best_peer(peer_rows, max_error)
    scipy, scipy_note = best_peer(scipy_rows, max_error), f"at equal error (<= {max_error:g} s)"
    if scipy is None and core is not None:
        same = [r for r in scipy_rows if r["rtol"] == core["rtol"]]
        if same:
            scipy, scipy_note = same[0], f"at the core's rtol: no SciPy run had error <= {max_error:g} s"
    if scipy is None:
        scipy_note = "" if scipy_rows else "not measured"
    core_time = core["wall_time"] if core else math.nan

    def entry(role, r, note=""):
        if r is None:
            return dict(
                role=role,
                solver="none",
                max_error=max_error,
                note=note or f"no run with error <= {max_error:g} s on the attractor",
            )
        return dict(
            role=role,
            solver=r["solver"],
            max_error=max_error,
            rtol=r["rtol"],
            wall_time=r["wall_time"],
            wall_time_min=r.get("wall_time_min"),
            repeats=r.get("repeats"),
            impact_time_error_1p5s=r.get("impact_time_error_1p5s"),
            n_impacts=r.get("n_impacts"),
            on_attractor=r.get("on_attractor"),
            time_over_core=r["wall_time"] / core_time,
            note=note,
        )

    out = [entry("core", core), entry("fastest compiled peer", peer), entry("SciPy", scipy, scipy_note)]
    out += [
        entry("free-flight floor", r, "no contact: a floor, not a competitor") for r in rows if r.get("kind") == "floor"
    ]
    return out


def _fmt(value, spec: str) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, str):
        return value
    return format(value, spec)


TABLE_COLUMNS = (  # key, title, format spec
    ("solver", "solver", "s"),
    ("rtol", "rtol", ".0e"),
    ("wall_time", "wall time, median [s]", ".3f"),
    ("wall_time_min", "min [s]", ".3f"),
    ("repeats", "runs", "d"),
    ("steps_per_period", "steps/period", ".1f"),
    ("rhs_per_period", "RHS/period", ".0f"),
    ("impact_time_error_1p5s", "impact-time error 1.5 s [s]", ".2e"),
    ("n_impacts", "impacts 100-500 s", "d"),
    ("on_attractor", "on attractor", "s"),
    ("status", "status", "s"),
)

HEADLINE_COLUMNS = (
    ("role", "", "s"),
    ("solver", "solver", "s"),
    ("rtol", "rtol", ".0e"),
    ("wall_time", "wall time, median [s]", ".3f"),
    ("impact_time_error_1p5s", "impact-time error 1.5 s [s]", ".2e"),
    ("n_impacts", "impacts 100-500 s", "d"),
    ("time_over_core", "time / core", ".2f"),
    ("note", "note", "s"),
)


def markdown_table(rows: list[dict], columns) -> list[str]:
    """Rows as Markdown table lines; '-' where a column does not apply (None, NaN)."""
    lines = ["| " + " | ".join(title for _, title, _ in columns) + " |", "|" + "---|" * len(columns)]
    for r in rows:
        cells = []
        for key, _, spec in columns:
            v = r.get(key)
            if spec == "d" and isinstance(v, float) and math.isfinite(v):
                v = int(v)
            cells.append(_fmt(v, spec).replace("|", "/"))
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def headline_sentence(head: list[dict]) -> str:
    """The headline in words: the ratio to the fastest compiled peer first, then SciPy."""
    by_role = {h["role"]: h for h in head}
    core, peer, scipy = by_role["core"], by_role["fastest compiled peer"], by_role["SciPy"]
    if core["solver"] == "none":
        return f"No run of the core had impact-time error <= {core['max_error']:g} s on the attractor."
    text = (
        f"At impact-time error <= {core['max_error']:g} s (first 1.5 s) the core (rtol {core['rtol']:g}) takes "
        f"{core['wall_time']:.3f} s"
    )
    if peer["solver"] != "none":
        text += (
            f"; the fastest compiled peer, {peer['solver']} at rtol {peer['rtol']:g}, takes "
            f"{peer['wall_time']:.3f} s: **{peer['time_over_core']:.2f}x the core's time**"
        )
    else:
        text += f"; no compiled peer reached that error on the attractor ({peer['note']})"
    if scipy["solver"] != "none":
        text += (
            f"; SciPy DOP853 + events at rtol {scipy['rtol']:g} takes {scipy['wall_time']:.1f} s "
            f"({scipy['time_over_core']:.0f}x the core's time; its error {scipy['impact_time_error_1p5s']:.1e} s, "
            f"{scipy['note']})"
        )
    return text + "."


def main(argv=None) -> int:
    import argparse

    from impactosc_bench.core_revision import revision_lines

    ap = argparse.ArgumentParser(
        prog="python -m impactosc_bench.core_speed",
        description="Time this core against the core of another git revision, in the same rounds "
        "(chaotic scene, from rest, 100 s + 400 s), and say whether their impacts are the same bit for bit.",
    )
    ap.add_argument("--against", required=True, help="git revision whose core is timed beside this one, e.g. HEAD~1")
    ap.add_argument("--rtols", type=float, nargs="+", default=[1e-8, 1e-10], help="tolerances (atol = rtol/100)")
    ap.add_argument("--repeats", type=int, default=7, help="timing rounds (median reported); default 7")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error(f"--repeats: must be >= 1, got {args.repeats}")
    if not all(0 < r < 1 for r in args.rtols):
        ap.error(f"--rtols: each must lie in (0, 1), got {args.rtols}")
    try:
        rows, _ = measure_core_speed(
            args.rtols, args.repeats, scipy_rtols=(), peer_methods=(), heyoka=False, against=args.against
        )
    except ValueError as e:
        ap.error(str(e))
    print("\n".join(revision_lines(rows, CORE)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
