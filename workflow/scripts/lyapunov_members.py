"""Realisations of the chaotic attractor's Lyapunov spectrum, one per start x0, all in one job.

Reads input.cache, params.chaos (omega, transient, n_periods, x0) and params.model; writes output.runs
(one JSON per start, in order: exponents, Kaplan-Yorke dimension, running estimates, the cost).

One job, because a job's start-up is over a third of a realisation's time: each settles from (x0, 0),
then runs the tangent dynamics with a QR step every period.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("lyapunov_members")
configure_logging(snakemake)

import logging
import time

from impactosc.dynamics.lyapunov import lyapunov_spectrum, settle
from impactosc.io.files import write_json
from impactosc.model.parameters import ModelParams


def run_member(c: dict, model: ModelParams, x0: float, output: str) -> None:
    wall, cpu = time.perf_counter(), time.process_time()
    y = settle([x0, 0.0], c["omega"], c["transient"], model)
    run = lyapunov_spectrum(
        y, c["omega"], c["n_periods"], model,
        log=lambda k, est: logging.info("%d periods: %.4f, %.4f per period", k, est[0], est[1]),
    )  # fmt: skip
    write_json(output, {
        "omega": run.omega, "x0": x0, "transient": c["transient"], "n_periods": c["n_periods"],
        "exponents_per_period": run.exponents, "exponents_per_second": run.per_second,
        "kaplan_yorke": run.kaplan_yorke, "running": run.running, "log_det": run.log_det, "points": run.points,
        "wall_seconds": time.perf_counter() - wall, "cpu_seconds": time.process_time() - cpu,
    })  # fmt: skip
    logging.info("x0 = %g m: exponents %s per period, Kaplan-Yorke %.4f", x0, run.exponents, run.kaplan_yorke)


p = snakemake.params
model_ = ModelParams(**p.model)
for x0_, output_ in zip(p.chaos["x0"], snakemake.output.runs, strict=True):
    run_member(p.chaos, model_, x0_, output_)
