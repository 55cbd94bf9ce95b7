"""Merge the per-figure-group rows into results/tables/paper_vs_replication.csv, .md and .html
(the copy the Snakemake report shows); the last two name the model (snakemake.params.model:
config["model_source"])."""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc_study.paper.table import merge_tables

out = snakemake.output
rows = merge_tables(snakemake.input.rows, out.csv, out.md, out.html, model=snakemake.params.model["description"])
logging.info(f"{len(rows)} rows")
