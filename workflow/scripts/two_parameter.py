"""The two-parameter curves' tables: points, summary per curve, codimension-two points (rule two_parameter).

Reads input.curves (named by params.names); writes output.csv (points), output.codim (codimension-two
points, CSV) and output.md (all three).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("two_parameter")
configure_logging(snakemake)

import logging

from impactosc.dynamics.two_parameter_map import (
    CODIM_COLUMNS,
    POINT_COLUMNS,
    codim_two_rows,
    point_rows,
    summary_rows,
)
from impactosc.io.files import read_json, write_csv, write_text
from impactosc_study.paper.table import to_markdown


def _md(rows, empty, columns=None):
    return to_markdown(rows, columns or list(rows[0])) if rows else f"{empty}\n"


def main(inp, params, out):
    curves = {name: read_json(path) for name, path in zip(params.names, inp.curves)}
    followed = {name: c for name, c in curves.items() if c["points"]}
    for name in set(curves) - set(followed):
        logging.warning("%s: not followed (%s)", name, curves[name]["stops"]["start"])
    points, codim = point_rows(followed), codim_two_rows(followed)
    write_csv(out.csv, points, POINT_COLUMNS, sources=inp.curves)
    write_csv(out.codim, codim, CODIM_COLUMNS, sources=inp.curves)
    write_text(
        out.md,
        "# Bifurcation curves in two parameters\n\n"
        "Each located point of the one-parameter table continued in w and the second parameter by "
        "pseudo-arclength on the extended system: the orbit P^N(y) = y and det(M + I) = 0 (period doubling), "
        "det(M - I) = 0 (fold) or a zero signed gap of the grazing excursion (grazing). `difference` is the "
        "curve's w at the model's value of the parameter minus the table's.\n\n"
        + _md(summary_rows(followed), "No curve was followed.")
        + "\n## Codimension-two points met on the curves\n\n"
        + _md(codim, "None within the ranges followed.", CODIM_COLUMNS)
        + "\n## Every point\n\n"
        + _md(points, "No points.", POINT_COLUMNS),
    )
    logging.info("%d curves, %d points, %d codimension-two points", len(followed), len(points), len(codim))


main(snakemake.input, snakemake.params, snakemake.output)
