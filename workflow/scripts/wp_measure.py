"""Measure one work-precision scene: the core and SciPy's solvers over the tolerance sweep.

Reads snakemake.params (model, the work_precision config, the scene's name and entry);
writes snakemake.output.csv (one row per solver and tolerance: wall time, RHS evaluations,
errors against the reference; see impactosc.benchmarks.workprecision.sweep_case) and a log.
"""

from _logging import configure_logging

configure_logging(snakemake)  # noqa: F821

import logging

from impactosc.files import write_table
from impactosc.benchmarks.workprecision import CORE, Case, sweep_case
from impactosc.integration.model import ModelParams


def main(model, wp, name, entry, out):
    case = Case(name, entry["omega"], entry["settle"], entry["horizon"], entry["starts"], entry["spacing"])
    rows = sweep_case(case, ModelParams(**model), wp["rtols"], wp["atol_ratio"], [CORE, *wp["scipy_methods"]],
                      wp["reference"], core_repeats=wp["core_repeats"], scipy_repeats=wp["scipy_repeats"],
                      repeat_below=wp["scipy_repeat_below"], time_cap=wp["scipy_time_cap"], log=logging.info)
    write_table(out, rows)


main(snakemake.params.model, snakemake.params.wp, snakemake.wildcards.wp_scene,  # noqa: F821
     snakemake.params.entry, snakemake.output.csv)  # noqa: F821
