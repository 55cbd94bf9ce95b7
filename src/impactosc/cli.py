"""Command line: ``impactosc simulate|extract|sweep-extract|surrogate|identify|config-docs ...`` (see ``impactosc <command> --help``)."""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
import time
import warnings

from . import __version__

EPILOG = """\
Units: SI throughout (s, m, m/s, rad/s). Model parameters are model BC of the paper
(m=8.735 kg, k=1418.9 N/m, xI=-2.086e-3 m, ...; see impactosc.integration.model.ModelParams)
unless --model / --param change them; the run file's attributes record every parameter
(param_*) and where they came from (model_source).
Examples (the chaotic scene of the paper, ~2875 impacts; the same with a rig's model file):
  impactosc simulate --omega 40.86 --transient 100 --duration 400 --output chaos.h5
  impactosc simulate --omega 40.86 --transient 100 --duration 400 --model rig.yaml --param k=1500 --output rig.h5
"""

MODEL_NAMES = "m m0e k c T eps kI b n1 n2 n3 xI"


def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not finite")
    return value


def _exponent(text: str) -> float | None:
    """A contact exponent: a number in [1, 2.5], or 'free' (None: fitted)."""
    if text.strip().lower() == "free":
        return None
    from .measured.extract import CONTACT_EXPONENT_RANGE

    value = _finite(text)
    lo, hi = CONTACT_EXPONENT_RANGE
    if not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"{text!r}: a contact exponent lies in [{lo:g}, {hi:g}] (or write 'free')")
    return value


RECORD_FORMATS = """\
Record formats (impactosc.measured.records):
  .csv   '# key: value' metadata block (units, omega, x_impact ...), then a header; columns
         chosen with --column; a column named 'phase' (or --phase-channel) is the phase
  .h5    record/t, record/x (m), optional record/phase (rad), metadata as attributes
  .tdms  National Instruments TDMS (LabVIEW, DAQmx): --group and --channel name the
         displacement (either may be left out when there is only one); time from the
         channel's wf_increment / wf_start_offset properties, or from --time-channel;
         units from the channel's unit_string (m, mm, um) or --units
Phase (optional): the unbalance's angle from an encoder (--phase-channel), 2 pi i at the
forcing's phase 0; units from its unit_string or --phase-units: rad, deg, rev, or counts:N
(N counts per revolution; counts reset each revolution are fine). With a phase, Poincare
points are taken where it crosses 2 pi i and w is measured from it (attribute
poincare_phase_source = encoder); without, at t = 2 pi i / omega (nominal omega).
"""


def _add_record_options(p, many: bool = False) -> None:
    """Options that say how to read a record (extract, sweep-extract); with `many`, several
    records or record sets (identify), the options applying to every file."""
    if many:
        p.add_argument(
            "record",
            nargs="+",
            help="record files (.csv, .h5 or .tdms) or record sets (HDF5, or a CSV manifest omega,file); "
            "the read options below apply to every file",
        )
    else:
        p.add_argument("record", help="record file (.csv, .h5 or .tdms)")
    p.add_argument(
        "--column",
        nargs=2,
        metavar=("TIME", "X"),
        default=("t", "x"),
        help="CSV column names of time (s) and displacement (default: t x)",
    )
    p.add_argument("--group", help="TDMS group holding the channels (default: the only group)")
    p.add_argument("--channel", help="TDMS displacement channel (default: the only channel besides phase and time)")
    p.add_argument(
        "--phase-channel",
        metavar="NAME",
        help="TDMS channel (or CSV column) of the measured forcing phase, e.g. the unbalance's encoder",
    )
    p.add_argument(
        "--time-channel",
        metavar="NAME",
        help="TDMS time channel (s, ms, or timestamps); default: the waveform properties wf_increment, wf_start_offset",
    )
    p.add_argument(
        "--units",
        choices=("m", "mm", "um"),
        help="displacement units when the record does not declare them (if it does, they must agree)",
    )
    p.add_argument(
        "--phase-units",
        metavar="U",
        help="phase units when the channel does not declare them: rad, deg, rev or counts:N (N per revolution)",
    )


