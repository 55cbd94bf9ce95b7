"""Fig 9: the ISI histogram, its kernel density, maxima and mixture fits, one panel per train.

Reads input.stats (statistics JSON of the model's train, then of the second train if configured); writes
output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig09")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure

fig = make_figure(9, stats=list(snakemake.input.stats))
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"fig09 from {', '.join(snakemake.input.stats)}")
