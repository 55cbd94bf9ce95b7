"""The checks that no impact is missed or invented, which the paper's table cites.

Reads input.cache and params.hc (config hard_cases); writes output.csv (one row per check: case, check,
measured, bound, unit, passed, detail). Nothing here is timed.

The grazing sweep against an independent fixed-step scan and the chattering sequences against SciPy at
rtol 1e-13.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("impact_checks")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_table
from impactosc_bench.hardcases import impact_checks

rows = impact_checks(snakemake.params.hc, log=logging.info)
write_table(snakemake.output.csv, rows)
failed = [r["check"] for r in rows if r["passed"] is False]
logging.info("%d checks, %d failed%s", len(rows), len(failed), "".join(f"\n  FAILED: {c}" for c in failed))
