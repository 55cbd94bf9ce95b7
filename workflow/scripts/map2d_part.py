"""One job of the 2-D map: a group of rows (parameter values), each a continuation in w.

Reads input.cache and params (map and per-w settings, model, solver, reading, part); writes output.part
(map HDF5 of those rows, impactosc.dynamics.maps format).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("map2d_part", chunk=0)
configure_logging(snakemake)

import logging
import time

import numpy as np

from impactosc.dynamics.diagram import classify_sweep
from impactosc.dynamics.maps import MapResult, save_map
from impactosc.dynamics.sweep import SweepSettings, parameter_rows, regular_grid


def main(params, output):
    m = params.map
    grid = regular_grid(m["omega"]["start"], m["omega"]["stop"], m["omega"]["step"])
    values = np.array_split(np.linspace(m["values"]["start"], m["values"]["stop"], m["values"]["n"]), m["chunks"])[
        params.part
    ]
    settings = SweepSettings.from_config(
        params.per_w, params.model, params.solver, n_transient=m["n_transient"], n_record=m["n_record"]
    )
    r = params.reading
    started = time.time()
    tables = []
    for value, res in parameter_rows(grid, settings, m["parameter"], values):
        tables.append(classify_sweep(res, x_tol=r["x_tol"], v_tol=r["v_tol"], isi_tol=r["isi_tol"]))
        logging.info(
            "%s = %g: %d w in %.1f s, %d abandoned",
            m["parameter"],
            value,
            len(res),
            res.wall_time.sum(),
            int((res.status != 0).sum()),
        )
    finished = time.time()
    save_map(
        output,
        MapResult.from_tables(m["parameter"], values, tables, wall_time=finished - started),
        started=started,
        finished=finished,
    )


main(snakemake.params, snakemake.output.part)
