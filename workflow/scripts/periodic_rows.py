"""Rows of the paper-vs-replication table for section 2.1, Fig 4 and the grazing w.

Reads snakemake.input.stats (results/stats/periodic/periodic.json), .before
(results/stats/periodic/before_grazing.json) and .grazing
(results/stats/periodic/grazing.json); writes snakemake.output.rows (CSV, impactosc.paper.table format).
"""

from _logging import configure_logging

configure_logging(snakemake)  # noqa: F821

import json
import logging

from impactosc.paper.rows import periodic_rows as table_rows
from impactosc.paper.table import write_rows

with open(snakemake.input.stats) as f:  # noqa: F821
    stats = json.load(f)
with open(snakemake.input.before) as f:  # noqa: F821
    stats.update(json.load(f))
with open(snakemake.input.grazing) as f:  # noqa: F821
    grazing = json.load(f)
write_rows(snakemake.output.rows, table_rows(stats, grazing), sources=snakemake.input)  # noqa: F821
logging.info(f"wrote {snakemake.output.rows}")  # noqa: F821
