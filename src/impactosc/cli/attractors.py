"""The attractors command: every attractor at one w found from random starts, without shooting,
with the share of starts each takes and the basins' entropy (:mod:`impactosc.dynamics.attractor_survey`)."""

from __future__ import annotations

import math
import sys
import time


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
    print(
        f"  basin entropy {e.entropy:.4f}, boundary basin entropy {e.boundary_entropy:.4f} on {e.boxes} boxes "
        f"({100 * e.boundary_fraction:.1f} % on a boundary; {'fractal' if e.fractal else 'not shown fractal'}: "
        f"S_bb {'>' if e.fractal else '<='} log 2)"
    )
    return 0
