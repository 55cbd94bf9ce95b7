"""Options the commands share: numbers, record reading (CSV, HDF5, TDMS) and the stated model.

Why a module of its own: ``impactosc.cli.main`` (every command but identify) and
``impactosc.cli.identify`` use the same option helpers; here neither imports the other.
"""

from __future__ import annotations

import argparse
import math

from impactosc.model.parameters import PARAM_UNITS

MODEL_NAMES = " ".join(PARAM_UNITS)  # every parameter a --param or --mismatch names


def finite_number(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not finite")
    return value


def contact_exponent(text: str) -> float | None:
    """A contact exponent: a number in [1, 2.5], or 'free' (None: fitted)."""
    if text.strip().lower() == "free":
        return None
    from impactosc.records.extract import CONTACT_EXPONENT_RANGE

    value = finite_number(text)
    lo, hi = CONTACT_EXPONENT_RANGE
    if not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"{text!r}: a contact exponent lies in [{lo:g}, {hi:g}] (or write 'free')")
    return value


RECORD_FORMATS = """\
Record formats (impactosc.records.formats):
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


def add_record_options(p, many: bool = False) -> None:
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
    from impactosc.model.model_file import resolve_model
    from impactosc.model.parameters import ParameterError

    try:
        return resolve_model(args.model, args.param)
    except ParameterError as exc:
        raise ParameterError("--param" if args.param else "--model", str(exc)) from None
    except ValueError as exc:  # the model file's reader names the file, the overrides the item
        if str(exc).startswith("parameter override"):
            raise ParameterError("--param", str(exc)) from None
        raise


def read_options(args) -> dict:
    """The read_record keywords of the options of :func:`add_record_options`."""
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


def open_record_args(args, omega=None):
    """The record of the options of :func:`add_record_options`, opened to be read in chunks."""
    from impactosc.records.streams import open_record_stream

    return open_record_stream(args.record, omega=omega, **read_options(args))


def add_noise_options(parser) -> None:
    """Noise in the dynamics (impactosc.model.noise), read by :func:`noise_from_args`: each option
    replaces the same process of the --model file's noise block."""
    group = parser.add_argument_group(
        "noise in the dynamics",
        "Smooth random processes (Ornstein-Uhlenbeck, drawn exactly on a grid of tau/20 and interpolated by a "
        "degree-7 spline), integrated as exactly as the noise-free model. RMS 0 (the default) is the noise-free "
        "model bit for bit. A --model file's noise block is used unless these options replace it.",
    )
    group.add_argument(
        "--motor-jitter",
        type=finite_number,
        nargs=2,
        metavar=("RMS", "TAU"),
        help="the motor's speed deviation: rms in rad/s and correlation time in s; the phase becomes "
        "phi = omega t + theta, theta' the deviation, and the unbalance's force m0e (phi'^2 sin phi - phi'' cos phi)",
    )
    group.add_argument(
        "--random-force",
        type=finite_number,
        nargs=2,
        metavar=("RMS", "TAU"),
        help="a random force on the cart: rms in N and correlation time in s",
    )
    group.add_argument(
        "--noise-seed", type=int, metavar="N", help="seed of the noise's draws (default: the model file's, else 0)"
    )
    group.add_argument(
        "--write-noise",
        action="store_true",
        help="also write the noise's draws into the run file (group noise, attribute noise_rule: the rule that "
        "turns them into the forcing), so that another solver can integrate the very same forcing",
    )


def noise_from_args(args):
    """The Noise of --model's noise block, with --motor-jitter, --random-force and --noise-seed applied."""
    from impactosc.model.model_file import read_model_file
    from impactosc.model.noise import Noise, NoiseProcess
    from impactosc.model.parameters import ParameterError

    base = read_model_file(args.model).noise if getattr(args, "model", None) else Noise()
    parts = {"motor": base.motor, "force": base.force}
    for name, option in (("motor", "motor_jitter"), ("force", "random_force")):
        given = getattr(args, option)
        if given is not None:
            parts[name] = NoiseProcess(*given)
    seed = base.seed if args.noise_seed is None else args.noise_seed
    try:
        return Noise(seed=seed, **parts)
    except ParameterError as exc:
        option = {"noise.seed": "--noise-seed"}.get(exc.name)
        if option is None:
            option = "--motor-jitter" if exc.name.startswith("noise.motor") else "--random-force"
        raise ParameterError(option, str(exc)) from None
