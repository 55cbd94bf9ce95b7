"""Fig 3b with the largest Lyapunov exponent of each w drawn under the diagram.

Reads input.sweep (the figure's sweep) and input.lambdas (the same sweep's lambda1 CSV); writes output.png,
output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig03b_lyapunov")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.lyapunov import sweep_with_exponent

i = snakemake.input
fig = sweep_with_exponent(i.sweep[0], i.lambdas[0], quantity="isi", x_obstacle=snakemake.params.model["xI"])
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info("wrote %s", snakemake.output.png)