def add_model_options(parser, description: str) -> None:
    """--model FILE and --param NAME=VALUE (repeatable): the model a command uses, read by
    :func:`model_from_args`; `description` says what the model is for in this command."""
    group = parser.add_argument_group("model", description)
    group.add_argument(
        "--model",
        metavar="FILE",
        help="model file (YAML, impactosc-model/1) whose parameters replace model BC's; parameters it leaves "
        "out keep model BC's values",
    )
    group.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help=f"set one model parameter (SI units; NAME one of {MODEL_NAMES}), applied after --model; "
        "repeatable, e.g. --param k=1500 --param xI=-2.1e-3",
    )


def model_from_args(args):
    """(ModelParams, description of where they came from) of --model and --param."""
    from .model_file import resolve_model

    return resolve_model(args.model, args.param)


def _read_options(args) -> dict:
    """The read_record keywords of the options of :func:`_add_record_options`."""
    return {
        "time_column": args.column[0],
        "x_column": args.column[1],
        "units": args.units,
        "group": args.group,
        "channel": args.channel,
        "phase_channel": args.phase_channel,
        "time_channel": args.time_channel,
        "phase_units": args.phase_units,
    }


def _read(args, omega=None):
    from .measured.records import read_record

    return read_record(args.record, omega=omega, **_read_options(args))


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
        help="integrate the model (model BC, or a model file) and write its events to an HDF5 run file",
        description="Integrate the model from (x0, v0) at t = 0 up to TRANSIENT + DURATION and write "
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
    add_model_options(sim, "The parameters of the run: model BC's, or those of --model, then each --param.")
    ext = sub.add_parser(
        "extract",
        help="extract impact events from a measured (or surrogate) displacement record",
        description="Read a record (CSV, HDF5 or TDMS; see below), validate it, and write the same event "
        "datasets as 'simulate' (impacts/t, impacts/v, penetrations/t, penetrations/h, poincare/* when omega "
        "or a phase channel is known; poincare/omega = w measured by the encoder) to an HDF5 file. Impacts "
        "are upward crossings of XI with hysteresis; their times are interpolated below the sample interval "
        "and their uncertainties stored in impacts/sigma_t.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=RECORD_FORMATS
        + "\nExamples:\n  impactosc extract examples/record_example.csv --x-impact=-2.086e-3 --output events.h5\n"
        "  impactosc extract examples/record_example.tdms --group rig --channel cart --phase-channel encoder "
        "--output events.h5\n"
        "XI, in order of precedence: --x-impact; the model's xI when --model or --param states it (a model "
        "file identified on the rig); the record's x_impact metadata; else estimated from the record's "
        "turning points near the obstacle (--x-impact-method) and printed with its sigma.",
    )
    _add_record_options(ext)
    ext.add_argument(
        "--x-impact",
        type=_finite,
        help="obstacle position XI, m (write --x-impact=-2.086e-3 for negative values; default: the model's xI "
        "when --model or --param states it, else record metadata, else estimated)",
    )
    ext.add_argument(
        "--x-impact-method",
        choices=("contact", "curvature"),
        default="contact",
        help="how XI is estimated when it is not given: 'contact' fits the contact law to the samples around "
        "every turning point (unbiased within 1.5 um at 5-10 um noise, with a stated sigma; default), "
        "'curvature' is the older estimate from the turning points' curvature (8-16 um too low, no sigma)",
    )
    ext.add_argument(
        "--contact-exponent",
        type=_exponent,
        default=1.5,
        metavar="E",
        help="exponent of the contact force in that fit: a number (default 1.5, Hertz, model BC's law) or "
        "'free' to fit it too when the rig's law is not known (a wider, honest sigma: 4-8 um per 30 s at 5 um noise)",
    )
    ext.add_argument("--output", required=True, help="HDF5 events file to write (atomically)")
    ext.add_argument("--omega", type=_finite, help="nominal forcing frequency, rad/s (overrides the record's)")
    ext.add_argument("--noise", type=_finite, help="sensor-noise std, m (default: estimated from the record)")
    ext.add_argument(
        "--sensor-delay",
        type=_finite,
        metavar="S",
        help="delay of the sensor chain, s (an anti-aliasing filter's group delay), subtracted from the sample "
        "times (default: the record's sensor_delay metadata, else 0)",
    )
    add_model_options(
        ext,
        "The model's obstacle position xI is XI when --x-impact is not given and the model file states xI "
        "(or --param xI=... sets it); no other parameter is used here.",
    )
    swe = sub.add_parser(
        "sweep-extract",
        help="cut a slow-sweep record (w drifting, one file) into the Poincare points of the Fig 2 panel",
        description="Read a record whose forcing frequency was swept slowly (a whole experimental "
        "bifurcation diagram in one file) with its encoder phase; take the Poincare points where the "
        "phase crosses 2 pi i, measure w at each from the phase, cut the record into segments of "
        "quasi-constant w (bins BIN_WIDTH wide, centred on multiples of it, with hysteresis at the edges), "
        "discard the first SETTLE s of each segment, and write the points (datasets omega = the segment's "
        "median measured w, and x, as the workflow's Fig 2 experimental panel reads them; plus t, "
        "point_omega, and per segment record_omega, n_points, segment_start, segment_stop, omega_spread) "
        "to an HDF5 file. See impactosc.measured.sweep.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=RECORD_FORMATS + "\nExample (the surrogate sweep of the README):\n"
        "  impactosc sweep-extract sweep.h5 --bin-width 0.25 --settle 10 --output fig02_experimental.h5\n"
        "Choose SETTLE a few relaxation times of the rig (model BC: 2.6 s from its damping alone) and "
        "BIN_WIDTH so that each segment keeps at least MIN_POINTS forcing periods after it.",
    )
    _add_record_options(swe)
    swe.add_argument(
        "--bin-width",
        type=_finite,
        default=0.25,
        help="width of the w bins, rad/s (default 0.25, the stepped sweep's step)",
    )
    swe.add_argument(
        "--settle",
        type=_finite,
        default=10.0,
        help="time discarded at the start of each segment, s (default 10: about 4 relaxation times of model BC)",
    )
    swe.add_argument("--min-points", type=int, default=5, help="fewest Poincare points a kept segment has (default 5)")
    swe.add_argument("--label", help="panel label stored with the points (default: the record's label)")
    swe.add_argument("--output", required=True, help="HDF5 points file to write (atomically)")
    sur = sub.add_parser(
        "surrogate",
        help="write a surrogate record: the model sampled like the rig, plus sensor noise",
        description="Simulate the model (model BC, or --model / --param) at OMEGA, sample x at RATE Hz on "
        "[TRANSIENT, TRANSIENT + DURATION], add white Gaussian noise of std NOISE and write it in the measured-record format (.csv or .h5), "
        "labelled 'surrogate (model + noise)'. With --ramp instead of --omega: a slow sweep in one record, "
        "w ramped linearly from W_START to W_STOP over DURATION after TRANSIENT s at W_START, with the "
        "forcing phase (column/dataset 'phase', rad) as an encoder measures it. The core takes w as a "
        "constant of a run, so the ramp is chained one-period runs (state and phase continuous, w stepping "
        "by dw/dt times a period); see impactosc.measured.surrogate.surrogate_driven.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Examples:\n  impactosc surrogate --omega 40.86 --transient 100 --duration 400 --output rec.h5\n"
        "  impactosc surrogate --ramp 20 45 --transient 200 --duration 2500 --encoder-counts 4096 --output sweep.h5",
    )
    what = sur.add_mutually_exclusive_group(required=True)
    what.add_argument("--omega", type=_finite, help="forcing frequency w in rad/s (> 0)")
    what.add_argument(
        "--ramp",
        type=_finite,
        nargs=2,
        metavar=("W_START", "W_STOP"),
        help="sweep w linearly from W_START to W_STOP rad/s over DURATION (0.01 rad/s^2 is quasi-stationary)",
    )
    sur.add_argument(
        "--encoder-counts",
        type=int,
        metavar="N",
        help="with --ramp: phase read by an encoder of N counts per revolution (default: exact phase)",
    )
    sur.add_argument("--transient", type=_finite, required=True, help="time discarded before sampling, s")
    sur.add_argument("--duration", type=_finite, required=True, help="sampled time, s")
    sur.add_argument("--rate", type=_finite, default=2000.0, help="sample rate, Hz (default 2000)")
    sur.add_argument("--noise", type=_finite, default=5e-6, help="sensor-noise std, m (default 5e-6)")
    sur.add_argument(
        "--mismatch",
        default="",
        help="relative parameter changes applied to the model, e.g. 'c=0.02,T=-0.05' (default none)",
    )
    sur.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    real = sur.add_argument_group(
        "sensor realism (all off by default; see impactosc.measured.surrogate.SurrogateOptions)"
    )
    real.add_argument(
        "--lowpass",
        dest="lowpass_hz",
        type=_finite,
        default=0.0,
        metavar="HZ",
        help="causal Butterworth anti-aliasing filter with this cutoff; its delay is written to the record's "
        "metadata as sensor_delay and extraction subtracts it",
    )
    real.add_argument("--lowpass-order", type=int, default=4, help="order of that filter (default 4)")
    real.add_argument("--drift", type=_finite, default=0.0, metavar="M", help="std of a slow zero drift, m")
    real.add_argument(
        "--drift-time", type=_finite, default=10.0, metavar="S", help="correlation time of the drift, s (default 10)"
    )
    real.add_argument("--clock-jitter", type=_finite, default=0.0, metavar="S", help="std of sample-time errors, s")
    real.add_argument("--quantum", type=_finite, default=0.0, metavar="M", help="ADC step, m (every sample rounded)")
    sur.add_argument("--units", choices=("m", "mm", "um"), default="m", help="CSV displacement units (default m)")
    sur.add_argument("--output", required=True, help="record file to write (.csv or .h5)")
    add_model_options(
        sur,
        "The parameters the record is drawn from, before --mismatch: model BC's, or those of --model, then each "
        "--param; the record's metadata names them (model_source).",
    )
    _add_identify_parser(sub)
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


