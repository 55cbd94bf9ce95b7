"""The largest Lyapunov exponent at one chunk of a sweep's w values, from the sweep's last Poincare points.

Reads input.sweep, params.sweeps (n_periods, n_discard, chunks, rtol), params.part and params.model;
writes output.part (CSV: omega, lambda1 per period).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("lyapunov_sweep_part", sweep="decreasing", chunk=0)
configure_logging(snakemake)

import logging
import math
import time

import numpy as np

from impactosc.dynamics.lyapunov import largest_exponent
from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import write_csv
from impactosc.model.parameters import ModelParams


def main(inp, params, out):
    res, _ = load_sweep(inp.sweep)
    s, model = params.sweeps, ModelParams(**params.model)
    idx = np.array_split(np.arange(len(res)), s["chunks"])[params.part]
    started, rows = time.process_time(), []
    for i in idx:
        y = np.array([res.poincare_x[i, -1], res.poincare_v[i, -1]])
        w = float(res.omega[i])
        lam = math.nan
        if np.all(np.isfinite(y)):
            lam = largest_exponent(
                y, w, s["n_periods"], model, n_discard=s["n_discard"], rtol=s["rtol"], atol=s["rtol"] * 1e-2
            )
        rows.append({"omega": round(w, 6), "lambda1_per_period": lam})
    write_csv(out.part, rows, floats=".8g", sources=[inp.sweep])
    logging.info("%d w (%.4f-%.4f), %.1f CPU s", len(rows), rows[0]["omega"], rows[-1]["omega"],
                 time.process_time() - started)  # fmt: skip


main(snakemake.input, snakemake.params, snakemake.output)
