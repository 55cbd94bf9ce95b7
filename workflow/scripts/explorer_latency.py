"""The live explorer's waits, through the scheduler its page uses.

Reads input.cache, params.repeats and params.columns (of the diagram); writes output.md (the table, with
the targets).

A new w's attractor, a diagram's first columns and the whole diagram, with as many worker processes as
the job has threads (at least the page's two). The measurement runs as its own command (python -m
impactosc_bench.explorer_latency): the workers it starts import their main module afresh, which must
not be this script.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("explorer_latency")
configure_logging(snakemake)

import logging
import subprocess
import sys

p = snakemake.params
workers = max(2, snakemake.threads)  # the page's default pool
command = [sys.executable, "-m", "impactosc_bench.explorer_latency", "--repeats", str(p.repeats)]
command += ["--workers", str(workers), "--columns", str(p.columns), "--output", snakemake.output.md]
run = subprocess.run(command, capture_output=True, text=True)
logging.info("%s\n%s", " ".join(command[1:]), run.stdout)
if run.returncode:
    raise RuntimeError(f"explorer latency failed ({run.returncode}):\n{run.stderr[-3000:]}")
