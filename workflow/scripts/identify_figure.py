"""Draw the identification figure: measured against simulated windows, residuals, parameters.

Reads input.windows (the fitted windows) and input.csv (the parameter table); writes output.png,
output.pdf (drawing in impactosc_study.figures.identification).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_figure")
configure_logging(snakemake)

import math

from impactosc.identification.report import read_fit_windows
from impactosc.io.files import read_table
from impactosc_study.figures import save_figure
from impactosc_study.figures.identification import identification_figure

win = read_fit_windows(snakemake.input.windows)
rows = read_table(snakemake.input.csv)
for r in rows:
    for k in ("field_value", "field_stderr"):
        r[k] = float(r[k]) if r[k] not in ("", None) else math.nan
fig = identification_figure(win, rows, "Identified model BC (multiple shooting): " + ", ".join(win["labels"]))
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
