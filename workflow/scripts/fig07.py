"""Fig 7: the Poincare return map and the impact map S_j -> S_{j+1} of the chaotic train.

Reads input.run (the chaos scene's run file); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig07")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure

fig = make_figure(7, run=snakemake.input.run)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"fig07 from {snakemake.input.run}")
