"""The two-parameter curves of a model with a covariance, each with its band (rule two_parameter_bands).

Reads input.curves and input.bands (named by params.names), params.model and params.model_source; writes
output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("two_parameter_bands")
configure_logging(snakemake)

import logging

from impactosc.dynamics.two_parameter_map import UNITS
from impactosc.io.files import read_json
from impactosc_study.figures import model_label, save_figure
from impactosc_study.figures.two_parameter import curves_band_figure


def main(inp, params, out):
    curves = {name: read_json(path) for name, path in zip(params.names, inp.curves)}
    bands = {name: read_json(path) for name, path in zip(params.names, inp.bands)}
    shown = [name for name in params.names if curves[name]["points"]]
    if not shown:
        raise ValueError("no curve has points: nothing to draw")
    parameter = curves[shown[0]]["parameter"]
    scale, unit = UNITS[parameter]
    fig = curves_band_figure(
        {name: curves[name] for name in shown},
        {name: bands[name] for name in shown},
        parameter,
        scale,
        unit,
        own=params.model[parameter],
        model=model_label(params.model_source),
    )
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
