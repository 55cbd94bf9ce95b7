"""Chaotic statistics at each core tolerance, and the ensemble that fixes their spread.

Reads input.cache and params (model, the chaotic scene, work_precision.statistics, atol_ratio, analysis);
writes output.csv (rows of kind "sweep" and "ensemble").
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("wp_statistics")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_table
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_bench.tolerance_statistics import statistics_convergence


def main(model, scene, stats, atol_ratio, analysis, out):
    rows = statistics_convergence(
        scene["omega"],
        scene["transient"],
        scene["duration"],
        stats["rtols"],
        atol_ratio,
        stats["ensemble_x0"],
        stats["ensemble_rtol"],
        ModelParams(**model),
        AnalysisOptions.from_config(analysis),
        log=logging.info,
    )
    write_table(out, rows)


main(
    snakemake.params.model,
    snakemake.params.scene,
    snakemake.params.stats,
    snakemake.params.atol_ratio,
    snakemake.params.analysis,
    snakemake.output.csv,
)