IDENTIFY_EPILOG = """
What is fitted: k/m, c/m, T/m, m0e/m, kI/m, b, n3 and xI, per unit mass because a displacement
record sees only forces over m. Not identifiable: the mass (--mass, else the stated model's m,
scales the ratios into N/m, N s/m, ...); eps (friction regularisation) and the Hertz exponents
n1 = n2 keep the stated model's values. A quantity the records do not pin (no impacts: kI/m, b,
n3) is fixed at the stated value, and the summary says why.
The model file (impactosc-model/1, YAML) holds every parameter with its unit and standard error,
the fixed ones and why, the correlation of the fitted ones, the records (with sha256), the fit's
residual and the package version; --model FILE gives it to every command, and the workflow takes
it with --config model_file=FILE.
Examples:
  impactosc identify examples/record_example.tdms --group rig --channel cart --phase-channel encoder --output rig.yaml
  impactosc identify run1.h5 run2.h5 --mass 9.1 --fix T/m=0 --table rig.md --output rig.yaml
  impactosc simulate --omega 40.86 --transient 100 --duration 400 --model rig.yaml --output rig_chaos.h5
"""


def _add_identify_parser(sub) -> None:
    """The identify command's options (records, stated model, what is fixed, outputs)."""
    from .identification.identify import STAGES
    from .identification.parameters import NAMES, UNITS

    idp = sub.add_parser(
        "identify",
        help="identify the model's parameters from displacement records and write a model file",
        description="Fit model BC's parameters per unit mass to displacement records by multiple shooting: "
        "the records are cut into windows of a few forcing periods, each window's start state is fitted with "
        "the parameters and the core integrates every window; standard errors come from the Jacobian of the "
        "residuals. Each record needs the forcing's phase: an encoder channel (--phase-channel) or omega in "
        "its metadata (t = 0 at the forcing's phase 0).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=RECORD_FORMATS + IDENTIFY_EPILOG,
    )
    _add_record_options(idp, many=True)
    idp.add_argument("--output", required=True, metavar="MODEL.yaml", help="model file to write (atomically)")
    idp.add_argument(
        "--mass",
        type=_finite,
        metavar="KG",
        help="the cart's mass, kg (default: the stated model's m); not identifiable from displacement, it "
        "turns the fitted ratios into the model's parameters",
    )
    idp.add_argument(
        "--fix",
        action="append",
        default=[],
        metavar="NAME[=VALUE]",
        help="keep a fitted quantity fixed at VALUE (per unit mass, in "
        + ", ".join(f"{nm} {u}" for nm, u in zip(NAMES, UNITS))
        + ") or, without VALUE, at the stated model's value; repeatable, e.g. --fix b=0 (Hertz contact) "
        "--fix T/m=0 (no dry friction)",
    )
    idp.add_argument(
        "--stages",
        type=_finite,
        nargs="+",
        default=STAGES,
        metavar="P",
        help="window lengths of the successive fits, forcing periods; each starts from the one before, the "
        f"last gives the estimate and its errors (default {' '.join(f'{p:g}' for p in STAGES)})",
    )
    idp.add_argument("--table", metavar="FILE", help="also write the parameter table (.csv or .md)")
    idp.add_argument(
        "--choose-model",
        metavar="FILE",
        help="also compare the contact laws (Hertz b = 0, Hunt-Crossley n3 = 1, model BC) with and without "
        "dry friction on held-out windows and write the ranked table (.md or .csv); six more fits, about six "
        "times as long",
    )
    idp.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    add_model_options(
        idp,
        "The stated model: m (unless --mass), eps, n1, n2 and the value of every quantity fixed (--fix) or not "
        "identifiable from the records; model BC's, or those of --model, then each --param.",
    )


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

    check_writable(args.output)
    x_impact, x_impact_source = _model_x_impact(args) if args.x_impact is None else (args.x_impact, None)
    rec = _read(args, omega=args.omega)
    options = ExtractOptions(
        noise=args.noise,
        x_impact_method=args.x_impact_method,
        contact_exponent=args.contact_exponent,
        delay=args.sensor_delay,
    )
    if x_impact is None and "x_impact" not in rec.meta and args.x_impact_method == "contact":
        minutes = (rec.t[-1] - rec.t[0]) / 60.0
        print(
            f"{args.record}: no x_impact given; fitting the contact law to the record's turning points "
            f"(about {5 * minutes * (rec.t.size / (rec.t[-1] - rec.t[0])) / 2000:.0f} s for {minutes:.1g} min of record)",
            file=sys.stderr,
        )
    events, attrs = extract_events(rec, x_impact, options)
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


