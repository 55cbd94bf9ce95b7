"""Both sweep directions over their common range: the Poincare points and the intervals, hysteresis marked.

Reads input.sweeps (named by params.names) and input.stats (the diagram reading: per-w periods, the windows
where the directions differ); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_overlay")
configure_logging(snakemake)

import logging

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json
from impactosc_study.figures import save_figure
from impactosc_study.figures.bifurcation import overlay_figure


def main(inp, params, out):
    stats = read_json(inp.stats)
    layers = []
    for name, path in zip(params.names, inp.sweeps):
        res, attrs = load_sweep(path)
        wp, x = res.poincare_points()
        wi, s = res.isi_points()
        per_w = stats["sweeps"][name]["per_w"]
        label = f"{name} " + r"$\omega$"
        layers.append((label, wp, x, wi, s, str(attrs["direction"]), per_w["omega"], per_w["period"]))
    fig = overlay_figure(layers, params.model["xI"], windows=stats["directions_differ"]["windows"])
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
