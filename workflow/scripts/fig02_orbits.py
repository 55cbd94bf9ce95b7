"""Fig 2 with the continued orbits (stable and unstable branches) over the sweep's points.

Reads input.segments (named by params.names) and input.sweeps (the figure's sweep); writes output.png,
output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig02_orbits")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.orbits import orbits_over_sweep

i, p = snakemake.input, snakemake.params
segments = dict(zip(p.names, i.segments, strict=True))
fig = orbits_over_sweep(segments, i.sweeps[0], quantity="poincare", x_obstacle=p.model["xI"])
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info("wrote %s", snakemake.output.png)
