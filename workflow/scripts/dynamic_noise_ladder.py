"""One noise in the dynamics of the chaotic scene at each intensity of its ladder, a few seeds each.

Reads input.cache, params (ladder {tau, levels}, seeds, scene, model, solver, analysis) and
wildcards.noise (motor or force); writes output.json (rows and pooled ISI densities) and output.csv.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("dynamic_noise_ladder", noise="motor")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_csv, write_json
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_study.dynamic_noise import COLUMNS, noise_ladder

p = snakemake.params
rows, densities = noise_ladder(
    snakemake.wildcards.noise,
    p.ladder["levels"],
    tau=p.ladder["tau"],
    seeds=p.seeds,
    omega=p.scene["omega"],
    transient=p.scene["transient"],
    duration=p.scene["duration"],
    params=ModelParams(**p.model),
    solver=dict(p.solver),
    options=AnalysisOptions.from_config(p.analysis),
    progress=logging.info,
)
write_json(
    snakemake.output.json,
    {"rows": rows, "densities": [{"rms": rms, "grid": g, "density": d} for rms, (g, d) in densities.items()]},
)
write_csv(snakemake.output.csv, rows, COLUMNS)
