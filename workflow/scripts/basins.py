"""Join the row groups of the basin map, classify rest (0, 0), count and draw (rules basins, basins_fine).

Reads input.parts (basin HDF5 row groups, in order), input.cache, params; writes output.map (joined HDF5),
output.table (CSV: cells and fraction per class, where rest lands), output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("basins")
configure_logging(snakemake)

import logging

import numpy as np

from impactosc.dynamics.basins import (
    BasinSettings,
    basin_fractions,
    class_names,
    classify_state,
    load_basins,
    merge_basins,
    save_basins,
)
from impactosc.io.files import write_csv
from impactosc_study.figures import save_figure
from impactosc_study.figures.basins import basins_figure

COLUMNS = ["class", "name", "n_periods", "impacts", "cells", "fraction", "se", "median_periods", "rest"]


def main(parts, params, out):
    parts = [parts] if isinstance(parts, str) else list(parts)
    loaded = [load_basins(p) for p in parts]
    m = merge_basins([p for p, _ in loaded])
    total = {int(extra["n_rows_total"]) for _, extra in loaded}
    if total != {m.rows.size}:
        raise ValueError(f"the parts hold {m.rows.size} rows of a grid of {sorted(total)} rows")
    settings = BasinSettings.from_config(params.basins, params.model, params.solver)
    if settings.to_attrs() != m.settings:
        raise ValueError(f"the parts were classified with {m.settings}, the config asks for {settings.to_attrs()}")
    rest = classify_state(0.0, 0.0, m.attractors, settings)
    names = class_names(m.attractors)
    rows = basin_fractions(m.classes, names, m.tail_period)
    for r in rows:
        base = not r["name"].startswith("unresolved,")
        if 0 < r["class"] <= len(m.attractors):
            a = m.attractors[r["class"] - 1]
            r.update(n_periods=a.n_periods, impacts=a.impacts)
        mask = m.classes == r["class"]
        r["median_periods"] = float(np.median(m.periods[mask])) if base and mask.any() else None
        r["rest"] = base and r["class"] == rest.cls
    write_csv(out.table, rows, COLUMNS, yes_no=True, sources=parts)
    save_basins(
        out.map, m, sources=parts, rest_class=rest.cls, rest_name=names[rest.cls], rest_periods=rest.periods,
        rest_tail_period=rest.tail_period,
    )  # fmt: skip
    fig = basins_figure(
        m.x0, m.v0, m.classes, m.periods, m.attractors, rows, (rest.cls, names[rest.cls]),
        omega=settings.omega, x_obstacle=settings.params.xI,
    )  # fmt: skip
    save_figure(fig, out.png, out.pdf)
    for r in rows:
        logging.info("%s: %d cells, %.4f +- %.4f", r["name"], r["cells"], r["fraction"], r["se"])
    logging.info(
        "rest (0, 0): %s after %d periods; %d x %d cells, %.1f CPU s in %d jobs",
        names[rest.cls], rest.periods, m.v0.size, m.x0.size, m.cpu_time, len(parts),
    )  # fmt: skip


main(snakemake.input.parts, snakemake.params, snakemake.output)
