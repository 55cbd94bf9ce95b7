"""Each sampling rate's clean run of the noise study (rule measured_noise_clean).

Reads snakemake.params (rates; surrogate: chaos scene, mismatch; model, solver); writes one run
file per rate to snakemake.output.runs, in the order of the rates (impactosc.io.files run files:
the exact events and the trajectory on the rate's sampling grid, not compressed: temporary
files that every noise level's job reads, measured_noise_level.py, instead of simulating them).
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_run
from impactosc.model.parameters import ModelParams
from impactosc_study.noise_study import clean_runs

p = snakemake.params
c = p.surrogate["chaos"]
t0 = time.perf_counter()
runs = clean_runs(
    c["omega"],
    c["transient"],
    c["duration"],
    p.rates,
    mismatch=p.surrogate["mismatch"],
    params=ModelParams(**p.model),
    **p.solver,
)
for rate, res, path in zip(p.rates, runs, snakemake.output.runs, strict=True):
    write_run(path, res.events, res.attrs, res.trajectory, compress=False)  # temporary: read at once
    logging.info(f"{rate:g} Hz: {res.trajectory['t'].size} samples, {res.events['impacts']['t'].size} impacts")
logging.info(f"{len(runs)} clean runs in {time.perf_counter() - t0:.1f} s")
