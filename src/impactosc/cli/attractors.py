"""The attractors command and its parser: every attractor at one w found from random starts,
without shooting, with the share of starts each takes and the basins' entropy
(:mod:`impactosc.dynamics.attractor_survey`)."""

from __future__ import annotations

import argparse
import math
import sys
import time

from impactosc.cli.options import add_model_options, finite_number


def _attractors(args) -> int:
    from impactosc.cli.options import model_from_args
    from impactosc.dynamics.attractor_survey import random_starts, save_survey, settings_attrs, survey, survey_rows
    from impactosc.dynamics.stroboscopic import oscillator_settings
    from impactosc.io.files import check_writable
    from impactosc.model.parameters import ParameterError

    check_writable(args.output)
    if not (math.isfinite(args.omega) and args.omega > 0):
        raise ParameterError("--omega", f"--omega must be > 0 rad/s, got {args.omega}")
    if args.samples < 1:
        raise ParameterError("--samples", f"--samples must be >= 1, got {args.samples}")
    if args.boxes < 1:
        raise ParameterError("--boxes", f"--boxes must be >= 1, got {args.boxes}")
    for name, (lo, hi) in (("--x-range", args.x_range), ("--v-range", args.v_range)):
        if not lo < hi:
            raise ParameterError(name, f"{name} must be LO < HI, got {lo} {hi}")
    try:
        settings = oscillator_settings(max_iterations=args.max_iterations)
    except ValueError as exc:
        raise ParameterError("--max-iterations", str(exc)) from None
    params, source = model_from_args(args)
    starts = random_starts(args.samples, tuple(args.x_range), tuple(args.v_range), seed=args.seed)
    began = time.perf_counter()
    shown = [0]

    def progress(done, total, found):
        if not args.quiet and (10 * done // total > shown[0] or done == total):
            shown[0] = 10 * done // total
            print(
                f"attractors: {done}/{total} starts, {found} attractors so far ({time.perf_counter() - began:.0f} s)",
                file=sys.stderr,
            )

    s = survey(args.omega, starts, params, settings, boxes=args.boxes, progress=progress,
               x_range=tuple(args.x_range), v_range=tuple(args.v_range))  # fmt: skip
    save_survey(args.output, s, model_source=source, seed=args.seed, **settings_attrs(settings))
    e = s.entropy
    print(f"w = {args.omega:g} rad/s: {len(s.attractors)} attractors from {args.samples} random starts "
          f"({s.cpu_time:.1f} CPU s); written to {args.output}")  # fmt: skip
    for r in survey_rows(s):
        if r["class"] <= 0 and not r["cells"]:
            continue
        what = (
            f"  exponent {r['exponent']:+.3f}/period, Poincare point ({r['x']:.6e} m, {r['v']:.6e} m/s)"
            if r["kind"]
            else ""
        )
        print(f"  {r['name']:<34} {r['cells']:>6} starts  {100 * r['fraction']:6.2f} +- {100 * r['se']:.2f} %{what}")
    if e is None:
        print(f"  basin entropy: no box of {args.boxes} x {args.boxes} holds two starts (use fewer --boxes)")
    else:
        print(
            f"  basin entropy {e.entropy:.4f}, boundary basin entropy {e.boundary_entropy:.4f} on {e.boxes} boxes "
            f"({100 * e.boundary_fraction:.1f} % on a boundary; {'fractal' if e.fractal else 'not shown fractal'}: "
            f"S_bb {'>' if e.fractal else '<='} log 2)"
        )
    return 0


def add_attractors_parser(sub) -> None:
    """The attractors command: every attractor at one w from random starts, with its basin's share."""
    att = sub.add_parser(
        "attractors",
        help="find every attractor at one w from random starts (no shooting): period, impacts, Lyapunov "
        "exponent, the share of starts each takes, basin entropy",
        description="Draw random states (x0, v0) at phase 0 in a rectangle, iterate each on the stroboscopic "
        "map until its Poincare points recur (a periodic tail repeating to 1 nm, or a recurrent set of "
        "coarse cells, chaotic or not), and name what it settles on: every attractor with its period, impacts "
        "per period, largest Lyapunov exponent and one Poincare point; the fraction of starts each takes with "
        "its binomial standard error; the basin entropy and boundary basin entropy (Daza et al. 2016) on "
        "boxes of the rectangle, with the log 2 test for a fractal boundary. A start that settles on nothing "
        "within --max-iterations periods is counted unresolved, one the core cannot integrate as stopped.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Output (HDF5): starts (x0, v0), labels (k: attractor k; 0 unresolved; -1 stopped), iterations;\n"
        "points and owner (each attractor's Poincare points), attributes periods, impacts, exponents, entropy_*.\n"
        "Example (w = 23.05: the period-1 orbit and the period-3 orbit past the grazing, about 12 s):\n"
        "  impactosc attractors --omega 23.05 --samples 1000 --output attractors_23.05.h5",
    )
    att.add_argument("--omega", type=finite_number, required=True, metavar="W", help="forcing frequency, rad/s")
    att.add_argument("--samples", type=int, default=1000, metavar="N", help="random starts (default 1000)")
    att.add_argument("--seed", type=int, default=0, help="seed of the random starts (default 0)")
    att.add_argument("--x-range", type=finite_number, nargs=2, default=[-8e-3, 4e-3], metavar=("LO", "HI"),
                     help="x0 of the starts, m (default -8e-3 4e-3: the basin grid's)")  # fmt: skip
    att.add_argument("--v-range", type=finite_number, nargs=2, default=[-0.3, 0.3], metavar=("LO", "HI"),
                     help="v0 of the starts, m/s (default -0.3 0.3)")  # fmt: skip
    att.add_argument("--boxes", type=int, default=10, metavar="B",
                     help="the rectangle is cut into B x B boxes for the basin entropy (default 10: about 10 "
                     "starts per box of 1000)")  # fmt: skip
    att.add_argument("--max-iterations", type=int, default=2000, metavar="N",
                     help="forcing periods a start may take to settle before it counts as unresolved (default 2000)")  # fmt: skip
    att.add_argument("--output", required=True, metavar="FILE.h5", help="the survey file (HDF5)")
    att.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    add_model_options(att, "the model whose attractors are found (default model BC)")
