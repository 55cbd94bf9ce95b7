"""Compiled peer solvers on the paper's chaotic scene: CyRK's C++ Runge-Kutta methods, heyoka's floor.

Why: SciPy (core_speed.py) is an interpreted yardstick; these peers are compiled, so they
tell how fast a general-purpose solver gets on model BC when it sees the whole model as ONE
right-hand side (contact included; the project's core splits at contact onset and exit, a
peer does not) and finds the impacts with its own event machinery.

The scene (as core_speed.py): w = 40.86 rad/s, model BC defaults, rest at t = 0 (x = v = 0),
500 s = 100 s transient + 400 s. Impacts are the upward crossings of x = xI (event function
x - xI, direction +1, non-terminal). Each peer at each rtol (atol = rtol * 1e-2) is a
contestant of the timing rounds (:mod:`impactosc_bench.timing_rounds`, which says what
a row measures and when a run is on the attractor), taken with the core's in core_speed.py.
How CyRK runs: :mod:`impactosc_bench.cyrk_runs`; heyoka's free-flight floor:
:mod:`impactosc_bench.free_flight`.

:func:`best_peer` picks the fastest (solver, rtol) whose 1.5 s error is <= max_error and that
stays on the attractor.

Command line: python -m impactosc_bench.peers [--rtols ...] [--repeats N] [--out table.csv]
"""

from __future__ import annotations

import argparse
import functools
import sys

import numpy as np

from impactosc_bench.cyrk_runs import model_cfuncs, run_cyrk
from impactosc_bench.cyrk_shim import PeerUnavailable, cyrk_method, load_cyrk_shim
from impactosc_bench.free_flight import FLOOR_TOL, FREE_FLIGHT, heyoka_free_flight, run_heyoka
from impactosc_bench.scene import ERR_HORIZON, TRANSIENT
from impactosc_bench.timing_rounds import (
    ATTRACTOR_TOLERANCE,
    CORE_RTOL,
    T_END,
    Contestant,
    format_table,
    measure_contestants,
    reference_impact_count,
    reference_times,
)

RTOLS = (1e-9, 1e-10, 1e-11, 1e-12)
METHODS = ("DOP853", "Vern8", "Vern7")  # CyRK's high-order explicit methods


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


def measure_peers(
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

    Rows read back from a CSV (impactosc.io.files.read_table) say on_attractor "yes"/"no"."""
    ok = [
        r
        for r in rows
        if r.get("kind", "scene") == "scene"
        and r.get("on_attractor") in (True, "yes")
        and r["impact_time_error_1p5s"] <= max_error
    ]
    return min(ok, key=lambda r: r["wall_time"], default=None)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m impactosc_bench.peers", description=__doc__.split("\n")[0])
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
    rows = measure_peers(
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
        from impactosc.io.files import write_table

        write_table(args.out, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
