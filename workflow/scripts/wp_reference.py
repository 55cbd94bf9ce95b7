"""The references of one work-precision scene: start states, SciPy's primary and check runs, uncertainty.

Reads input.cache and params (model, the scene's entry, work_precision.reference); writes output.json
(impactosc_bench.workprecision.reference_set). Not a timing rule: it runs beside other jobs.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("wp_reference", wp_scene="chaotic")
configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_json
from impactosc.model.parameters import ModelParams
from impactosc_bench.workprecision import Case, reference_set


def main(model, name, entry, ref, out):
    case = Case(name, entry["omega"], entry["settle"], entry["horizon"], entry["starts"], entry["spacing"])
    t0 = time.perf_counter()
    refset = reference_set(case, ModelParams(**model), ref)
    unc = refset["uncertainty"]
    logging.info(
        "%s: %d start(s), %d reference impacts, uncertainty (%s vs %s) %.2e s in impact time; %.1f s",
        name,
        len(refset["starts"]),
        unc["n_impacts_ref"],
        ref["check_method"],
        ref["method"],
        unc["impact_time_error"],
        time.perf_counter() - t0,
    )
    write_json(out, refset)


main(
    snakemake.params.model,
    snakemake.wildcards.wp_scene,
    snakemake.params.entry,
    snakemake.params.reference,
    snakemake.output.json,
)
