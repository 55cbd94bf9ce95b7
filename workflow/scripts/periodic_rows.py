"""Rows of the paper-vs-replication table for section 2.1, Fig 4 and the grazing w.

Reads input.stats (periodic.json), input.before (before_grazing.json) and input.grazing (grazing.json);
writes output.rows (CSV, impactosc_study.paper.table format).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("periodic_rows")
configure_logging(snakemake)

import json
import logging

from impactosc_study.paper.rows.periodic import periodic_rows as table_rows
from impactosc_study.paper.table import write_rows

with open(snakemake.input.stats) as f:
    stats = json.load(f)
with open(snakemake.input.before) as f:
    stats.update(json.load(f))
with open(snakemake.input.grazing) as f:
    grazing = json.load(f)
write_rows(snakemake.output.rows, table_rows(stats, grazing), sources=snakemake.input)
logging.info(f"wrote {snakemake.output.rows}")
