"""Draw the noise-study figure.

Reads input.json (rows of impactosc_study.noise_study.noise_study) and params.density_rate; writes
output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_figure")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json
from impactosc_study.figures import save_figure
from impactosc_study.figures.measured import noise_study_figure

rows = read_json(snakemake.input.json)["rows"]
fig = noise_study_figure(rows, snakemake.params.density_rate)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"{len(rows)} rows")
