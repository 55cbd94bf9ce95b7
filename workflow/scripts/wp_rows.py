"""Rows of the paper-vs-replication table from the hard cases and the work-precision run.

Reads snakemake.input (hard_cases.csv, the statistics summary and the speed headline);
writes snakemake.output.rows (impactosc.paper.table.write_rows format).
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.files import read_table
from impactosc.paper.rows.numerics import numerics_rows as paper_rows
from impactosc.paper.table import write_rows


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
