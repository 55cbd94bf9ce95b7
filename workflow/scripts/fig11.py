"""Fig 11: the histogram of the maximal penetrations H_j of the model's train and its modes.

Reads input.stats (statistics JSON of the model's train); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig11")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure

fig = make_figure(11, stats=list(snakemake.input.stats))
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"fig11 from {', '.join(snakemake.input.stats)}")
