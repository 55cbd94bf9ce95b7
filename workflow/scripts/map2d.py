"""Join the row groups of the 2-D map and draw it.

Reads input.parts (map HDF5 row groups, in order); writes output.map (joined map HDF5), output.png,
output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("map2d")
configure_logging(snakemake)

import logging

from impactosc.dynamics.maps import load_map, merge_maps, save_map
from impactosc_study.figures import save_figure
from impactosc_study.figures.two_parameter import map2d_figure

UNITS = {"xI": (1e3, "mm"), "m0e": (1e3, "g m")}


def main(parts, model, out):
    parts = [parts] if isinstance(parts, str) else list(parts)
    m = merge_maps([load_map(p) for p in parts])
    save_map(out.map, m, sources=parts)
    scale, unit = UNITS[m.parameter]
    fig = map2d_figure(m.omega, m.values, m.period, m.rate, m.parameter, scale, unit, marker=model[m.parameter])
    save_figure(fig, out.png, out.pdf)
    logging.info("map %s: %d x %d cells, %.1f core seconds", m.parameter, m.values.size, m.omega.size, m.wall_time)


main(snakemake.input.parts, snakemake.params.model, snakemake.output)
