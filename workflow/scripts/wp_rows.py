"""Rows of the paper-vs-replication table from the hard cases and the work-precision run.

Reads input.hard (hard_cases.csv), input.summary (the statistics summary) and input.headline (the speed
headline); writes output.rows (impactosc_study.paper.table format).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("wp_rows")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_table
from impactosc_study.paper.rows.numerics import numerics_rows as paper_rows
from impactosc_study.paper.table import write_rows


def main(hard, summary, headline, out, command):
    rows = paper_rows(read_table(hard), read_table(summary), read_table(headline), command)
    write_rows(out, rows, sources=[hard, summary, headline])
    logging.info("%d rows to %s", len(rows), out)


main(
    snakemake.input.hard,
    snakemake.input.summary,
    snakemake.input.headline,
    snakemake.output.rows,
    snakemake.params.command,
)
