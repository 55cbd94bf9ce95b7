"""Draw the noise-study figure.

Reads snakemake.input.json (rows of impactosc.measured.noise_study.noise_study); writes
snakemake.output.png and .pdf (drawing in impactosc.plotting.measured).
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.files import read_json
from impactosc.plotting import save_figure
from impactosc.plotting.measured import noise_study_figure

rows = read_json(snakemake.input.json)["rows"]
fig = noise_study_figure(rows, snakemake.params.density_rate)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"{len(rows)} rows")
