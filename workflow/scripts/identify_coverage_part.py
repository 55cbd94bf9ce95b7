"""One part of the identification coverage study: draws part, part + parts, ... of the seeds.

Reads input.kernels, input.cache, params.coverage, params.identification (stages, mass), params.model
(the truths are drawn around it, with its contact law) and wildcards.part; writes output.json (one
row per draw, impactosc_study.coverage.identification_draw).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_coverage_part", part=0)
configure_logging(snakemake)

import logging

import numpy as np

from impactosc.identification.report import stated_model
from impactosc.io.files import write_json
from impactosc_study.coverage import identification_draw

c = snakemake.params.coverage
base = stated_model(snakemake.params.identification, snakemake.params.model)
part = int(snakemake.wildcards.part)
b = c["branch"]
branch = np.arange(b["start"], b["stop"] + b["step"] / 2, b["step"])
rows = []
for seed in range(part, c["draws"], c["parts"]):
    row = identification_draw(
        seed,
        omegas=tuple(c["omegas"]),
        duration=c["duration"],
        rate=c["rate"],
        noise=c["noise"],
        spread=c["spread"],
        branch_omegas=branch,
        base=base,
        stages=snakemake.params.identification["stages"],
    )
    rows.append(row)
    logging.info(
        f"draw {seed}: {row['seconds']:.0f} s, all within 2 se: {row['all_within_2se']}, "
        f"branch within {row['branch_max_m'] * 1e6:.2f} um at {row['branch_periodic_w']} periodic w"
    )
write_json(snakemake.output.json, {"draws": rows})
