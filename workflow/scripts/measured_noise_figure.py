"""Draw the noise-study figure.

Reads snakemake.input.json (rows of impactosc.measured.surrogate.noise_study); writes
snakemake.output.png and .pdf (drawing in impactosc.plotting.measured).
"""

from _logging import configure_logging

configure_logging(snakemake)  # noqa: F821

import logging

from impactosc.files import read_json
from impactosc.plotting import save_figure
from impactosc.plotting.measured import noise_study_figure

rows = read_json(snakemake.input.json)["rows"]  # noqa: F821
fig = noise_study_figure(rows, snakemake.params.density_rate)  # noqa: F821
save_figure(fig, snakemake.output.png, snakemake.output.pdf)  # noqa: F821
logging.info(f"{len(rows)} rows")
