"""Fig 2: the Poincare bifurcation diagram on the increasing sweep, with the measured diagram beside it.

Reads input.sweeps (the configured sweep), input.stats (the diagram reading: transitions to mark),
input.experimental (a measured diagram, optional) and, for a model with a covariance, input.bands (its
segments' predictions: bands and points with standard errors); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig02")
configure_logging(snakemake)

import logging

import h5py

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json
from impactosc_study.figures import model_label, save_figure
from impactosc_study.figures.bifurcation import fig02_poincare, marks_of


def main(inp, params, out):
    res, _ = load_sweep(inp.sweeps[0])
    summary = read_json(inp.stats)["sweeps"][params.names[0]]
    exp = None
    if params.experimental:
        with h5py.File(params.experimental["file"], "r") as f:
            exp = (f["omega"][()], f["x"][()], params.experimental["label"])
    w, x = res.poincare_points()
    fig = fig02_poincare(
        w,
        x,
        params.model["xI"],
        experimental=exp,
        marks=marks_of(summary),
        abandoned=summary["failed_omegas"],
        model=model_label(params.model_source),
        uncertainty=[read_json(p) for p in inp.get("bands", [])] or None,
    )
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
