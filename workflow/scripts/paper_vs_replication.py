"""Merge the per-figure-group rows into results/tables/paper_vs_replication.csv and .md."""

from pathlib import Path

from impactosc.paper.table import merge_tables

rows = merge_tables(snakemake.input.rows, snakemake.output.csv, snakemake.output.md)  # noqa: F821
Path(snakemake.log[0]).write_text(f"{len(rows)} rows\n")  # noqa: F821
