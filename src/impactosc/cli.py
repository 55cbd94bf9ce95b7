"""Command line: ``impactosc simulate ...`` (see ``impactosc simulate --help``)."""

from __future__ import annotations

import argparse
import math
import sys
import time

from . import __version__

EPILOG = """\
Units: SI throughout (s, m, m/s, rad/s). Model parameters are model BC of the paper
(m=8.735 kg, k=1418.9 N/m, xI=-2.086e-3 m, ...); see impactosc.model.ModelParams.
Example (the chaotic scene of the paper, ~2875 impacts):
  impactosc simulate --omega 40.86 --transient 100 --duration 400 --output chaos.h5
"""


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not finite")
    return value


def build_parser() -> argparse.ArgumentParser:
    from .simulate import ALL_EVENTS, DEFAULT_ATOL, DEFAULT_RTOL

    parser = argparse.ArgumentParser(prog="impactosc", description="Forced impacting oscillator (model BC): "
                                     "event-exact simulation and impact statistics.")
    parser.add_argument("--version", action="version", version=f"impactosc {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    sim = sub.add_parser(
        "simulate", help="integrate model BC and write its events to an HDF5 run file",
        description="Integrate model BC from (x0, v0) at t = 0 up to TRANSIENT + DURATION and write "
        "the events with t >= TRANSIENT (impact onsets, deepest penetrations, near misses, Poincare "
        "points at t = 2 pi i / omega) and an optional trajectory window to an HDF5 file.",
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    sim.add_argument("--omega", type=_finite, required=True, help="forcing frequency w in rad/s (> 0)")
    sim.add_argument("--transient", type=_finite, required=True, help="time discarded before recording, s (>= 0)")
    sim.add_argument("--duration", type=_finite, required=True, help="recorded time after the transient, s (> 0)")
    sim.add_argument("--x0", type=_finite, default=0.0, help="initial displacement at t = 0, m (default 0)")
    sim.add_argument("--v0", type=_finite, default=0.0, help="initial velocity at t = 0, m/s (default 0)")
    sim.add_argument("--rtol", type=_finite, default=DEFAULT_RTOL, help=f"relative tolerance (default {DEFAULT_RTOL:g})")
    sim.add_argument("--atol", type=_finite, default=DEFAULT_ATOL,
                     help=f"absolute tolerance, m and m/s (default {DEFAULT_ATOL:g})")
    sim.add_argument("--window", type=_finite, nargs=3, metavar=("T1", "T2", "DT"),
                     help="also store x, v sampled at t = T1, T1+DT, ... <= T2 (absolute times, s)")
    sim.add_argument("--events", default=",".join(ALL_EVENTS),
                     help=f"comma-separated events to store (default: all of {','.join(ALL_EVENTS)})")
    sim.add_argument("--output", required=True, help="HDF5 file to write (written atomically)")
    sim.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    return parser


def _simulate(args) -> int:
    from .io import check_writable, write_run
    from .simulate import Window, simulate, warm_up

    record = tuple(e.strip() for e in args.events.split(",") if e.strip())
    window = Window(*args.window) if args.window else None
    check_writable(args.output)
    # validate everything before compiling or integrating
    from .simulate import _validate

    _validate(args.omega, args.transient, args.duration, args.x0, args.v0, args.rtol, args.atol, window)
    jit = warm_up()
    last = [time.perf_counter()]

    def progress(t, t_end, n_imp):
        now = time.perf_counter()
        if not args.quiet and now - last[0] > 2.0:
            print(f"impactosc: t = {t:.1f} / {t_end:.1f} s, {n_imp} impacts", file=sys.stderr, flush=True)
            last[0] = now

    res = simulate(args.omega, args.transient, args.duration, x0=args.x0, v0=args.v0, rtol=args.rtol,
                   atol=args.atol, window=window, record=record, progress=progress)
    res.attrs["jit_and_load_time"] = jit
    write_run(args.output, res.events, res.attrs, res.trajectory)
    n_imp = len(res.events["impacts"]["t"]) if "impacts" in res.events else 0
    print(f"{args.output}: {n_imp} impacts in [{args.transient:g}, {args.transient + args.duration:g}] s, "
          f"wall time {res.attrs['wall_time']:.3f} s ({res.attrs['n_steps']} steps)")
    return 0


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "simulate":
            return _simulate(args)
    except (ValueError, FileNotFoundError, OSError) as exc:
        print(f"impactosc {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"impactosc {args.command}: interrupted, nothing written", file=sys.stderr)
        return 130
    return 1


if __name__ == "__main__":
    sys.exit(main())
