"""The build-time table of one tier: wall and CPU time of every job of the tier, per group.

Reads input.benchmarks (every job's benchmark file), params.largest, params.target and params.command
(the tier's target rule and the command that builds it); writes output.csv (one row per group and a
total) and output.md (the same, then the longest jobs).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("build_times", tier="paper")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_csv, write_text
from impactosc_study.build_times import build_times_markdown, group_table, largest_jobs, read_benchmark

jobs = [read_benchmark(path) for path in snakemake.input.benchmarks]
groups = group_table(jobs)
write_csv(snakemake.output.csv, groups, floats="", sources=snakemake.input.benchmarks)
p = snakemake.params
write_text(snakemake.output.md, build_times_markdown(groups, largest_jobs(jobs, p.largest), p.target, p.command))
if groups:
    total = groups[-1]
    logging.info(f"{total['jobs']} jobs, {total['wall_s']:.1f} s of wall time, {total['cpu_s']:.1f} s of CPU time")