def _model_x_impact(args) -> tuple[float | None, str | None]:
    """(xI, where from) of the model when --model or --param states xI (a model file's own xI,
    not model BC's filling in for it), else (None, None): the record or the estimate decides."""
    if args.model is None and not args.param:
        return None, None
    from .model_file import read_model_file

    params, source = model_from_args(args)
    by_param = any(item.partition("=")[0].strip() == "xI" for item in args.param)
    if by_param or (args.model is not None and "xI" not in read_model_file(args.model).defaulted):
        return params.xI, f"the model's xI, {source}"
    return None, None


def _sweep_extract(args) -> int:
    from .files import check_writable
    from .measured.sweep import sweep_segments, write_sweep_points

    check_writable(args.output)
    rec = _read(args)
    points, info = sweep_segments(rec, args.bin_width, args.settle, min_points=args.min_points)
    write_sweep_points(args.output, points, info, label=args.label or rec.label, sources=[args.record])
    print(
        f"{args.output}: {info['n_segments']} segments of w {points['record_omega'].min():.4g}.."
        f"{points['record_omega'].max():.4g} rad/s, {points['x'].size} Poincare points "
        f"(of {info['n_points_total']}; {info['n_points_settling']} discarded while settling, "
        f"{info['n_segments_dropped']} segments with fewer than {info['min_points']} points dropped)"
    )
    return 0


