"""One job of the attractors along w: a group of w, each surveyed from the same random starts.

Reads input.sweeps (Figs 2's and 3b's: where they differ joins the grid), input.cache and params;
writes output.part (HDF5, a group per w, impactosc.dynamics.attractor_continuation) and a line per w.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("attractors_part", chunk=0)
configure_logging(snakemake)

import logging
import time

from impactosc.dynamics.attractor_continuation import save_surveys, study_omegas, survey_along
from impactosc.dynamics.attractor_survey import random_starts, settings_attrs
from impactosc.dynamics.basins import chunk_rows
from impactosc.dynamics.stroboscopic import oscillator_settings
from impactosc.dynamics.sweep import load_sweep
from impactosc.model.parameters import ModelParams


def main(inp, params, out):
    a, b = params.attractors, params.basins
    increasing, decreasing = (load_sweep(path)[0] for path in inp.sweeps)
    omegas, differing = study_omegas(increasing, decreasing, params.reading, a["omega"])
    mine = omegas[chunk_rows(omegas.size, a["chunks"], params.part)]
    starts = random_starts(
        a["samples"], (b["x0"]["start"], b["x0"]["stop"]), (b["v0"]["start"], b["v0"]["stop"]), seed=a["seed"]
    )
    settings = oscillator_settings(max_iterations=a["max_iterations"])
    logging.info(
        "%d w values (%d where the sweeps differ), this job %d: %.3f..%.3f rad/s, %d starts each",
        omegas.size, len(differing), mine.size, mine[0], mine[-1], a["samples"],
    )  # fmt: skip
    started = time.time()

    def progress(i, n, s):
        names = ", ".join(x.name for x in s.attractors)
        logging.info("w %d/%d = %.4f rad/s: %s (%.1f CPU s; %.0f s so far)", i, n, s.omega, names, s.cpu_time,
                     time.time() - started)  # fmt: skip

    surveys = survey_along(mine, starts, ModelParams(**params.model), settings, boxes=a["boxes"], progress=progress)
    save_surveys(
        out.part, surveys, sources=list(inp.sweeps), chunk=params.part, chunks=a["chunks"],
        n_omegas_total=omegas.size, samples=a["samples"], seed=a["seed"], **settings_attrs(settings),
    )  # fmt: skip
    logging.info("%d w in %.0f s", mine.size, time.time() - started)


main(snakemake.input, snakemake.params, snakemake.output)
