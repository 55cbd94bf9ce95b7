"""One noise level of the noise study at every rate (rule measured_noise_level).

Reads snakemake.input.runs (each rate's clean run, in the order of the rates: rule
measured_noise_clean), snakemake.params (study: rates, noise levels, x_impact_span and levels;
surrogate: chaos scene, mismatch, seed; analysis: chaotic.analysis options) and wildcards.level
(index into the noise levels); writes snakemake.output.json (the rows, with ISI kernel
densities) and .csv (the same rows as table cells): each a slice of the study's two outputs,
which the merge (measured_noise_study.py) puts together in the study's order.
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging
import time

from impactosc.io.files import read_run, write_csv, write_json
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_study.noise_study import TABLE_COLUMNS, noise_level_rows

p = snakemake.params
c = p.surrogate["chaos"]
level = int(snakemake.wildcards.level)
t0 = time.perf_counter()
runs = [(events, trajectory) for events, _, trajectory in map(read_run, snakemake.input.runs)]
rows = noise_level_rows(
    c["omega"],
    c["transient"],
    c["duration"],
    p.study["rates"],
    p.study["noise"],
    level,
    analysis=AnalysisOptions.from_config(p.analysis),
    mismatch=p.surrogate["mismatch"],
    seed=p.surrogate["seed"],
    params=ModelParams(**p.model),
    x_impact_span=p.study["x_impact_span"],
    x_impact_noise=p.study["x_impact_noise"],
    runs=runs,
)
write_json(snakemake.output.json, {"rows": rows})
write_csv(snakemake.output.csv, [{k: r.get(k, "") for k in TABLE_COLUMNS} for r in rows])
logging.info(f"noise {p.study['noise'][level]:g} m: {len(rows)} rows in {time.perf_counter() - t0:.1f} s")
