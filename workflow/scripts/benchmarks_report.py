"""The benchmarks' report: the speeds the benchmarks tier measured and the hard cases' verdict.

Reads input.wp_headline (work-precision speed ratios), input.core_headline (the core against the compiled
peers), input.pieces (where the core's time goes, per piece) and input.hard (the hard-case table); writes
output.csv (paper-table rows) and output.md.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("benchmarks_report")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_table, write_text
from impactosc_bench.benchmarks_report import benchmark_rows, report_markdown
from impactosc_study.paper.table import to_markdown, write_rows

i = snakemake.input
rows = benchmark_rows(
    read_table(i.wp_headline),
    read_table(i.core_headline),
    read_table(i.hard),
    snakemake.params.command,
    read_table(i.pieces),
)
write_rows(snakemake.output.csv, rows, sources=[i.wp_headline, i.core_headline, i.pieces, i.hard])
write_text(snakemake.output.md, report_markdown(rows, to_markdown(rows)))
logging.info("%d rows to %s", len(rows), snakemake.output.md)
