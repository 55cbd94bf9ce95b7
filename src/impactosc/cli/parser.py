"""The command line's parsers, all of them: one function per command, each with its help and
examples (the commands themselves run in cli.main and, for identify, cli.identify)."""

from __future__ import annotations

import argparse
import re

from impactosc import __version__
from impactosc.cli.attractors import add_attractors_parser
from impactosc.cli.options import (
    RECORD_FORMATS,
    add_model_options,
    add_noise_options,
    add_record_options,
    contact_exponent,
    finite_number,
)
from impactosc.model.parameters import model_bc_summary

EPILOG = f"""\
Units: SI throughout (s, m, m/s, rad/s). Model parameters are model BC of the paper
({model_bc_summary()}, ...; see impactosc.model.parameters.ModelParams)
unless --model / --param change them; the run file's attributes record every parameter
(param_*) and where they came from (model_source).
Bad values get one line, "impactosc simulate: error: --option: ...", exit status 2 and no file;
negative numbers may follow their option after a space (--x0 -2e-3). A run longer than a few
seconds says its expected wall time on stderr; SIGTERM or Ctrl-C leave no file.
Examples (the chaotic scene of the paper, ~2875 impacts; the same with a rig's model file):
  impactosc simulate --omega 40.86 --transient 100 --duration 400 --output chaos.h5
  impactosc simulate --omega 40.86 --transient 100 --duration 400 --model rig.yaml --param k=1500 --output rig.h5
"""


