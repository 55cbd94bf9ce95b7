"""The sensor-realism rows of the noise study (rule measured_noise_realism).

Reads snakemake.params (study: realism noise and cases, density_rate, x_impact_span; surrogate:
chaos scene, mismatch, seed; model, solver); writes snakemake.output.json (the rows) and .csv
(the same rows as table cells), the last slice of the study's outputs (measured_noise_study.py).
"""

from _logging import configure_logging

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
