"""Fig 5: successive iterations S_{j+1} vs S_j and the histogram of the S_j at w = 23.03.

Reads input.run (the period-4 scene) and input.stats (periodic.json); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig05")
configure_logging(snakemake)

import json
import logging

import numpy as np

from impactosc.io.files import read_run
from impactosc_study.figures import save_figure
from impactosc_study.figures.periodic import fig05_impact_map

events, attrs, _ = read_run(snakemake.input.run)
with open(snakemake.input.stats) as f:
    numbers = json.load(f)["after_grazing"]["impact_map"]
fig = fig05_impact_map(np.diff(events["impacts"]["t"]), numbers, attrs["omega"])
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"wrote {snakemake.output.png} and {snakemake.output.pdf}")
