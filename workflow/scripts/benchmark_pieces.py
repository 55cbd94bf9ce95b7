"""Where the core's time goes, piece by piece, on the chaotic scene.

Reads input.cache (the compiled core, so that no timing round compiles) and params.bp (config
benchmark_pieces); writes output.csv (per core, one row per piece, the sum
of the pieces and the core) and output.md (the tables; before and after with benchmark_pieces.against).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("benchmark_pieces")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_table, write_text
from impactosc_bench.piece_costs import measure, report, table_rows

bp = snakemake.params.bp
results = measure(bp["repeats"], bp["t_end"], bp["rtol"], bp["against"], log=logging.info)
for m in results:
    logging.info(f"{m['label']}: core {m['core_us']:.1f} us/period, pieces {m['pieces_us']:.1f}")
write_table(snakemake.output.csv, table_rows(results))
write_text(snakemake.output.md, report(results, "snakemake -j1 benchmark_pieces"))
