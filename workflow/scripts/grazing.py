"""Supplementary figure: the grazing bifurcation located (gap and impact count vs w, bracket).

Reads input.stats (results/stats/periodic/grazing.json); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("grazing")
configure_logging(snakemake)

import json
import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.periodic import grazing_evidence

with open(snakemake.input.stats) as f:
    stats = json.load(f)
fig = grazing_evidence(
    stats["per_w"]["branch"], stats["per_w"]["from_rest"], stats, stats["paper_omegas"], snakemake.params.window
)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"wrote {snakemake.output.png} and {snakemake.output.pdf}")
