"""A bifurcation diagram with the largest Lyapunov exponent under it (rules fig02_lyapunov, fig03b_lyapunov).

Reads input.sweep and input.lambdas (the same sweep's lambda1 CSV), params.quantity (poincare for Fig 2,
isi for Fig 3b); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig02_lyapunov")
configure_logging(snakemake)

import logging

from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_csv
from impactosc_study.figures import save_figure
from impactosc_study.figures.lyapunov import diagram_with_exponent


def main(inp, params, out):
    res, attrs = load_sweep(inp.sweep[0])
    rows = read_csv(inp.lambdas[0], numbers=True)
    w = [float(r["omega"]) for r in rows]
    lam = [float(r["lambda1_per_period"]) for r in rows]
    sw, sy = res.poincare_points() if params.quantity == "poincare" else res.isi_points()
    title = f"{'Fig 2' if params.quantity == 'poincare' else 'Fig 3b'} with the largest Lyapunov exponent ({attrs['direction']} w)"
    fig = diagram_with_exponent(sw, sy, w, lam, quantity=params.quantity, x_obstacle=params.model["xI"], title=title)
    save_figure(fig, out.png, out.pdf)
    logging.info("wrote %s", out.png)


main(snakemake.input, snakemake.params, snakemake.output)
