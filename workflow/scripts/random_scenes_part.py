"""One part of the randomized differential test of the core: scenes part, part + parts, ... of the seed.

Reads input.cache, params.rs (seed, scenes, parts, horizon, rtol, atol) and wildcards.part; writes
output.csv (one row per scene: drawn parameters, status, impacts compared, worst difference).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("random_scenes_part", part=0)
configure_logging(snakemake)

import logging

from impactosc.io.files import write_csv
from impactosc_bench.random_scenes import compare_scene, draw_scene

rs = snakemake.params.rs
part = int(snakemake.wildcards.part)
rows = []
for i in range(part, rs["scenes"], rs["parts"]):
    row = compare_scene(draw_scene(rs["seed"], i), rs["horizon"], rtol=rs["rtol"], atol=rs["atol"])
    logging.info(
        "scene %d: %s, %d impacts over %.3g s, worst %.2g s (%s)",
        i,
        row["status"],
        row["compared"],
        row["horizon"],
        row["worst_dt"],
        row["reference"],
    )
    rows.append(row)
write_csv(snakemake.output.csv, rows, floats="")
