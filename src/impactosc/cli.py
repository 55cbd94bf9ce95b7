"""Command line: ``impactosc simulate|extract|surrogate|config-docs ...`` (see ``impactosc <command> --help``)."""

from __future__ import annotations

import argparse
import math
import sys
import time

from . import __version__

EPILOG = """\
Units: SI throughout (s, m, m/s, rad/s). Model parameters are model BC of the paper
(m=8.735 kg, k=1418.9 N/m, xI=-2.086e-3 m, ...); see impactosc.integration.model.ModelParams.
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
    from .integration.layout import DEFAULT_STEP_BUDGET
    from .integration.simulate import ALL_EVENTS, DEFAULT_ATOL, DEFAULT_RTOL

    parser = argparse.ArgumentParser(
        prog="impactosc",
        description="Forced impacting oscillator (model BC): event-exact simulation and impact statistics.",
    )
    parser.add_argument("--version", action="version", version=f"impactosc {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    sim = sub.add_parser(
        "simulate",
        help="integrate model BC and write its events to an HDF5 run file",
        description="Integrate model BC from (x0, v0) at t = 0 up to TRANSIENT + DURATION and write "
        "the events with t >= TRANSIENT (impact onsets, deepest penetrations, near misses, Poincare "
        "points at t = 2 pi i / omega) and an optional trajectory window to an HDF5 file.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sim.add_argument("--omega", type=_finite, required=True, help="forcing frequency w in rad/s (> 0)")
    sim.add_argument("--transient", type=_finite, required=True, help="time discarded before recording, s (>= 0)")
    sim.add_argument("--duration", type=_finite, required=True, help="recorded time after the transient, s (> 0)")
    sim.add_argument("--x0", type=_finite, default=0.0, help="initial displacement at t = 0, m (default 0)")
    sim.add_argument("--v0", type=_finite, default=0.0, help="initial velocity at t = 0, m/s (default 0)")
    sim.add_argument(
        "--rtol", type=_finite, default=DEFAULT_RTOL, help=f"relative tolerance (default {DEFAULT_RTOL:g})"
    )
    sim.add_argument(
        "--atol", type=_finite, default=DEFAULT_ATOL, help=f"absolute tolerance, m and m/s (default {DEFAULT_ATOL:g})"
    )
    sim.add_argument(
        "--window",
        type=_finite,
        nargs=3,
        metavar=("T1", "T2", "DT"),
        help="also store x, v sampled at t = T1, T1+DT, ... <= T2 (absolute times, s)",
    )
    sim.add_argument(
        "--events",
        default=",".join(ALL_EVENTS),
        help=f"comma-separated events to store (default: all of {','.join(ALL_EVENTS)})",
    )
    sim.add_argument("--output", required=True, help="HDF5 file to write (written atomically)")
    sim.add_argument(
        "--step-budget",
        type=_finite,
        default=DEFAULT_STEP_BUDGET,
        metavar="N",
        help="watchdog: step attempts allowed per forcing period of progress; a run that spends "
        f"them without advancing one period stops with an error naming where (default {DEFAULT_STEP_BUDGET:g}, "
        "~10^4 times what the chaotic scene needs)",
    )
    sim.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    ext = sub.add_parser(
        "extract",
        help="extract impact events from a measured (or surrogate) displacement record",
        description="Read a record (CSV with a '# key: value' metadata block and a header, or HDF5 "
        "record/t, record/x; see impactosc.measured.records), validate it, and write the same event datasets as "
        "'simulate' (impacts/t, impacts/v, penetrations/t, penetrations/h, poincare/* when omega is "
        "known) to an HDF5 file. Impacts are upward crossings of XI with hysteresis; their times are "
        "interpolated below the sample interval and their uncertainties stored in impacts/sigma_t.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Example:\n  impactosc extract examples/record_example.csv --x-impact=-2.086e-3 --output events.h5\n"
        "Without --x-impact (and no x_impact in the record) XI is estimated from the record's highest "
        "turning points and the estimate is printed.",
    )
    ext.add_argument("record", help="record file (.csv or .h5)")
    ext.add_argument(
        "--x-impact",
        type=_finite,
        help="obstacle position XI, m (write --x-impact=-2.086e-3 for negative values; default: record metadata, else estimated)",
    )
    ext.add_argument("--output", required=True, help="HDF5 events file to write (atomically)")
    ext.add_argument(
        "--column",
        nargs=2,
        metavar=("TIME", "X"),
        default=("t", "x"),
        help="CSV column names of time (s) and displacement (default: t x)",
    )
    ext.add_argument("--units", choices=("m", "mm"), help="displacement units when the record does not declare them")
    ext.add_argument("--omega", type=_finite, help="forcing frequency, rad/s (overrides the record's)")
    ext.add_argument("--noise", type=_finite, help="sensor-noise std, m (default: estimated from the record)")
    sur = sub.add_parser(
        "surrogate",
        help="write a surrogate record: the model sampled like the rig, plus sensor noise",
        description="Simulate model BC at OMEGA, sample x at RATE Hz on [TRANSIENT, TRANSIENT + DURATION], "
        "add white Gaussian noise of std NOISE and write it in the measured-record format (.csv or .h5), "
        "labelled 'surrogate (model + noise)'.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Example:\n  impactosc surrogate --omega 40.86 --transient 100 --duration 400 --output rec.h5",
    )
    sur.add_argument("--omega", type=_finite, required=True, help="forcing frequency w in rad/s (> 0)")
    sur.add_argument("--transient", type=_finite, required=True, help="time discarded before sampling, s")
    sur.add_argument("--duration", type=_finite, required=True, help="sampled time, s")
    sur.add_argument("--rate", type=_finite, default=2000.0, help="sample rate, Hz (default 2000)")
    sur.add_argument("--noise", type=_finite, default=5e-6, help="sensor-noise std, m (default 5e-6)")
    sur.add_argument("--mismatch", default="", help="relative parameter changes, e.g. 'c=0.02,T=-0.05' (default none)")
    sur.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    sur.add_argument("--units", choices=("m", "mm"), default="m", help="CSV displacement units (default m)")
    sur.add_argument("--output", required=True, help="record file to write (.csv or .h5)")
    doc = sub.add_parser(
        "config-docs",
        help="write config/README.md (every config key) from the config schema",
        description="Render the JSON schema of the workflow config as a Markdown reference: per section a "
        "table of dotted key, type, default, allowed values and description. Run from the repository root.",
        epilog="Example:\n  impactosc config-docs --check   # exit 1 if config/README.md is out of date",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    doc.add_argument(
        "--schema",
        default="workflow/schemas/config.schema.yaml",
        help="config schema (default workflow/schemas/config.schema.yaml)",
    )
    doc.add_argument("--output", default="config/README.md", help="Markdown file to write (default config/README.md)")
    doc.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 if OUTPUT differs from the schema's rendering"
    )
    return parser


def _config_docs(args) -> int:
    from .config_docs import write

    if write(args.schema, args.output, check=args.check):
        print(f"{args.output}: up to date with {args.schema}")
        return 0
    if args.check:
        print(
            f"impactosc config-docs: {args.output} is out of date with {args.schema}; "
            "run `impactosc config-docs` to regenerate it",
            file=sys.stderr,
        )
        return 1
    print(f"{args.output}: written from {args.schema}")
    return 0


def _extract(args) -> int:
    from .files import check_writable, write_run
    from .measured.extract import ExtractOptions, extract_events
    from .measured.records import read_record

    check_writable(args.output)
    rec = read_record(
        args.record, time_column=args.column[0], x_column=args.column[1], units=args.units, omega=args.omega
    )
    events, attrs = extract_events(rec, args.x_impact, ExtractOptions(noise=args.noise))
    write_run(args.output, events, attrs)
    print(
        f"{args.output}: {attrs['n_impacts']} impacts in [{attrs['t_start']:g}, {attrs['t_stop']:g}] s; "
        f"x_impact = {attrs['x_impact']:.6g} m ({attrs['x_impact_source']}); noise {attrs['noise_sigma']:.3g} m; "
        f"timing uncertainty median {attrs['timing_sigma_median']:.3g} s, max {attrs['timing_sigma_max']:.3g} s "
        f"(sample interval {attrs['sample_interval']:.3g} s)"
    )
    return 0


def _parse_mismatch(text):
    out = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        if "=" not in item:
            raise ValueError(f"mismatch item {item!r} must read name=relative_change")
        k, v = item.split("=", 1)
        try:
            out[k.strip()] = float(v)
        except ValueError:
            raise ValueError(f"mismatch value {v!r} of {k} is not a number") from None
    return out


def _surrogate(args) -> int:
    from .files import check_writable
    from .measured.records import write_record
    from .measured.surrogate import SurrogateOptions, surrogate_record

    check_writable(args.output)
    opts = SurrogateOptions(rate=args.rate, noise=args.noise, mismatch=_parse_mismatch(args.mismatch), seed=args.seed)
    rec, _ = surrogate_record(args.omega, args.transient, args.duration, opts)
    write_record(args.output, rec.t, rec.x, omega=rec.omega, meta=rec.meta, units=args.units)
    print(f"{args.output}: surrogate record, {rec.t.size} samples at {args.rate:g} Hz, noise {args.noise:g} m")
    return 0


def _simulate(args) -> int:
    from .files import check_writable, write_run
    from .integration.simulate import Window, simulate, warm_up

    record = tuple(e.strip() for e in args.events.split(",") if e.strip())
    window = Window(*args.window) if args.window else None
    check_writable(args.output)
    # validate everything before compiling or integrating
    from .integration.simulate import _validate

    _validate(args.omega, args.transient, args.duration, args.x0, args.v0, args.rtol, args.atol, window)
    if args.step_budget < 100:
        raise ValueError(f"--step-budget must be >= 100 step attempts per forcing period, got {args.step_budget:g}")
    jit = warm_up()
    last = [time.perf_counter()]

    def progress(t, t_end, n_imp):
        now = time.perf_counter()
        if not args.quiet and now - last[0] > 2.0:
            print(f"impactosc: t = {t:.1f} / {t_end:.1f} s, {n_imp} impacts", file=sys.stderr, flush=True)
            last[0] = now

    res = simulate(
        args.omega,
        args.transient,
        args.duration,
        x0=args.x0,
        v0=args.v0,
        rtol=args.rtol,
        atol=args.atol,
        window=window,
        record=record,
        progress=progress,
        step_budget=args.step_budget,
    )
    res.attrs["jit_and_load_time"] = jit
    write_run(args.output, res.events, res.attrs, res.trajectory)
    n_imp = len(res.events["impacts"]["t"]) if "impacts" in res.events else 0
    print(
        f"{args.output}: {n_imp} impacts in [{args.transient:g}, {args.transient + args.duration:g}] s, "
        f"wall time {res.attrs['wall_time']:.3f} s ({res.attrs['n_steps']} steps)"
    )
    return 0


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if args.command == "simulate":
            return _simulate(args)
        if args.command == "extract":
            return _extract(args)
        if args.command == "surrogate":
            return _surrogate(args)
        if args.command == "config-docs":
            return _config_docs(args)
    except (ValueError, FileNotFoundError, OSError) as exc:
        print(f"impactosc {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:  # the core stopped (StallError: where and why), nothing written
        print(f"impactosc {args.command}: error: {exc}; nothing written", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print(f"impactosc {args.command}: interrupted, nothing written", file=sys.stderr)
        return 130
    return 1


if __name__ == "__main__":
    sys.exit(main())
