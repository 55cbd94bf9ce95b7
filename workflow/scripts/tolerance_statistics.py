"""Chaotic statistics at each core tolerance, and the ensemble that fixes their spread.

Reads input.cache and params (model, the chaotic scene, work_precision.statistics, atol_ratio, analysis);
writes output.csv (rows of kind "sweep" and "ensemble", the work of each run as its count of right-hand
side evaluations: no timing) and output.summary (each tolerance against the ensemble: z-scores, converged).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("tolerance_statistics")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_table
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc_bench.tolerance_statistics import statistics_convergence, statistics_summary


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
    write_table(out.csv, rows)
    summary = statistics_summary(rows)
    write_table(out.summary, summary, sources=out.csv)
    loose = [r["rtol"] for r in summary if not r["converged"]]
    logging.info("%d tolerances, not converged at %s", len(summary), ", ".join(f"{r:g}" for r in loose) or "none")


main(
    snakemake.params.model,
    snakemake.params.scene,
    snakemake.params.stats,
    snakemake.params.atol_ratio,
    snakemake.params.analysis,
    snakemake.output,
)
