"""The build-time table (rule build_times).

Reads snakemake.input.benchmarks (the benchmark file of every job of the default build) and
snakemake.params.largest (how many of the longest jobs to list); writes snakemake.output.csv
(one row per group and a total: jobs, wall and CPU time, share, longest job) and .md (the same,
then the longest jobs), with impactosc_study.build_times.
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.io.files import write_csv, write_text
from impactosc_study.build_times import build_times_markdown, group_table, largest_jobs, read_benchmark

jobs = [read_benchmark(path) for path in snakemake.input.benchmarks]
groups = group_table(jobs)
write_csv(snakemake.output.csv, groups, floats="", sources=snakemake.input.benchmarks)
write_text(snakemake.output.md, build_times_markdown(groups, largest_jobs(jobs, snakemake.params.largest)))
if groups:
    total = groups[-1]
    logging.info(f"{total['jobs']} jobs, {total['wall_s']:.1f} s of wall time, {total['cpu_s']:.1f} s of CPU time")
