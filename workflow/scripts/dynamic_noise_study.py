"""The dynamic-noise study's table, summary (where the ISI maxima merge, per noise) and figure.

Reads input.json (one ladder per noise); writes output.csv, output.summary, output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("dynamic_noise_study")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json, write_csv, write_json
from impactosc_study.dynamic_noise import COLUMNS, summary
from impactosc_study.figures import save_figure
from impactosc_study.figures.dynamic_noise import dynamic_noise_figure

ladders = [read_json(path) for path in snakemake.input.json]
rows = [r for ladder in ladders for r in ladder["rows"]]
write_csv(snakemake.output.csv, rows, COLUMNS, sources=snakemake.input.json)
found = summary(rows)
write_json(snakemake.output.summary, found)
save_figure(dynamic_noise_figure(ladders, found), snakemake.output.png, snakemake.output.pdf)
for name, s in found.items():
    merge = "not merged up to" if s["merge_rms"] is None else f"merged at {s['merge_rms']:g} {s['unit']} of"
    logging.info(f"{name}: ISI maxima {merge} {s['largest_rms']:g} {s['unit']} tried")
