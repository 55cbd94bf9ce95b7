"""One job of the basin map: a group of v0 rows of the grid, every cell classified.

Reads input.cache and params (basins settings, grid, model, solver, part); writes output.part (HDF5 of
those rows, impactosc.dynamics.basins format) and a log with the CPU time.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("basins_part", grid="coarse", chunk=0)
configure_logging(snakemake)

import logging
import time

import numpy as np

from impactosc.dynamics.basins import (
    BasinGrid,
    BasinSettings,
    basin_fractions,
    chunk_rows,
    class_names,
    classify_rows,
    reference_attractors,
    save_basins,
)


def main(params, output):
    b, g = params.basins, params.grid
    settings = BasinSettings.from_config(b, params.model, params.solver)
    grid = BasinGrid.linspace(
        (b["x0"]["start"], b["x0"]["stop"]), (b["v0"]["start"], b["v0"]["stop"]), g["n_x"], g["n_v"]
    )
    rows = chunk_rows(g["n_v"], g["chunks"], params.part)
    started = time.time()
    cpu = time.process_time()
    attractors = reference_attractors(settings.omega, b["attractors"], settings.params)
    for a in attractors:
        logging.info(
            "%s: %d impacts per %d periods, |mu| = %s, Poincare x = %s m, v = %s m/s",
            a.name, a.impacts, a.n_periods, np.round(np.abs(a.multipliers), 4), a.x, a.v,
        )  # fmt: skip
    shot = time.process_time() - cpu
    m = classify_rows(grid, rows, attractors, settings)
    finished = time.time()
    counts = {r["name"]: r["cells"] for r in basin_fractions(m.classes, class_names(attractors), m.tail_period)}
    logging.info(
        "rows %d..%d of %d: %d cells in %.1f CPU s (%.1f ms per cell; attractors shot in %.2f s), "
        "median %d periods per cell; %s",
        rows[0], rows[-1], g["n_v"], m.classes.size, m.cpu_time, 1e3 * m.cpu_time / m.classes.size, shot,
        np.median(m.periods), counts,
    )  # fmt: skip
    save_basins(output, m, started=started, finished=finished, n_rows_total=g["n_v"], attractors_cpu_time=shot)


main(snakemake.params, snakemake.output.part)
