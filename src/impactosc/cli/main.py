"""Command line: ``impactosc simulate|extract|sweep-extract|surrogate|identify|predict|stats|explore|attractors ...`` (see ``impactosc <command> --help``)."""

from __future__ import annotations

import csv
import math
import signal
import sys
import time
import warnings

from impactosc.cli.attractors import _attractors
from impactosc.cli.explore import _explore
from impactosc.cli.identify import _identify
from impactosc.cli.options import MODEL_NAMES, model_from_args, noise_from_args, open_record_args
from impactosc.cli.parser import build_parser
from impactosc.cli.predict import _predict
from impactosc.cli.progress import WallTimeForecast
from impactosc.cli.stats import _stats
from impactosc.io.names import split_assignment
from impactosc.model.parameters import ParameterError


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

    def estimating(head):  # once the leading samples are read: what the x_impact fit reads, and how long it takes
        if args.x_impact_method == "contact":
            minutes = head.x.size * head.dt / 60.0
            whole = "whole record" if head.x.size < LEADING_SAMPLES else f"first {minutes:.2g} min"
            print(
                f"{args.record}: no x_impact given; fitting the contact law to the turning points of the record's "
                f"{whole} (about {5 * minutes / (2000 * head.dt):.0f} s)",
                file=sys.stderr,
            )

    with open_record_args(args, omega=args.omega) as stream:
        progress = _progress_printer(args.record, stream)
        events, attrs = extract_events(stream, x_impact, options, progress=progress, estimating=estimating)
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
    """A progress callback: the expected wall time once a record takes longer than a few seconds,
    and a line at each tenth of a long record (none for a record of unknown length)."""
    if not stream.n_samples:
        return None
    start, shown = time.perf_counter(), [0.0]
    forecast = WallTimeForecast("extract")

    def show(done):
        forecast(done)
        if stream.n_samples >= min_samples and (done >= shown[0] + every or done >= 1.0):
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
            raise ParameterError("--mismatch", f"mismatch item {item!r} must read name=relative_change")
        try:
            out[k] = float(v)
        except ValueError:
            raise ParameterError("--mismatch", f"mismatch value {v!r} of {k} is not a number") from None
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
    forecast = WallTimeForecast("surrogate")

    def progress(t, t_end, n_impacts):
        forecast(t / t_end)

    if args.ramp is None:
        if args.encoder_counts is not None:
            raise ValueError("--encoder-counts goes with --ramp (a constant-w record has no phase channel)")
        rec, _ = surrogate_record(args.omega, args.transient, args.duration, opts, params=params, progress=progress)
        meta = dict(rec.meta, model_source=source)
        write_record(args.output, rec.t, rec.x, omega=rec.omega, meta=meta, units=args.units)
        print(f"{args.output}: surrogate record, {rec.t.size} samples at {args.rate:g} Hz, noise {args.noise:g} m")
        return 0
    w0, w1 = args.ramp
    if not (w0 > 0 and w1 > 0 and args.transient >= 0 and args.duration > 0):
        raise ValueError("--ramp needs W_START, W_STOP > 0 rad/s, --transient >= 0 s and --duration > 0 s")
    if args.encoder_counts is not None and args.encoder_counts < 4:
        raise ParameterError("encoder_counts", f"an encoder has >= 4 counts per revolution, got {args.encoder_counts}")
    n_initial = round(args.transient * w0 / (2 * math.pi))  # whole periods: the ramp starts at phase 0
    rec, _ = surrogate_ramp(
        w0,
        w1,
        args.duration,
        opts,
        n_initial=n_initial,
        encoder_counts=args.encoder_counts,
        params=params,
        progress=progress,
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
    from impactosc.core.simulation import Window, check_step_budget, simulate, warm_up
    from impactosc.io.files import check_writable, write_run

    record = tuple(e.strip() for e in args.events.split(",") if e.strip())
    window = Window(*args.window) if args.window else None
    check_writable(args.output)
    # validate everything before compiling or integrating
    from impactosc.core.simulation import _validate

    _validate(args.omega, args.transient, args.duration, args.x0, args.v0, args.rtol, args.atol, window)
    check_step_budget(args.step_budget)
    params, source = model_from_args(args)
    noise = noise_from_args(args)
    jit = warm_up()
    last = [time.perf_counter()]
    forecast = WallTimeForecast("simulate", quiet=args.quiet)

    def progress(t, t_end, n_imp):
        now = time.perf_counter()
        forecast(t / t_end)
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
        noise=noise,
    )
    res.attrs["jit_and_load_time"] = jit
    res.attrs["model_source"] = source
    events = res.events
    if args.write_noise and res.realisation is not None:
        from impactosc.model.noise_realisation import realisation_datasets

        datasets, rule = realisation_datasets(res.realisation)
        events, res.attrs = {**events, **datasets}, {**res.attrs, **rule}
    write_run(args.output, events, res.attrs, res.trajectory)
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
    "stats": _stats,
    "explore": _explore,
    "attractors": _attractors,
}


