"""The two-parameter curves drawn over the 2-D map, and the map's cells checked against them.

Reads input.map (the joined map), input.curves (named by params.names) and input.table; writes
output.png, output.pdf, output.separation (CSV: one row per check) and output.md (its summary).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("map2d_curves")
configure_logging(snakemake)

import logging

from impactosc.dynamics.maps import load_map
from impactosc.dynamics.two_parameter_map import SEPARATION_COLUMNS, UNITS, separation
from impactosc.io.files import read_json, write_csv, write_text
from impactosc_study.figures import save_figure
from impactosc_study.figures.two_parameter import map2d_curves_figure
from impactosc_study.paper.table import to_markdown


def main(inp, params, out):
    m = load_map(inp.map)
    curves = {name: read_json(path) for name, path in zip(params.names, inp.curves)}
    curves = {name: c for name, c in curves.items() if c["points"]}
    bad = [name for name, c in curves.items() if c["parameter"] != m.parameter]
    if bad:
        raise ValueError(f"curves {bad} are in another parameter than the map ({m.parameter})")
    rows = separation(m.omega, m.values, m.period, m.impacts, curves)
    write_csv(out.separation, rows, SEPARATION_COLUMNS, yes_no=True, sources=[inp.map, *inp.curves])
    failed = [r for r in rows if not r["ok"]]
    scale, unit = UNITS[m.parameter]
    write_text(
        out.md,
        "# The 2-D map's cells against the two-parameter curves\n\n"
        f"{len(rows) - len(failed)} of {len(rows)} checks pass, to one grid cell ({m.omega[1] - m.omega[0]:.4g} rad/s). "
        "`sides`: at each crossing of a map row by a curve, of the nearest cells beyond one grid cell on either "
        "side exactly one is the curve's orbit (period, impacts per orbit). `between`: where two curves bound one "
        "orbit from either side in a row (a grazing and a doubling of it; the doubling that creates it and the one "
        "that doubles it again), every cell between them beyond one grid cell is that orbit. The map's rows follow "
        "increasing w from rest, so where two attractors coexist a row can stay on the other one past a curve "
        "(hysteresis): such a failed check does not say the curve is wrong.\n\n"
        + (to_markdown([{**r, "value": f"{r['value'] * scale:.4g} {unit}", "omega": f"{r['omega']:.3f}"}
                        for r in failed], ["check", "curve", "value", "omega", "cells"])
           if failed else "Every check passes.\n"),
    )  # fmt: skip
    plotted = {
        name: (c["kind"], [p["omega"] for p in c["points"]], [p["value"] for p in c["points"]],
               [d["omega"] for d in c["codim_two"]], [d["value"] for d in c["codim_two"]])
        for name, c in curves.items()
    }  # fmt: skip
    marks = [(w, params.model[m.parameter]) for w in params.marks]
    fig = map2d_curves_figure(m.omega, m.values, m.period, plotted, m.parameter, scale, unit, marks)
    save_figure(fig, out.png, out.pdf)
    logging.info("%d of %d checks pass; failed: %s", len(rows) - len(failed), len(rows), failed)


main(snakemake.input, snakemake.params, snakemake.output)
