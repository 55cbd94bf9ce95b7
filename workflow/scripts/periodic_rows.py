"""Rows of the paper-vs-replication table for section 2.1, Fig 4 and the grazing w.

Reads snakemake.input.stats (results/stats/periodic.json), .before
(results/stats/before_grazing.json) and .grazing
(results/stats/grazing.json); writes snakemake.output.rows (CSV, impactosc.table format).
"""

import json
from pathlib import Path

from impactosc.analysis.periodic import table_rows
from impactosc.paper.table import write_rows

with open(snakemake.input.stats) as f:  # noqa: F821
    stats = json.load(f)
with open(snakemake.input.before) as f:  # noqa: F821
    stats.update(json.load(f))
with open(snakemake.input.grazing) as f:  # noqa: F821
    grazing = json.load(f)
write_rows(snakemake.output.rows, table_rows(stats, grazing))  # noqa: F821
Path(snakemake.log[0]).write_text(f"wrote {snakemake.output.rows}\n")  # noqa: F821
