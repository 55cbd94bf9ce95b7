"""Rows of the paper-vs-replication table for section 2.1, Fig 4 and the grazing w.

Reads snakemake.input.stats (results/stats/periodic/periodic.json), .before
(results/stats/periodic/before_grazing.json) and .grazing
(results/stats/periodic/grazing.json); writes snakemake.output.rows (CSV, impactosc_study.paper.table format).
"""

from _logging import configure_logging

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
