"""Merge the per-figure-group rows into results/tables/paper_vs_replication.csv, .md and .html
(the copy the Snakemake report shows)."""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.paper.table import merge_tables

rows = merge_tables(snakemake.input.rows, snakemake.output.csv, snakemake.output.md, snakemake.output.html)
logging.info(f"{len(rows)} rows")
