"""One sampling rate of the noise study, at every noise level.

Reads input.kernels (compiled kernels), input.cache, params (study, surrogate, analysis, model, solver) and
wildcards.rate (Hz); writes output.json (the rows, with ISI kernel densities) and output.csv.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_rate", rate="2000")
configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_csv, write_json
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_study.noise_study import TABLE_COLUMNS, noise_study

p = snakemake.params
c = p.surrogate["chaos"]
rate = float(snakemake.wildcards.rate)
t0 = time.perf_counter()
rows = noise_study(
    c["omega"],
    c["transient"],
    c["duration"],
    [rate],
    p.study["noise"],
    analysis=AnalysisOptions.from_config(p.analysis),
    mismatch=p.surrogate["mismatch"],
    seed=p.surrogate["seed"],
    params=ModelParams(**p.model),
    x_impact_span=p.study["x_impact_span"],
    x_impact_noise=p.study["x_impact_noise"],
    **p.solver,
)
write_json(snakemake.output.json, {"rows": rows})
write_csv(snakemake.output.csv, [{k: r.get(k, "") for k in TABLE_COLUMNS} for r in rows])
logging.info(f"{rate:g} Hz: {len(rows)} rows in {time.perf_counter() - t0:.1f} s")
