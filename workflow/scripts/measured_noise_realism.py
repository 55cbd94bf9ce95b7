"""The sensor-realism rows of the noise study.

Reads input.kernels (compiled kernels), input.cache and params (study, surrogate, model, solver); writes
output.json (the rows) and output.csv (the same rows as table cells), the last slice of the study's outputs.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_realism")
configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_csv, write_json
from impactosc.model.parameters import ModelParams
from impactosc_study.noise_study import TABLE_COLUMNS, realism_rows

p = snakemake.params
c = p.surrogate["chaos"]
t0 = time.perf_counter()
rows = realism_rows(
    c["omega"],
    c["transient"],
    c["duration"],
    float(p.study["density_rate"]),
    p.study["realism"]["noise"],
    p.study["realism"]["cases"],
    mismatch=p.surrogate["mismatch"],
    seed=p.surrogate["seed"],
    params=ModelParams(**p.model),
    x_impact_span=p.study["x_impact_span"],
    **p.solver,
)
write_json(snakemake.output.json, {"rows": rows})
write_csv(snakemake.output.csv, [{k: r.get(k, "") for k in TABLE_COLUMNS} for r in rows])
logging.info(f"{len(rows)} realism rows in {time.perf_counter() - t0:.1f} s")
