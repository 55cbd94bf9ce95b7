"""Checks of the chaotic spectrum: other tangent numerics on the same points, and the exponents' sum.

Reads input.run (the first lyapunov_members file), params.chaos and params.model; writes output.checks
(JSON: the spectrum at other core rtol and difference step, the sum against the mean divergence).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("lyapunov_checks")
configure_logging(snakemake)

import logging
import math
import time

import numpy as np

from impactosc.dynamics.lyapunov import RTOL, STEP, exponents_along
from impactosc.dynamics.variational import variational_monodromy
from impactosc.io.files import read_json, write_json
from impactosc.model.parameters import ModelParams


def main(inp, params, out):
    c, model = params.chaos, ModelParams(**params.model)
    run = read_json(inp.run[0])
    w, points = run["omega"], np.asarray(run["points"], float)
    pts = points[: c["check_points"]]
    reference = exponents_along(pts, w, model)
    checks = []
    for chk in c["checks"]:
        got = exponents_along(pts, w, model, step=chk["step"], rtol=chk["rtol"], atol=chk["rtol"] * 1e-2)
        checks.append({**chk, "exponents": got, "difference": got - reference})
        logging.info("rtol %g, step %g: %s (difference %s)", chk["rtol"], chk["step"], got, got - reference)
    # sum of the exponents over these periods = mean log|det J| (QR); Liouville: log det of the
    # variational monodromy = integral of the divergence over the period, computed by SciPy
    n = min(c["identity_periods"], len(points))
    started = time.perf_counter()
    div = np.array([math.log(abs(np.linalg.det(variational_monodromy(y, w, 1, model)[1]))) for y in points[:n]])
    fd = np.asarray(run["log_det"][:n], float)
    identity = {
        "periods": n,
        "sum_of_exponents_per_period": float(fd.mean()),
        "mean_divergence_per_period": float(div.mean()),
        "difference_per_period": float(fd.mean() - div.mean()),
        "largest_single_period_difference": float(np.max(np.abs(fd - div))),
        "seconds": time.perf_counter() - started,
    }
    logging.info("identity over %d periods: sum %.8f, divergence %.8f", n, fd.mean(), div.mean())
    write_json(out.checks, {"reference": {"rtol": RTOL, "step": STEP, "exponents": reference},
                            "check_points": len(pts), "checks": checks, "identity": identity},
               sources=list(inp.run))  # fmt: skip


main(snakemake.input, snakemake.params, snakemake.output)
