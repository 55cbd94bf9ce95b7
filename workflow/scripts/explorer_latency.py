"""The live explorer's waits, through the scheduler its page uses.

Reads input.cache, params.repeats and params.columns (of the diagram); writes output.md (the table, with the targets).

A new w's attractor, a diagram's first columns and the whole diagram, with as many worker processes as
the job has threads (at least the page's two).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("explorer_latency")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_text
from impactosc_bench.explorer_latency import markdown, measure_latency

workers = max(2, snakemake.threads)  # the page's default pool
rows = measure_latency(snakemake.params.repeats, workers, snakemake.params.columns)
write_text(snakemake.output.md, "# Explorer latency\n\n" + markdown(rows, workers))
for r in rows:
    logging.info(f"{r['what']}: median {r['median']:.3f} s, worst {r['worst']:.3f} s")
