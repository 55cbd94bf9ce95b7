"""Merge the coverage draws: per parameter, how often the truth lies within 1 and 2 standard errors.

Reads input.parts; writes output.csv (the per-parameter table), output.md (with the branch comparison)
and output.draws (every draw).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_coverage")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json, write_table, write_text
from impactosc_study.coverage import coverage_markdown, coverage_table

draws = [row for path in snakemake.input.parts for row in read_json(path)["draws"]]
table = coverage_table(draws)
write_table(snakemake.output.csv, table, sources=list(snakemake.input.parts))
write_table(snakemake.output.draws, draws, sources=list(snakemake.input.parts))
write_text(snakemake.output.md, coverage_markdown(table, draws))
for r in table:
    logging.info(f"{r['parameter']}: {r['within_2se']}/{r['draws']} within 2 se")
