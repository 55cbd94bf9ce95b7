"""Draw this study's Fig 2 and Fig 3b over another study's, with the period each reads at every w.

Reads input.sweeps, input.other_sweeps (each study's Fig 2 and Fig 3b sweeps), input.stats and
input.other_stats (each study's diagram reading); writes output.fig02_png, output.fig02_pdf,
output.fig03b_png, output.fig03b_pdf. By hand: give compare.study in a --configfile.
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


def layer(study, sweep_file, stats_file, sweep, quantity):
    """(label, w, y, x_obstacle, omega, period) of one study's diagram, as studies_figure takes it."""
    res, _ = load_sweep(sweep_file)
    per_w = json.loads(Path(stats_file).read_text())["sweeps"][sweep]["per_w"]
    w, y = res.poincare_points() if quantity == "poincare" else res.isi_points()
    return f"study {study}", w, y, res.settings.params.xI, per_w["omega"], per_w["period"]


def main(inp, params, out):
    for k, (name, quantity) in enumerate((("fig02", "poincare"), ("fig03b", "isi"))):
        files = [(inp.sweeps[k], inp.stats), (inp.other_sweeps[k], inp.other_stats)]
        layers = [layer(study, *pair, params.sweeps[k], quantity) for study, pair in zip(params.studies, files)]
        fig = studies_figure(
            layers, quantity, title=f"{TITLES[name]}, studies {params.studies[0]} and {params.studies[1]}"
        )
        save_figure(fig, out[f"{name}_png"], out[f"{name}_pdf"])
        logging.info("wrote %s", out[f"{name}_png"])


main(snakemake.input, snakemake.params, snakemake.output)