#: A negative number in any notation Python's float reads (-2e-3, -.5, -1E+3, -inf, -nan): such
#: an argument is a value, never an option (argparse alone knows -2 and -0.5 only, and takes
#: -2e-3 for an option). -inf and -nan are then refused by the options' finite check.
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """An ArgumentParser that reads ``--x0 -2e-3`` as the option and its value (its
    subcommands' parsers are of the same class)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="impactosc",
        description="Forced impacting oscillator (model BC): event-exact simulation and impact statistics.",
    )
    parser.add_argument("--version", action="version", version=f"impactosc {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    _add_simulate_parser(sub)
    _add_extract_parser(sub)
    _add_sweep_extract_parser(sub)
    _add_surrogate_parser(sub)
    _add_identify_parser(sub)
    _add_predict_parser(sub)
    _add_stats_parser(sub)
    _add_explore_parser(sub)
    add_attractors_parser(sub)
    return parser


def _add_stats_parser(sub) -> None:
    """The stats command: the statistics of a train, and its distances to another."""
    from impactosc.cli.stats import EXPLAINED, TEST_TEXT
    from impactosc.statistics.train_surrogates import SURROGATE_KINDS

    lines = "\n".join(f"  {name:<19} {text}" for name, text in EXPLAINED)
    sta = sub.add_parser(
        "stats",
        help="the paper's statistics and the local ones (CV2, LV, LvR, serial correlations) of an impact train; "
        "with --against, the ISI- and SPIKE-distances to another train and their surrogate tests",
        description="Read the impact train of a run file (impactosc simulate) or of a record's events "
        "(impactosc extract), compute the statistics of the paper's section 2.2 with the workflow's own "
        "functions and the local measures beyond it, print a short table and, with --json, write every "
        "number. The statistics (keys of the JSON file):\n" + lines + "\n\nWith --against OTHER.h5: both "
        "trains' statistics side by side, and the ISI-distance (Kreuz 2007) and SPIKE-distance (Kreuz 2013) "
        "of the two trains on a common span, each tested against " + " and ".join(SURROGATE_KINDS) + " "
        "surrogates (joint_isi: each impact re-drawn between its neighbours from the train's joint "
        "distribution of successive intervals; shuffled: the intervals in random order). The test: " + TEST_TEXT + ".",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Examples:\n  impactosc simulate --omega 40.86 --transient 100 --duration 400 --output chaos.h5\n"
        "  impactosc stats chaos.h5 --json chaos_stats.json\n"
        "  impactosc extract rig.csv --output events.h5\n  impactosc stats events.h5 --against chaos.h5 --json rig_vs_model.json",
    )
    sta.add_argument("train", metavar="TRAIN.h5", help="a run file or an extracted events file (impacts/t)")
    sta.add_argument("--json", metavar="FILE", help="also write every number to this JSON file (atomically)")
    sta.add_argument(
        "--against",
        metavar="OTHER.h5",
        help="a second train: its statistics beside the first's, and the two trains' distances with their tests",
    )
    sta.add_argument(
        "--align",
        choices=("start", "absolute"),
        default="start",
        help="the common span of --against: each train from its own span's start, cut to the shorter (start, "
        "default), or the times as recorded on the overlap of the spans (absolute: keeps the forcing's phase "
        "when both start at phase 0)",
    )
    sta.add_argument(
        "--refractoriness",
        type=finite_number,
        default=5e-3,
        metavar="R",
        help="LvR's refractoriness R, s (default 0.005: Shinomoto et al. 2009 and Elephant's default)",
    )
    sta.add_argument(
        "--surrogates",
        type=int,
        default=99,
        metavar="N",
        help="surrogates of each train per kind for the distance tests (default 99; p-values are at least 1/(2N+1))",
    )
    sta.add_argument("--seed", type=int, default=0, help="seed of every surrogate (default 0)")


def _add_explore_parser(sub) -> None:
    """The explore command: the live explorer in the browser."""
    from impactosc.cli.explore import port_number, worker_count

    exp = sub.add_parser(
        "explore",
        help="explore the dynamics live in the browser: bifurcation diagram, attractors, periodic orbits",
        description="Start a local web app (a Bokeh server; extra 'explore') and print its address: the "
        "bifurcation diagram (Poincare x or the intervals S_j against w, either sweep direction; box-zoom "
        "recomputes the window), the attractor of a clicked or typed w (time series, phase portrait, Poincare "
        "points, impact map; a periodic one shot with its Floquet multipliers), sliders and fields for the "
        "model's parameters, a record's Poincare points overlaid, and a button that writes the view as a config "
        "file with the snakemake command that draws it as a figure.\n\n"
        "The address carries a random token (?token=...): the page opens only with it, so other users of the "
        "machine cannot use the explorer. Records are read only from the --data-dir directories and the "
        "--record file. A worker process that dies (killed, out of memory) is replaced: the page says its "
        "request failed and why, and the next request runs.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Examples:\n  impactosc explore\n  impactosc explore --model rig.yaml --record examples/record_example.csv "
        "--port 5007 --no-browser\n  impactosc explore --data-dir records --data-dir ~/rig/runs",
    )
    exp.add_argument("--record", metavar="FILE", help="a record (.csv, .h5, .tdms) whose Poincare points are overlaid")
    exp.add_argument(
        "--data-dir",
        metavar="DIR",
        action="append",
        help="a directory the page may load records from (repeatable; default the current directory); a path "
        "that resolves outside them (symbolic links followed) is refused",
    )
    exp.add_argument(
        "--port", type=port_number, default=5006, help="local port to serve on, 0..65535 (default 5006; 0: a free one)"
    )
    exp.add_argument("--no-browser", action="store_true", help="print the address only, do not open a browser")
    exp.add_argument(
        "--no-token",
        action="store_true",
        help="serve without the token: anyone on the machine can use the page (a trusted machine only)",
    )
    exp.add_argument(
        "--w-range",
        type=finite_number,
        nargs=2,
        default=[20.0, 45.0],
        metavar=("LO", "HI"),
        help="the diagram's first window, rad/s (default 20 45)",
    )
    exp.add_argument("--columns", type=int, default=200, help="columns of the diagram (default 200)")
    exp.add_argument(
        "--omega", type=finite_number, default=40.86, help="w of the first attractor shown (default 40.86)"
    )
    exp.add_argument(
        "--workers", type=worker_count, default=2, help="worker processes, 1..the machine's cores (default 2)"
    )
    exp.add_argument(
        "--snippet",
        metavar="FILE",
        default="explore_view.yaml",
        help="where 'Write config' writes the view's config (default explore_view.yaml; never through a symbolic link)",
    )
    add_model_options(exp, "The model explored: model BC's, or those of --model, then each --param.")


def _add_predict_parser(sub) -> None:
    """The predict command: located points with standard errors from a model file."""
    pred = sub.add_parser(
        "predict",
        help="locate a model file's bifurcation points on its period-1 branch (and doubled ones), with standard errors",
        description="Continue the model's period-1 branch (seeded from rest), locate its grazings, period "
        "doublings and folds, and give each the standard error the model file's covariance implies (delta "
        "method; each point's sensitivity to every fitted parameter by implicit differentiation of the "
        "equation that locates it). A model file without a covariance (model BC's) gets the points alone.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Example (a model identified from the example record):\n"
        "  impactosc identify examples/record_example.tdms --group rig --channel cart --phase-channel encoder "
        "--output rig.yaml\n  impactosc predict rig.yaml --w-range 20 40 --output points.md\n"
        "  impactosc predict rig.yaml --max-period 4   # and the doubled branches' points up to period 4",
    )
    pred.add_argument("model_file", metavar="MODEL.yaml", help="the model file (impactosc identify writes one)")
    pred.add_argument(
        "--w-range",
        type=finite_number,
        nargs=2,
        default=[19.0, 45.0],
        metavar=("LO", "HI"),
        help="w range of the branch, rad/s (default 19 45)",
    )
    pred.add_argument(
        "--seed-omega",
        type=finite_number,
        metavar="W",
        help="w at which the period-1 orbit is found from rest (default: the range's middle)",
    )
    pred.add_argument(
        "--max-period",
        type=int,
        default=1,
        metavar="N",
        help="also follow the doubled branches born at the located period doublings, up to orbits of N "
        "forcing periods (2, 4, ...; default 1: the period-1 branch only)",
    )
    pred.add_argument("--output", metavar="FILE", help="also write the points as a table (.csv or .md)")
    pred.add_argument("--quiet", action="store_true", help="no progress lines on stderr")


def _add_simulate_parser(sub) -> None:
    """The simulate command: integrate the model and write its events."""
    from impactosc.core.layout import DEFAULT_STEP_BUDGET
    from impactosc.core.simulation import ALL_EVENTS, DEFAULT_ATOL, DEFAULT_RTOL

    sim = sub.add_parser(
        "simulate",
        help="integrate the model (model BC, or a model file) and write its events to an HDF5 run file",
        description="Integrate the model from (x0, v0) at t = 0 up to TRANSIENT + DURATION and write "
        "the events with t >= TRANSIENT (impact onsets, deepest penetrations, near misses, Poincare "
        "points at t = 2 pi i / omega) and an optional trajectory window to an HDF5 file.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sim.add_argument("--omega", type=finite_number, required=True, help="forcing frequency w in rad/s (> 0)")
    sim.add_argument("--transient", type=finite_number, required=True, help="time discarded before recording, s (>= 0)")
    sim.add_argument(
        "--duration",
        type=finite_number,
        required=True,
        help="recorded time after the transient, s (> 0; transient + duration <= 1e6 s, impactosc.core.simulation.MAX_T_END)",
    )
    sim.add_argument("--x0", type=finite_number, default=0.0, help="initial displacement at t = 0, m (default 0)")
    sim.add_argument("--v0", type=finite_number, default=0.0, help="initial velocity at t = 0, m/s (default 0)")
    sim.add_argument(
        "--rtol", type=finite_number, default=DEFAULT_RTOL, help=f"relative tolerance (default {DEFAULT_RTOL:g})"
    )
    sim.add_argument(
        "--atol",
        type=finite_number,
        default=DEFAULT_ATOL,
        help=f"absolute tolerance, m and m/s (default {DEFAULT_ATOL:g})",
    )
    sim.add_argument(
        "--window",
        type=finite_number,
        nargs=3,
        metavar=("T1", "T2", "DT"),
        help="also store x, v sampled at t = T1, T1+DT, ... <= T2 (absolute times, s); refused up front when "
        "its samples would not fit in memory",
    )
    sim.add_argument(
        "--events",
        default=",".join(ALL_EVENTS),
        help=f"comma-separated events to store (default: all of {','.join(ALL_EVENTS)})",
    )
    sim.add_argument("--output", required=True, help="HDF5 file to write (written atomically)")
    sim.add_argument(
        "--step-budget",
        type=finite_number,
        default=DEFAULT_STEP_BUDGET,
        metavar="N",
        help="watchdog: step attempts allowed per forcing period of progress; a run that spends "
        f"them without advancing one period stops with an error naming where (default {DEFAULT_STEP_BUDGET:g}, "
        "~10^4 times what the chaotic scene needs)",
    )
    sim.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    add_model_options(sim, "The parameters of the run: model BC's, or those of --model, then each --param.")
    add_noise_options(sim)


def _add_extract_parser(sub) -> None:
    """The extract command: events from a measured record."""
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
    add_record_options(ext)
    ext.add_argument(
        "--x-impact",
        type=finite_number,
        help="obstacle position XI, m (default: the model's xI "
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
        type=contact_exponent,
        default=1.5,
        metavar="E",
        help="exponent of the contact force in that fit: a number (default 1.5, Hertz, model BC's law) or "
        "'free' to fit it too when the rig's law is not known (a wider, honest sigma: 7-9 um per 30 s at 5 um noise)",
    )
    ext.add_argument("--output", required=True, help="HDF5 events file to write (atomically)")
    ext.add_argument("--omega", type=finite_number, help="nominal forcing frequency, rad/s (overrides the record's)")
    ext.add_argument("--noise", type=finite_number, help="sensor-noise std, m (default: estimated from the record)")
    ext.add_argument(
        "--sensor-delay",
        type=finite_number,
        metavar="S",
        help="delay of the sensor chain, s (an anti-aliasing filter's group delay), subtracted from the sample "
        "times (default: the record's sensor_delay metadata, else 0)",
    )
    add_model_options(
        ext,
        "The model's obstacle position xI is XI when --x-impact is not given and the model file states xI "
        "(or --param xI=... sets it); no other parameter is used here.",
    )


def _add_sweep_extract_parser(sub) -> None:
    """The sweep-extract command: Poincare points of a rig's sweep records."""
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
        "to an HDF5 file. See impactosc.records.slow_sweep.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=RECORD_FORMATS + "\nExample (the surrogate sweep of docs/measured.md):\n"
        "  impactosc sweep-extract sweep.h5 --bin-width 0.25 --settle 10 --output fig02_experimental.h5\n"
        "Choose SETTLE a few relaxation times of the rig (model BC: 2.6 s from its damping alone) and "
        "BIN_WIDTH so that each segment keeps at least MIN_POINTS forcing periods after it.",
    )
    add_record_options(swe)
    swe.add_argument(
        "--bin-width",
        type=finite_number,
        default=0.25,
        help="width of the w bins, rad/s (default 0.25, the stepped sweep's step)",
    )
    swe.add_argument(
        "--settle",
        type=finite_number,
        default=10.0,
        help="time discarded at the start of each segment, s (default 10: about 4 relaxation times of model BC)",
    )
    swe.add_argument("--min-points", type=int, default=5, help="fewest Poincare points a kept segment has (default 5)")
    swe.add_argument("--label", help="panel label stored with the points (default: the record's label)")
    swe.add_argument("--output", required=True, help="HDF5 points file to write (atomically)")


