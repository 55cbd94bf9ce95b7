"""The paper-vs-replication table: every number the paper states beside ours.

Reads input.rows (each figure group's rows), params.model (the model's source, to name) and
params.study (the folder the rows' paths name); writes
output.csv, output.md and output.html (the copy the Snakemake report shows).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("paper_vs_replication")
configure_logging(snakemake)

import logging

from impactosc_study.paper.table import merge_tables

out = snakemake.output
rows = merge_tables(
    snakemake.input.rows,
    out.csv,
    out.md,
    out.html,
    model=snakemake.params.model["description"],
    study=snakemake.params.study,
)
logging.info(f"{len(rows)} rows")
