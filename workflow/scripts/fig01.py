"""Fig 1: schematic of the rig with the symbols of model BC.

Reads nothing; writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig01")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.schematic import fig01_rig

save_figure(fig01_rig(), snakemake.output.png, snakemake.output.pdf)
logging.info(f"wrote {snakemake.output.png} and {snakemake.output.pdf}")
