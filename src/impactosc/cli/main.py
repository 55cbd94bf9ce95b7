"""Command line: ``impactosc simulate|extract|sweep-extract|surrogate|identify|predict|explore ...`` (see ``impactosc <command> --help``)."""

from __future__ import annotations

import math
import sys
import time

from impactosc.cli.explore import _explore
from impactosc.cli.identify import _identify
from impactosc.cli.options import model_from_args, open_record_args
from impactosc.cli.parser import build_parser
from impactosc.cli.predict import _predict
from impactosc.io.names import split_assignment


def _extract(args) -> int:
    from impactosc.io.files import check_writable, write_run
    from impactosc.records.extract import LEADING_SAMPLES, ExtractOptions, extract_events

    check_writable(args.output)
    x_impact, x_impact_source = _model_x_impact(args) if args.x_impact is None else (args.x_impact, None)
    options = ExtractOptions(
        noise=args.noise,
        x_impact_method=args.x_impact_method,
        contact_exponent=args.contact_exponent,
        delay=args.sensor_delay,
    )
    with open_record_args(args, omega=args.omega) as stream:
        if x_impact is None and "x_impact" not in stream.meta and args.x_impact_method == "contact":
            lead = min(stream.n_samples or LEADING_SAMPLES, LEADING_SAMPLES)
            minutes = lead * stream.dt / 60.0
            print(
                f"{args.record}: no x_impact given; fitting the contact law to the turning points of the record's "
                f"first {minutes:.2g} min (about {5 * minutes / (2000 * stream.dt):.0f} s)",
                file=sys.stderr,
            )
        events, attrs = extract_events(stream, x_impact, options, progress=_progress_printer(args.record, stream))
    if x_impact_source:
        attrs["x_impact_source"] = x_impact_source
    write_run(args.output, events, attrs, sources=[args.record])
    section = ""
    if "poincare" in events:
        section = f"; {events['poincare']['t'].size} Poincare points ({attrs['poincare_phase_source']}"
        if "omega_measured_median" in attrs:
            section += f", measured w {attrs['omega_measured_min']:.5g}..{attrs['omega_measured_max']:.5g} rad/s"
        section += ")"
    print(
        f"{args.output}: {attrs['n_impacts']} impacts in [{attrs['t_start']:g}, {attrs['t_stop']:g}] s; "
        f"x_impact = {attrs['x_impact']:.6g} m ({attrs['x_impact_source']}); noise {attrs['noise_sigma']:.3g} m; "
        f"timing uncertainty median {attrs['timing_sigma_median']:.3g} s, max {attrs['timing_sigma_max']:.3g} s "
        f"(sample interval {attrs['sample_interval']:.3g} s){section}"
    )
    return 0


def _progress_printer(name, stream, every=0.1, min_samples=20_000_000):
    """A progress callback printing to stderr at each tenth of a long record (none for a short one)."""
    if not stream.n_samples or stream.n_samples < min_samples:
        return None
    start, shown = time.perf_counter(), [0.0]

    def show(done):
        if done >= shown[0] + every or done >= 1.0:
            shown[0] = done
            print(f"{name}: {100 * done:.0f} % extracted ({time.perf_counter() - start:.0f} s)", file=sys.stderr)

    return show


def _model_x_impact(args) -> tuple[float | None, str | None]:
    """(xI, where from) of the model when --model or --param states xI (a model file's own xI,
    not model BC's filling in for it), else (None, None): the record or the estimate decides."""
    if args.model is None and not args.param:
        return None, None
    from impactosc.model.model_file import read_model_file

    params, source = model_from_args(args)
    by_param = any(split_assignment(item)[0] == "xI" for item in args.param)
    if by_param or (args.model is not None and "xI" not in read_model_file(args.model).defaulted):
        return params.xI, f"the model's xI, {source}"
    return None, None


def _sweep_extract(args) -> int:
    from impactosc.io.files import check_writable
    from impactosc.records.slow_sweep import sweep_segments, write_sweep_points

    check_writable(args.output)
    with open_record_args(args) as stream:
        points, info = sweep_segments(stream, args.bin_width, args.settle, min_points=args.min_points)
    write_sweep_points(args.output, points, info, label=args.label or stream.label, sources=[args.record])
    print(
        f"{args.output}: {info['n_segments']} segments of w {points['record_omega'].min():.4g}.."
        f"{points['record_omega'].max():.4g} rad/s, {points['x'].size} Poincare points "
        f"(of {info['n_points_total']}; {info['n_points_settling']} discarded while settling, "
        f"{info['n_segments_dropped']} segments with fewer than {info['min_points']} points dropped)"
    )
    return 0


