"""Fig 2 or Fig 3b with the continued orbits over the sweep (rules fig02_orbits, fig03b_orbits).

Reads input.segments (named by params.names), input.sweeps (the figure's sweep) and params.figure (fig02:
Poincare points, fig03b: inter-impact intervals); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig02_orbits")
configure_logging(snakemake)

import logging

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json
from impactosc_study.figures import save_figure
from impactosc_study.figures.orbits import orbit_figure


def main(inp, params, out):
    segments = {name: read_json(path) for name, path in zip(params.names, inp.segments)}
    res, attrs = load_sweep(inp.sweeps[0])
    direction = str(attrs["direction"])
    if params.figure == "fig02":
        w, y = res.poincare_points()
        fig = orbit_figure(segments, w, y, quantity="poincare", x_obstacle=params.model["xI"],
                           title=rf"Fig 2 with the continued orbits ({direction} $\omega$ sweep in grey)")  # fmt: skip
    elif params.figure == "fig03b":
        w, y = res.isi_points()
        fig = orbit_figure(segments, w, y, quantity="isi",
                           title=rf"Fig 3b with the continued orbits ({direction} $\omega$ sweep in grey)")  # fmt: skip
    else:
        raise ValueError(f"unknown orbit figure {params.figure!r}")
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
