"""Continue one branch segment of periodic orbits (config periodic_orbits.segments.<name>).

Reads input.cache, params (spec, ds, tol, settle_periods, model) and, for a doubled segment, input.parent;
writes output.segment (JSON: orbits in branch order, located special points, why each end stopped).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("orbit_segment", segment="period1")
configure_logging(snakemake)

import logging

from impactosc.dynamics.branch_segments import seed_from_rest, trace_segment
from impactosc.io.files import read_json, write_json
from impactosc.model.parameters import ModelParams

NEAR = 0.5  # rad/s: a parent's doubling farther than this from `near` is not the one meant


def main(inp, params, name, out):
    spec, model = params.spec, ModelParams(**params.model)
    options = dict(ds=params.ds, w_range=tuple(spec["w_range"]), max_points=spec["max_points"], params=model,
                   tol=params.tol, log=lambda m: logging.info("%s: %s", name, m))  # fmt: skip
    sources = []
    if "seed" in spec:
        seed = spec["seed"]
        logging.info("%s: seed from rest at w = %s, period %d", name, seed["omega"], seed["n_periods"])
        orbit = seed_from_rest(seed["omega"], seed["n_periods"], model, settle_periods=params.settle_periods)
        result = trace_segment(seed=orbit, **options)
    else:
        parent, near = spec["doubling_of"]["segment"], spec["doubling_of"]["near"]
        parent_file = read_json(inp.parent)
        doublings = [
            s for s in parent_file["special_points"]
            if s["kind"] == "period_doubling" and s["located"] and abs(s["omega"] - near) <= NEAR
        ]  # fmt: skip
        sources = [inp.parent]
        if not doublings:
            # e.g. other model parameters, or a parent that is empty itself: an empty segment
            # that says why, rather than a failed workflow
            why = f"segment {parent!r} has no located period doubling within {NEAR} rad/s of {near}"
            logging.warning("%s: %s; nothing to follow", name, why)
            empty = {"n_periods": 2 * parent_file["n_periods"], "points": [], "special_points": [],
                     "stops": {"start": why, "end": why}, "wall_seconds": 0.0, "cpu_seconds": 0.0}  # fmt: skip
            write_json(out.segment, {"segment": name, "spec": spec, **empty}, sources=sources)
            return
        at = min(doublings, key=lambda s: abs(s["omega"] - near))
        logging.info("%s: doubled branch of %s's doubling at w = %.10f", name, parent, at["omega"])
        result = trace_segment(parent_doubling=at, **options)
    for s in result["special_points"]:
        logging.info("%s: %s at w = %.10f%s", name, s["kind"], s["omega"], "" if s["located"] else " (not located)")
    logging.info("%s: %d points, %.1f s (%.1f CPU s)", name, len(result["points"]), result["wall_seconds"],
                 result["cpu_seconds"])  # fmt: skip
    write_json(out.segment, {"segment": name, "spec": spec, **result}, sources=sources)


main(snakemake.input, snakemake.params, snakemake.wildcards.segment, snakemake.output)
