"""One two-parameter curve's band: w* and its standard error at points along the curve.

Reads input.cache, input.curve (rule two_parameter_curve), input.model (a model file with a covariance) and
params.band_points; writes output.band (JSON: w, the curve parameter's value and se of w at each chosen point).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("two_parameter_band", curve="doubling_1_2")
configure_logging(snakemake)

import logging
import time

from impactosc.identification.predictions import curve_band, read_model_with_covariance
from impactosc.io.files import read_json, write_json


def main(inp, params, name, out):
    start = time.process_time()
    curve = read_json(inp.curve)
    model, covariance = read_model_with_covariance(inp.model)
    band = curve_band(
        curve,
        model.params,
        covariance,
        max_points=params.band_points,
        progress=lambda m: logging.info("%s: %s", name, m),
    )
    seconds = time.process_time() - start
    logging.info("%s: band at %d points, %.0f CPU s", name, len(band["omega"]), seconds)
    write_json(
        out.band,
        {"curve": name, "kind": curve["kind"], "parameter": curve["parameter"], **band, "cpu_seconds": seconds},
        sources=[inp.curve, inp.model],
    )


main(snakemake.input, snakemake.params, snakemake.wildcards.curve, snakemake.output)
