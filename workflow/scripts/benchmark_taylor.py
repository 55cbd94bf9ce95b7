"""Taylor steps against the core's DOP853 steps and heyoka, piece by piece.

Reads input.cache, input.headline (benchmark_core's headline) and params.bt (config benchmark_taylor);
writes output.csv (one row per piece x method x rtol) and output.md (the table and the projections).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("benchmark_taylor")
configure_logging(snakemake)

import logging
import math

from impactosc.io.files import read_table, write_table, write_text
from impactosc_bench.taylor_pieces import (
    core_per_period,
    measure_pieces,
    projection,
    taylor_markdown,
    taylor_through_the_band,
)

bt = snakemake.params.bt
if bt["projection_rtol"] not in bt["rtols"]:
    raise ValueError(f"benchmark_taylor.projection_rtol {bt['projection_rtol']:g} is not one of rtols {bt['rtols']}")
rows = measure_pieces(bt["rtols"], bt["orders"], repeats=bt["repeats"], inner=bt["inner"])
core = core_per_period(bt["projection_rtol"])
projected = projection(rows, core)
peer = [r for r in read_table(snakemake.input.headline) if r["role"] == "fastest compiled peer"]
lead = float(peer[0]["time_over_core"]) if peer else math.nan
try:
    band = taylor_through_the_band()
except ImportError:
    band = None
for r in projected:
    logging.info(f"{r['method']}: core {r['core_us_per_period']:.1f} -> {r['projected_us_per_period']:.1f} us/period")
write_table(snakemake.output.csv, rows)
write_text(snakemake.output.md, taylor_markdown(rows, core, projected, lead, band))