def _progress(args, command: str):
    """A progress callback printing to stderr, or a silent one with --quiet."""
    if args.quiet:
        return lambda msg: None
    return lambda msg: print(f"impactosc {command}: {msg}", file=sys.stderr, flush=True)


def _stated_model(args):
    """(ModelParams, description) of --model / --param, with the mass of --mass."""
    import dataclasses

    params, source = model_from_args(args)
    if args.mass is not None:
        try:
            params = dataclasses.replace(params, m=args.mass)
        except ValueError as exc:
            raise ValueError(f"--mass {args.mass:g}: {exc}") from None
        source += f", m = {args.mass:g} kg (--mass)"
    return params, source


def _fixed_quantities(items, base) -> dict:
    """name -> value (None: the stated model's) of the --fix items; errors name the item."""
    import dataclasses

    from .identification.parameters import FIELDS, NAMES, PER_MASS
    from .names import closest_name

    fixed = {}
    for item in items:
        name, eq, text = (part.strip() for part in item.partition("="))
        if name not in NAMES:
            guess = NAMES[FIELDS.index(name)] if name in FIELDS else closest_name(name, NAMES)
            hint = f"did you mean {guess!r}?" if guess else f"choose from {' '.join(NAMES)}"
            raise ValueError(f"--fix {item}: unknown quantity {name!r} ({hint})")
        value = None
        if eq:
            try:
                value = _finite(text)
            except argparse.ArgumentTypeError as exc:
                raise ValueError(f"--fix {item}: {exc}") from None
            field = FIELDS[NAMES.index(name)]
            scaled = value * (base.m if PER_MASS[NAMES.index(name)] else 1.0)
            try:
                dataclasses.replace(base, **{field: scaled})
            except ValueError as exc:
                raise ValueError(f"--fix {item} ({field} = {scaled:.6g} at m = {base.m:g} kg): {exc}") from None
        fixed[name] = value
    return fixed


