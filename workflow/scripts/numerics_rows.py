"""Rows of the paper-vs-replication table on the numerics, from checks that time nothing.

Reads input.checks (the impact checks: grazing sweep, chattering sequences) and input.summary (the
chaotic statistics against tolerance); writes output.rows (impactosc_study.paper.table format).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("numerics_rows")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_table
from impactosc_study.paper.rows.numerics import numerics_rows as paper_rows
from impactosc_study.paper.table import write_rows


def main(checks, summary, out, command):
    rows = paper_rows(read_table(checks), read_table(summary), command)
    write_rows(out, rows, sources=[checks, summary])
    logging.info("%d rows to %s", len(rows), out)


main(snakemake.input.checks, snakemake.input.summary, snakemake.output.rows, snakemake.params.command)
