"""Continue one located bifurcation in w and a second parameter (config two_parameter.curves.<name>).

Reads input.cache, input.segment (the orbit segment whose located point starts the curve) and params;
writes output.curve (JSON: the points in order, codimension-two points met, why each end stopped).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("two_parameter_curve", curve="doubling_1_2")
configure_logging(snakemake)

import logging
import time

from impactosc.dynamics.two_parameter import CurveProblem, curve_record, start_point, trace_curve
from impactosc.io.files import read_json, write_json
from impactosc.model.parameters import ModelParams

NEAR = 0.5  # rad/s: a located point farther than this from `near` is not the one meant


def main(inp, params, name, out):
    wall, cpu = time.perf_counter(), time.process_time()
    spec, model = params.spec, ModelParams(**params.model)
    segment = read_json(inp.segment)
    found = [
        s for s in segment["special_points"]
        if s["kind"] == spec["kind"] and s["located"] and abs(s["omega"] - spec["near"]) <= NEAR
    ]  # fmt: skip
    head = {"curve": name, "spec": spec, "kind": spec["kind"], "parameter": params.parameter}
    if not found:
        # other model parameters, or an empty parent segment: an empty curve that says why
        why = f"segment {spec['segment']!r} has no located {spec['kind']} within {NEAR} rad/s of {spec['near']}"
        logging.warning("%s: %s; nothing to continue", name, why)
        write_json(out.curve, {**head, "n_periods": 0, "points": [], "codim_two": [], "start": None,
                               "stops": {"start": why, "end": why}, "wall_seconds": 0.0, "cpu_seconds": 0.0},
                   sources=[inp.segment])  # fmt: skip
        return
    at = min(found, key=lambda s: abs(s["omega"] - spec["near"]))
    problem = CurveProblem(spec["kind"], params.parameter, at["n_periods"], model)
    start = start_point(problem, at["omega"], at["x0"], at["v0"])
    logging.info("%s: starts at w = %.10f (the table: %.10f)", name, start.orbit.omega, at["omega"])
    curve = trace_curve(problem, start, ds=params.ds, ds_min=params.ds_min, value_range=tuple(params.values),
                        w_range=tuple(params.w_range), max_points=params.max_points,
                        log=lambda m: logging.info("%s: %s", name, m))  # fmt: skip
    for c in curve.codim_two:
        logging.info("%s: %s at w = %.8f, %s = %.6g", name, c["what"], c["omega"], params.parameter, c["value"])
    record = {**head, **curve_record(curve),
              "start": {"table_omega": at["omega"], "omega": start.orbit.omega, "value": start.value},
              "wall_seconds": time.perf_counter() - wall, "cpu_seconds": time.process_time() - cpu}  # fmt: skip
    logging.info("%s: %d points, %.1f s (%.1f CPU s)", name, len(curve.points), record["wall_seconds"],
                 record["cpu_seconds"])  # fmt: skip
    write_json(out.curve, record, sources=[inp.segment])


main(snakemake.input, snakemake.params, snakemake.wildcards.curve, snakemake.output)