def _check_identify_outputs(args) -> None:
    """Refuse unknown table formats, clashing or unwritable outputs before any fitting."""
    from pathlib import Path

    from .files import check_writable

    paths = [args.output]
    for option, path in (("--table", args.table), ("--choose-model", args.choose_model)):
        if path is not None:
            if Path(path).suffix.lower() not in (".csv", ".md"):
                raise ValueError(f"{option} {path}: the table is written as .csv or .md")
            paths.append(path)
    if len({Path(path).resolve() for path in paths}) < len(paths):
        raise ValueError("--output, --table and --choose-model name the same file")
    for path in paths:
        check_writable(path)


def _check_forcing_phase(records) -> None:
    """Every record states omega or carries a phase: the fit needs the forcing's phase."""
    for rec in records:
        if rec.omega is None and rec.phase is None:
            raise ValueError(
                f"{rec.path}: neither omega nor a forcing phase; identification needs the forcing's phase "
                "(declare omega in the record's metadata, with t = 0 at the forcing's phase 0, or give "
                "--phase-channel)"
            )


def _write_rows(path, rows, markdown: str, sources) -> None:
    """A table as Markdown (.md) or CSV."""
    from .files import write_table, write_text

    if str(path).lower().endswith(".md"):
        write_text(path, markdown)
    else:
        write_table(path, rows, sources=sources)


