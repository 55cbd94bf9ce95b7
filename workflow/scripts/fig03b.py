"""Fig 3b: the inter-impact intervals against w on the decreasing sweep, with a zoom on the grazing.

Reads input.sweeps (the configured sweep), input.stats (the diagram reading) and, for a model with a
covariance, input.bands (its segments' predictions); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig03b")
configure_logging(snakemake)

import logging

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json
from impactosc_study.figures import model_label, save_figure
from impactosc_study.figures.bifurcation import fig03b_arguments, fig03b_isi


def main(inp, params, out):
    res, attrs = load_sweep(inp.sweeps[0])
    summary = read_json(inp.stats)["sweeps"][params.names[0]]
    w, s, kw = fig03b_arguments(res, attrs, summary, params.zoom_near, params.zoom_half_width)
    uncertainty = [read_json(p) for p in inp.get("bands", [])] or None
    fig = fig03b_isi(w, s, **kw, uncertainty=uncertainty, model=model_label(params.model_source))
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
