"""Merge the per-figure-group rows into results/tables/paper_vs_replication.csv and .md."""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.paper.table import merge_tables

rows = merge_tables(snakemake.input.rows, snakemake.output.csv, snakemake.output.md)
logging.info(f"{len(rows)} rows")
