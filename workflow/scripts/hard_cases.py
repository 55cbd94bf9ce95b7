"""Every hard case at full size: the table of checks.

Reads input.cache, input.checks (the impact checks the paper's tier ran: the table's first rows) and
params.hc (config hard_cases); writes output.csv (one row per check: case, check, measured, bound, unit,
passed, detail) and a log of every measurement.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("hard_cases")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_table, write_table
from impactosc_bench.hardcases import run_all


def main(hc, checks, out):
    rows = run_all(hc, log=logging.info, impact_rows=read_table(checks))
    write_table(out, rows, sources=checks)
    failed = [r["check"] for r in rows if r["passed"] in (False, "no")]
    logging.info("%d checks, %d failed%s", len(rows), len(failed), "".join(f"\n  FAILED: {c}" for c in failed))


main(snakemake.params.hc, snakemake.input.checks, snakemake.output.csv)
