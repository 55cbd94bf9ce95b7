"""Fig 10: the ACF of the intervals (eq. 3) and its spectrum, one row per train.

Reads input.stats (statistics JSON of the model's train, then of the second train if configured); writes
output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig10")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure

fig = make_figure(10, stats=list(snakemake.input.stats))
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"fig10 from {', '.join(snakemake.input.stats)}")
