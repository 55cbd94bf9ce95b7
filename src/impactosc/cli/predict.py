"""The predict command: a model file's bifurcation points on its period-1 branch, with the
standard errors its covariance gives them (:mod:`impactosc.identification.predictions`)."""

from __future__ import annotations

import math
import sys

#: The columns of a point's row (those of every row; a covariance adds d_<parameter>), the
#: header of a table without located points.
COLUMNS = ("segment", "kind", "omega", "n_periods", "se", "note")
#: Longest orbit followed, forcing periods. Why: each doubling's branch costs more than all before
#: it (model BC over w 20..21: 1.5 s to period 1, 4 s to 2, 9 s to 4, over 100 s to 8), and the
#: cascade's doublings crowd towards its limit point, so orbits beyond 64 periods are out of reach.
MAX_PERIOD = 64


def _predict(args) -> int:
    from impactosc.cli.identify import _write_rows, check_table_path
    from impactosc.identification.predictions import (
        covariance_source,
        field_covariance,
        points_markdown,
        predicted_points,
    )
    from impactosc.io.files import check_writable
    from impactosc.model.model_file import read_model_file
    from impactosc.model.parameters import ParameterError

    if args.output:
        check_table_path("--output", args.output)
        check_writable(args.output)
    lo, hi = args.w_range
    if not 0 < lo < hi:
        raise ParameterError("--w-range", f"--w-range must be 0 < LO < HI, got {lo} {hi}")
    if args.max_period < 1:
        raise ParameterError("--max-period", f"--max-period must be >= 1, got {args.max_period}")
    if args.max_period > MAX_PERIOD:
        raise ParameterError("--max-period", f"--max-period must be <= {MAX_PERIOD}, got {args.max_period}")
    seed = args.seed_omega if args.seed_omega is not None else 0.5 * (lo + hi)
    if not lo < seed < hi:
        raise ParameterError("--seed-omega", f"{seed:g} rad/s lies outside --w-range {lo:g} {hi:g}")
    model = read_model_file(args.model_file)
    cov = field_covariance(model)
    if cov is None:
        print(f"{args.model_file}: no covariance (a stated model): the points come without errors", file=sys.stderr)
    elif model.covariance is None:
        print(f"{args.model_file}: uncertainty from {covariance_source(model)}", file=sys.stderr)

    def say(message):
        if not args.quiet:
            print(f"predict: {message}", file=sys.stderr)

    rows = predicted_points(
        model.params, cov, w_range=(lo, hi), seed_omega=seed, max_period=args.max_period, progress=say
    )
    text = points_markdown(
        rows,
        title=f"Predicted bifurcation points of {args.model_file}",
        description=f"The period-1 branch over w in [{lo:g}, {hi:g}] rad/s"
        + (f" and its doubled branches up to period {args.max_period}" if args.max_period > 1 else "")
        + "; each point located on its branch and its "
        "standard error from the model file's covariance (delta method, sensitivities by implicit "
        "differentiation; impactosc.dynamics.point_sensitivity).",
    )
    if args.output:
        _write_rows(args.output, rows, text, [args.model_file], COLUMNS)
    for r in rows:
        se = f" +- {r['se']:.3g} rad/s (2 se: {r['omega'] - 2 * r['se']:.6f} .. {r['omega'] + 2 * r['se']:.6f})"
        print(
            f"{r['segment']}: {r['kind'].replace('_', ' ')} at w = {r['omega']:.8f}"
            + (se if math.isfinite(r["se"]) else f" ({r['note']})")
        )
    if not rows:
        print(f"no grazing, period doubling or fold on the period-1 branch in [{lo:g}, {hi:g}] rad/s")
    return 0
