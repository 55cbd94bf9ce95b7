"""Draw several studies' (or contact laws') Fig 2 and Fig 3b over each other, with the period each reads at every w.

Reads input.sweeps (each layer's Fig 2 then Fig 3b sweep, layer after layer) and input.stats (each layer's
diagram reading); writes output.fig02_png, output.fig02_pdf, output.fig03b_png, output.fig03b_pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("compare_studies")
configure_logging(snakemake)

import json
import logging
from pathlib import Path

from impactosc.dynamics.sweep import load_sweep
from impactosc_study.figures import save_figure
from impactosc_study.figures.bifurcation import studies_figure

TITLES = {
    "fig02": r"Fig 2: Poincare points at increasing $\omega$",
    "fig03b": r"Fig 3b: inter-impact intervals at decreasing $\omega$",
}


def layer(label, sweep_file, stats_file, sweep, quantity):
    """(label, w, y, x_obstacle, omega, period) of one layer's diagram, as studies_figure takes it;
    label a template filled with the sweep's model (e.g. "{law}, e = {e:.4f}"), whose e is known
    only once a job of the build has matched it."""
    res, _ = load_sweep(sweep_file)
    per_w = json.loads(Path(stats_file).read_text())["sweeps"][sweep]["per_w"]
    w, y = res.poincare_points() if quantity == "poincare" else res.isi_points()
    params = res.settings.params
    return label.format(**params.to_dict()), w, y, params.xI, per_w["omega"], per_w["period"]


def main(inp, params, out):
    for k, (name, quantity) in enumerate((("fig02", "poincare"), ("fig03b", "isi"))):
        layers = [
            layer(label, inp.sweeps[2 * n + k], inp.stats[n], params.sweeps[k], quantity)
            for n, label in enumerate(params.labels)
        ]
        fig = studies_figure(layers, quantity, title=f"{TITLES[name]}, {params.title}")
        save_figure(fig, out[f"{name}_png"], out[f"{name}_pdf"])
        logging.info("wrote %s", out[f"{name}_png"])


main(snakemake.input, snakemake.params, snakemake.output)
