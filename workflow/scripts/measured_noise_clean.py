"""Each sampling rate's clean run of the noise study, read by every noise level's job.

Reads input.cache and params (rates, surrogate, model, solver); writes output.runs (one run file per rate,
in the order of the rates: the exact events and the trajectory on the rate's sampling grid).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_clean")
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