#: The option a library argument is given by, where its name does not say it (``--`` + the
#: name with - for _ does otherwise): per command, as :class:`ParameterError` names it.
OPTIONS = {
    "simulate": {"t_end": "--transient/--duration"},
    "surrogate": {
        "t_end": "--transient/--duration",
        "window": "--rate",
        "lowpass_hz": "--lowpass",
        **dict.fromkeys(MODEL_NAMES.split(), "--mismatch"),
    },
    "extract": {"delay": "--sensor-delay", "x_impact": "--x-impact"},
}


def _option(command: str, name: str) -> str:
    if name.startswith("--"):
        return name
    return OPTIONS.get(command, {}).get(name, "--" + name.replace("_", "-"))


def _one_line_warnings(message, category, filename, lineno, file=None, line=None):
    """Warnings (e.g. a parameter outside the tested ranges) as one line each, as errors are."""
    print(f"impactosc: warning: {message}", file=sys.stderr)


def _interruption(exc, kinds):
    """The Ctrl-C or SIGTERM an exception comes from, or None. Why a search: one that arrives
    while compiled code calls back into Python comes out as numba's SystemError, caused by it."""
    while exc is not None and not isinstance(exc, kinds):
        exc = exc.__cause__ or exc.__context__
    return exc


def main(argv=None) -> int:
    """Run one command. Every error a user can cause ends in one line on stderr, ``impactosc
    <command>: error: [--option: ]what``, exit status 2 (3: the core stopped; 130: Ctrl-C; 143:
    SIGTERM), and nothing written; argparse's own refusals print the usage, then that line."""
    parser = build_parser()
    args = parser.parse_args(argv)
    from impactosc.io.files import Terminated, raise_on_sigterm

    say = f"impactosc {args.command}: error:"
    handler = raise_on_sigterm()
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warnings
            return COMMANDS[args.command](args)
    except ParameterError as exc:
        option = _option(args.command, exc.name)
        print(f"{say} {exc}" if str(exc).startswith(option) else f"{say} {option}: {exc}", file=sys.stderr)
        return 2
    except (ValueError, FileNotFoundError, OSError) as exc:
        print(f"{say} {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:  # the core stopped (StallError: where and why), nothing written
        print(f"{say} {exc}; nothing written", file=sys.stderr)
        return 3
    except (ArithmeticError, MemoryError, csv.Error) as exc:  # the last resort: a value no check foresaw
        print(
            f"{say} {type(exc).__name__}: {exc} (a value beyond what the computation can take); nothing written",
            file=sys.stderr,
        )
        return 2
    except (KeyboardInterrupt, Terminated, SystemError) as exc:
        stop = _interruption(exc, (KeyboardInterrupt, Terminated))
        if stop is None:
            raise
        why = "terminated (SIGTERM)" if isinstance(stop, Terminated) else "interrupted"
        print(f"impactosc {args.command}: {why}, nothing written", file=sys.stderr)
        return stop.code if isinstance(stop, Terminated) else 130
    finally:
        if handler is not None:
            signal.signal(signal.SIGTERM, handler)


if __name__ == "__main__":
    sys.exit(main())
