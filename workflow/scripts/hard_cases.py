"""Run every hard case at full size and write the table of checks.

Reads input.cache and params.hc (config hard_cases); writes output.csv (one row per check: case, check,
measured, bound, unit, passed, detail) and a log of every measurement.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("hard_cases")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_table
from impactosc_bench.hardcases import run_all


def main(hc, out):
    rows = run_all(hc, log=logging.info)
    write_table(out, rows)
    failed = [r["check"] for r in rows if r["passed"] is False]
    logging.info("%d checks, %d failed%s", len(rows), len(failed), "".join(f"\n  FAILED: {c}" for c in failed))


main(snakemake.params.hc, snakemake.output.csv)