def _parse_mismatch(text):
    out = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        k, v = split_assignment(item)
        if v is None:
            raise ValueError(f"mismatch item {item!r} must read name=relative_change")
        try:
            out[k] = float(v)
        except ValueError:
            raise ValueError(f"mismatch value {v!r} of {k} is not a number") from None
    return out


def _surrogate(args) -> int:
    from impactosc.io.files import check_writable
    from impactosc.records.formats import write_record
    from impactosc.records.surrogate import REALISM_FIELDS, SurrogateOptions, surrogate_ramp, surrogate_record

    check_writable(args.output)
    params, source = model_from_args(args)
    opts = SurrogateOptions(
        rate=args.rate,
        noise=args.noise,
        mismatch=_parse_mismatch(args.mismatch),
        seed=args.seed,
        **{name: getattr(args, name) for name in REALISM_FIELDS},  # the options' dests are the field names
    )
    if args.ramp is None:
        if args.encoder_counts is not None:
            raise ValueError("--encoder-counts goes with --ramp (a constant-w record has no phase channel)")
        rec, _ = surrogate_record(args.omega, args.transient, args.duration, opts, params=params)
        meta = dict(rec.meta, model_source=source)
        write_record(args.output, rec.t, rec.x, omega=rec.omega, meta=meta, units=args.units)
        print(f"{args.output}: surrogate record, {rec.t.size} samples at {args.rate:g} Hz, noise {args.noise:g} m")
        return 0
    w0, w1 = args.ramp
    if not (w0 > 0 and w1 > 0 and args.transient >= 0 and args.duration > 0):
        raise ValueError("--ramp needs W_START, W_STOP > 0 rad/s, --transient >= 0 s and --duration > 0 s")
    n_initial = round(args.transient * w0 / (2 * math.pi))  # whole periods: the ramp starts at phase 0
    rec, _ = surrogate_ramp(
        w0, w1, args.duration, opts, n_initial=n_initial, encoder_counts=args.encoder_counts, params=params
    )
    meta = dict(rec.meta, model_source=source)
    write_record(args.output, rec.t, rec.x, meta=meta, units=args.units, phase=rec.phase)
    print(
        f"{args.output}: surrogate sweep record, w {w0:g} -> {w1:g} rad/s in {args.duration:g} s "
        f"({abs(w1 - w0) / args.duration:.3g} rad/s^2), {rec.t.size} samples at {args.rate:g} Hz with phase, "
        f"noise {args.noise:g} m"
    )
    return 0


def _simulate(args) -> int:
    from impactosc.core.simulation import Window, simulate, warm_up
    from impactosc.io.files import check_writable, write_run

    record = tuple(e.strip() for e in args.events.split(",") if e.strip())
    window = Window(*args.window) if args.window else None
    check_writable(args.output)
    # validate everything before compiling or integrating
    from impactosc.core.simulation import _validate

    _validate(args.omega, args.transient, args.duration, args.x0, args.v0, args.rtol, args.atol, window)
    if args.step_budget < 100:
        raise ValueError(f"--step-budget must be >= 100 step attempts per forcing period, got {args.step_budget:g}")
    params, source = model_from_args(args)
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
        params=params,
    )
    res.attrs["jit_and_load_time"] = jit
    res.attrs["model_source"] = source
    write_run(args.output, res.events, res.attrs, res.trajectory)
    n_imp = len(res.events["impacts"]["t"]) if "impacts" in res.events else 0
    print(
        f"{args.output}: {n_imp} impacts in [{args.transient:g}, {args.transient + args.duration:g}] s, "
        f"wall time {res.attrs['wall_time']:.3f} s ({res.attrs['n_steps']} steps)"
    )
    return 0


COMMANDS = {
    "simulate": _simulate,
    "extract": _extract,
    "sweep-extract": _sweep_extract,
    "surrogate": _surrogate,
    "identify": _identify,
    "predict": _predict,
    "explore": _explore,
}


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return COMMANDS[args.command](args)
    except (ValueError, FileNotFoundError, OSError) as exc:
        print(f"impactosc {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:  # the core stopped (StallError: where and why), nothing written
        print(f"impactosc {args.command}: error: {exc}; nothing written", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print(f"impactosc {args.command}: interrupted, nothing written", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