def _add_surrogate_parser(sub) -> None:
    """The surrogate command: a synthetic record of the model, sampled like the rig."""
    sur = sub.add_parser(
        "surrogate",
        help="write a surrogate record: the model sampled like the rig, plus sensor noise",
        description="Simulate the model (model BC, or --model / --param) at OMEGA, sample x at RATE Hz on "
        "[TRANSIENT, TRANSIENT + DURATION], add white Gaussian noise of std NOISE and write it in the measured-record format (.csv or .h5), "
        "labelled 'surrogate (model + noise)'. With --ramp instead of --omega: a slow sweep in one record, "
        "w ramped linearly from W_START to W_STOP over DURATION after TRANSIENT s at W_START, with the "
        "forcing phase (column/dataset 'phase', rad) as an encoder measures it. The core takes w as a "
        "constant of a run, so the ramp is chained one-period runs (state and phase continuous, w stepping "
        "by dw/dt times a period); see impactosc.records.surrogate.surrogate_driven.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Examples:\n  impactosc surrogate --omega 40.86 --transient 100 --duration 400 --output rec.h5\n"
        "  impactosc surrogate --ramp 20 45 --transient 200 --duration 2500 --encoder-counts 4096 --output sweep.h5",
    )
    what = sur.add_mutually_exclusive_group(required=True)
    what.add_argument("--omega", type=finite_number, help="forcing frequency w in rad/s (> 0)")
    what.add_argument(
        "--ramp",
        type=finite_number,
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
    sur.add_argument("--transient", type=finite_number, required=True, help="time discarded before sampling, s")
    sur.add_argument("--duration", type=finite_number, required=True, help="sampled time, s")
    sur.add_argument("--rate", type=finite_number, default=2000.0, help="sample rate, Hz (default 2000)")
    sur.add_argument("--noise", type=finite_number, default=5e-6, help="sensor-noise std, m (default 5e-6)")
    sur.add_argument(
        "--mismatch",
        default="",
        help="relative parameter changes applied to the model, e.g. 'c=0.02,T=-0.05' (default none)",
    )
    sur.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    real = sur.add_argument_group(
        "sensor realism (all off by default; see impactosc.records.surrogate.SurrogateOptions)"
    )
    real.add_argument(
        "--lowpass",
        dest="lowpass_hz",
        type=finite_number,
        default=0.0,
        metavar="HZ",
        help="causal Butterworth anti-aliasing filter with this cutoff; its delay is written to the record's "
        "metadata as sensor_delay and extraction subtracts it",
    )
    real.add_argument("--lowpass-order", type=int, default=4, help="order of that filter (default 4)")
    real.add_argument("--drift", type=finite_number, default=0.0, metavar="M", help="std of a slow zero drift, m")
    real.add_argument(
        "--drift-time",
        type=finite_number,
        default=10.0,
        metavar="S",
        help="correlation time of the drift, s (default 10)",
    )
    real.add_argument(
        "--clock-jitter", type=finite_number, default=0.0, metavar="S", help="std of sample-time errors, s"
    )
    real.add_argument(
        "--quantum", type=finite_number, default=0.0, metavar="M", help="ADC step, m (every sample rounded)"
    )
    sur.add_argument("--units", choices=("m", "mm", "um"), default="m", help="CSV displacement units (default m)")
    sur.add_argument("--output", required=True, help="record file to write (.csv or .h5)")
    add_model_options(
        sur,
        "The parameters the record is drawn from, before --mismatch: model BC's, or those of --model, then each "
        "--param; the record's metadata names them (model_source).",
    )


IDENTIFY_EPILOG = """
What is fitted: k/m, c/m, T/m, m0e/m, kI/m, xI and the contact law's own constants (model BC's
b and n3, a restitution law's e, Kelvin-Voigt's cI/m, Hertz none; the law is the stated model's:
--model FILE with a contact block), per unit mass because a displacement record sees only forces
over m. Not identifiable: the mass (--mass, else the stated model's m, scales the ratios into
N/m, N s/m, ...); eps (friction regularisation) and the contact exponents n1, n2 keep the stated
model's values. A quantity the records do not pin (no impacts: kI/m, b, n3) is fixed at the
stated value, and the summary says why. --choose-model fits model BC (with and without dry
friction), Hertz, Kelvin-Voigt and the restitution laws (one fit: they are one force written
in e four ways) and ranks them by BIC, with each one's error on held-out windows.
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
    from impactosc.identification.fitted_parameters import QUANTITIES, quantity_unit
    from impactosc.identification.staged_fit import STAGES

    idp = sub.add_parser(
        "identify",
        help="identify the model's parameters from displacement records and write a model file",
        description="Fit the model's parameters per unit mass to displacement records by multiple shooting: "
        "the records are cut into windows of a few forcing periods, each window's start state is fitted with "
        "the parameters and the core integrates every window; standard errors come from the Jacobian of the "
        "residuals. Each record needs the forcing's phase: an encoder channel (--phase-channel) or omega in "
        "its metadata (t = 0 at the forcing's phase 0).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=RECORD_FORMATS + IDENTIFY_EPILOG,
    )
    add_record_options(idp, many=True)
    idp.add_argument("--output", required=True, metavar="MODEL.yaml", help="model file to write (atomically)")
    idp.add_argument(
        "--mass",
        type=finite_number,
        metavar="KG",
        help="the cart's mass, kg (default: the stated model's m); not identifiable from displacement, it "
        "turns the fitted ratios into the model's parameters",
    )
    idp.add_argument(
        "--fix",
        action="append",
        default=[],
        metavar="NAME[=VALUE]",
        help="keep a fitted quantity of the stated model's contact law fixed at VALUE (per unit mass, in "
        + ", ".join(f"{nm} {quantity_unit(nm)}" for nm in QUANTITIES)
        + "; b and n3 are model BC's, the others each law's own: see impactosc identify --choose-model; a "
        "linear law's kI/m is in 1/s^2) or, "
        "without VALUE, at the stated model's value; repeatable, e.g. --fix b=0 (Hertz contact) "
        "--fix T/m=0 (no dry friction)",
    )
    idp.add_argument(
        "--stages",
        type=finite_number,
        nargs="+",
        default=STAGES,
        metavar="P",
        help="window lengths of the successive fits, forcing periods; each starts from the one before, the "
        f"last gives the estimate and its errors (default {' '.join(f'{p:g}' for p in STAGES)})",
    )
    idp.add_argument(
        "--duration",
        type=finite_number,
        metavar="S",
        help="fit only the first S seconds of each record file, read in chunks (a long record's rest is never "
        "loaded; a minute or two of a chaotic record pins the parameters; default: whole records)",
    )
    idp.add_argument("--table", metavar="FILE", help="also write the parameter table (.csv or .md)")
    idp.add_argument(
        "--choose-model",
        metavar="FILE",
        help="also compare the contact laws (model BC with and without dry friction, Hertz, Kelvin-Voigt, the "
        "restitution laws) on held-out windows and by BIC, and write the ranked table (.md or .csv); five more "
        "fits, about five times as long",
    )
    idp.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    add_model_options(
        idp,
        "The stated model: m (unless --mass), eps, n1, n2 and the value of every quantity fixed (--fix) or not "
        "identifiable from the records; model BC's, or those of --model, then each --param.",
    )
