"""One noise level of the noise study at every rate.

Reads input.runs (each rate's clean run), params (study, surrogate, analysis) and wildcards.level (index
into the noise levels); writes output.json (the rows, with ISI kernel densities) and output.csv.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_noise_level", level=0)
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