def _identify_summary(args, ident, rows, source: str, choice) -> str:
    """What was written and identified: residual, every parameter with its error, what was fixed and why."""
    p = ident.params
    lines = [
        f"{args.output}: model identified from {len(ident.records)} record(s) in {ident.seconds:.1f} s; "
        f"residual rms {ident.noise * 1e6:.3f} um ({ident.windows.size} windows of {ident.periods:g} forcing "
        f"periods, {'converged' if ident.fit.converged else 'NOT converged'})"
    ]
    for r in rows:
        value = f"{r['field']:<4} = {r['field_value']:.6g}"
        unit = "" if r["unit"] == "-" else f" {r['unit']}"
        if r["status"] == "fitted":
            lines.append(f"  {value} +- {r['field_stderr']:.2g}{unit}")
        else:
            lines.append(f"  {value}{unit}, fixed: {r['status']}")
    lines.append(f"  m    = {p.m:.6g} kg, given ({source}): the mass is not identifiable from displacement")
    lines.append(f"  eps = {p.eps:g} m/s, n1 = {p.n1:g}, n2 = {p.n2:g}: fixed at the stated model's values")
    if args.table:
        lines.append(f"{args.table}: parameter table")
    if choice:
        lines.append(
            f"{args.choose_model}: the records support {choice[0]['law']}, {choice[0]['friction']} "
            f"(smallest BIC of {len(choice)} candidates)"
        )
    return "\n".join(lines)


@contextlib.contextmanager
def _warning_lines(command: str):
    """Each warning once, on one line of stderr ('impactosc COMMAND: warning: ...'), not with the
    library's source line."""
    seen = set()

    def show(message, *_):
        if str(message) not in seen:
            seen.add(str(message))
            print(f"impactosc {command}: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        yield


def _identify(args) -> int:
    with _warning_lines("identify"):
        return _identify_run(args)


def _identify_run(args) -> int:
    from .identification import identify
    from .identification.choice import candidates, choice_markdown, choose_model
    from .identification.report import parameter_markdown, parameter_table, write_identified_model
    from .measured.records import read_records

    _check_identify_outputs(args)
    if not all(periods > 0 for periods in args.stages):
        raise ValueError(f"--stages: window lengths must be > 0 forcing periods, got {args.stages}")
    base, source = _stated_model(args)
    fixed = _fixed_quantities(args.fix, base)
    records = read_records(args.record, **_read_options(args))
    _check_forcing_phase(records)
    say = _progress(args, "identify")
    stages = tuple(args.stages)
    ident = identify(records, base=base, fixed=fixed, stages=stages, progress=say)
    for item in args.fix:
        ident.fixed[item.partition("=")[0].strip()] = f"held fixed (--fix {item})"
    choice = None
    if args.choose_model:
        say(
            f"model choice: {len(candidates())} candidate fits (contact law x dry friction), each about as long "
            f"as the identification ({ident.seconds:.0f} s)"
        )
        with warnings.catch_warnings():  # candidates the records reject stray far out: their fit says so
            warnings.simplefilter("ignore")
            choice = choose_model(records, base=base, stages=stages, progress=say)
        if not any(row["n_held_out"] for row in choice):
            print(
                "impactosc identify: warning: the records are too short to hold blocks of windows out of the fits; "
                "the model choice rests on AIC and BIC alone",
                file=sys.stderr,
            )
    # written only now: an error or an interrupt above leaves no output behind
    write_identified_model(args.output, ident)
    rows = parameter_table(ident)
    if args.table:
        _write_rows(args.table, rows, parameter_markdown(rows, ident), args.record)
    if choice:
        _write_rows(args.choose_model, choice, choice_markdown(choice), args.record)
    print(_identify_summary(args, ident, rows, source, choice))
    if not ident.fit.converged:
        print(
            "impactosc identify: warning: the last stage did not converge; the model file is written but its "
            "values and errors are not an estimate (is the forcing's phase right? try an encoder channel, "
            "shorter --stages or longer records)",
            file=sys.stderr,
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
    from .measured.surrogate import REALISM_FIELDS, SurrogateOptions, surrogate_ramp, surrogate_record

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
    "config-docs": _config_docs,
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
