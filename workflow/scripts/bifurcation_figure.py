"""Draw one bifurcation figure (rules fig02, fig03b, bifurcation_overlay; params.figure).

Reads input.sweeps (named by params.names), input.stats (the diagram reading: transitions to mark), for
fig02 input.experimental (a measured diagram, optional), and for fig02 and fig03b of a model with a covariance
input.bands (its segments' predictions: bands and points with standard errors); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig02")
configure_logging(snakemake)

import json
import logging
from pathlib import Path

import h5py

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json
from impactosc_study.figures import model_label, save_figure
from impactosc_study.figures.bifurcation import fig02_poincare, fig03b_arguments, fig03b_isi, marks_of, overlay_figure


def main(inp, params, out):
    stats = json.loads(Path(inp.stats).read_text())
    sweeps = {n: load_sweep(p) for n, p in zip(params.names, inp.sweeps)}
    x_obstacle = params.model["xI"]
    uncertainty = [read_json(p) for p in inp.get("bands", [])] or None
    if params.figure == "fig02":
        name = params.names[0]
        res, _ = sweeps[name]
        exp = None
        if params.experimental:
            with h5py.File(params.experimental["file"], "r") as f:
                exp = (f["omega"][()], f["x"][()], params.experimental["label"])
        w, x = res.poincare_points()
        summary = stats["sweeps"][name]
        fig = fig02_poincare(
            w,
            x,
            x_obstacle,
            experimental=exp,
            marks=marks_of(summary),
            abandoned=summary["failed_omegas"],
            model=model_label(params.model_source),
            uncertainty=uncertainty,
        )
    elif params.figure == "fig03b":
        name = params.names[0]
        res, attrs = sweeps[name]
        w, s, kw = fig03b_arguments(res, attrs, stats["sweeps"][name], params.zoom_near, params.zoom_half_width)
        fig = fig03b_isi(w, s, **kw, uncertainty=uncertainty, model=model_label(params.model_source))
    elif params.figure == "overlay":
        layers = []
        for name in params.names:
            res, attrs = sweeps[name]
            wp, x = res.poincare_points()
            wi, s = res.isi_points()
            direction = str(attrs["direction"])
            per_w = stats["sweeps"][name]["per_w"]
            layers.append((f"{name} " + r"$\omega$", wp, x, wi, s, direction, per_w["omega"], per_w["period"]))
        fig = overlay_figure(layers, x_obstacle, windows=stats["directions_differ"]["windows"])
    else:
        raise ValueError(f"unknown bifurcation figure {params.figure!r}")
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
