"""One segment's predictions with error bars: its located points with their standard errors and its band.

Reads input.cache, input.segment (an orbit segment, rule orbit_segment), input.model (a model file with a covariance) and
params.band_points; writes output.band (JSON: points, each with se and its sensitivities; band: at each chosen
orbit its w, stability, Poincare points and intervals with their standard errors).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("prediction_segment", segment="period1")
configure_logging(snakemake)

import logging
import time

from impactosc.identification.predictions import branch_band, point_errors, read_model_with_covariance
from impactosc.io.files import read_json, write_json


def main(inp, params, name, out):
    start = time.process_time()
    segment = read_json(inp.segment)
    model, covariance = read_model_with_covariance(inp.model)

    def say(message):
        logging.info("%s: %s", name, message)

    points = point_errors(segment["special_points"], model.params, covariance, progress=say)
    for p in points:
        say(f"{p['kind']} at w = {p['omega']:.8f}: se {p['se']:.3g} rad/s {p['note']}")
    band = branch_band(segment, model.params, covariance, max_points=params.band_points, progress=say)
    seconds = time.process_time() - start
    say(f"{len(points)} points, band at {len(band['omega'])} orbits, {seconds:.0f} CPU s")
    write_json(
        out.band,
        {"segment": name, "n_periods": segment["n_periods"], "fields": covariance[0], "points": points,
         "band": band, "cpu_seconds": seconds},
        sources=[inp.segment, inp.model],
    )  # fmt: skip


main(snakemake.input, snakemake.params, snakemake.wildcards.segment, snakemake.output)
