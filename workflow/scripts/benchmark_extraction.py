"""Throughput and peak memory of extracting long records, against sample rate and record length.

Reads input.cache, params.be (config benchmark_extraction), params.model and params.scratch (where the records
go); writes output.csv (a row per format x rate x duration x path), output.md, output.png and output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("benchmark_extraction")
configure_logging(snakemake)

import logging
import tempfile
from pathlib import Path

from impactosc.io.files import write_table, write_text
from impactosc.model.parameters import ModelParams
from impactosc_bench.extraction_scaling import extraction_scaling, scaling_figure, scaling_markdown, startup_floor

be = snakemake.params.be
scratch = Path(snakemake.params.scratch)
scratch.mkdir(parents=True, exist_ok=True)
# every record is deleted after its case, the folder at the end (also when a case fails)
with tempfile.TemporaryDirectory(prefix="extraction_scaling_", dir=scratch) as tmp:
    floor = startup_floor(tmp)
    logging.info(f"startup floor: {floor.wall_s:.2f} s, peak RSS {floor.peak_rss / 1e6:.0f} MB")
    rows = extraction_scaling(
        be["formats"],
        be["rates"],
        be["durations"],
        tmp,
        log=logging.info,
        omega=be["omega"],
        transient=be["transient"],
        noise=be["noise"],
        seed=be["seed"],
        params=ModelParams(**snakemake.params.model),
        in_memory_max_samples=be["in_memory_max_samples"],
        cold_cache=be["cold_cache"],
    )
write_table(snakemake.output.csv, rows)
write_text(snakemake.output.md, scaling_markdown(rows, be, floor))
scaling_figure(rows, snakemake.output.png, snakemake.output.pdf, be["goal"])
logging.info(f"wrote {snakemake.output.md}")
