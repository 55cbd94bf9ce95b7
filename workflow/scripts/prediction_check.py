"""The Monte Carlo check of the predicted points' standard errors (rule prediction_check).

Reads input.cache, input.segment (segment params.check.segment), input.band (its points' se), input.model and
params.check; writes output.csv and output.md: per point the delta method's se beside the spread of the point
relocated for each draw from the covariance, with a verdict and the other points within `near` standard errors.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("prediction_check")
configure_logging(snakemake)

import logging
import math
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from impactosc.identification.predictions import check_row, read_model_with_covariance, relocated_point
from impactosc.io.files import read_json, write_csv, write_text
from impactosc_study.paper.table import to_markdown


def _part(job):
    """One share of one point's draws (a process of its own)."""
    model_path, point, draws, seed, sensitivities = job
    model, covariance = read_model_with_covariance(model_path)
    return relocated_point(point, model.params, covariance, draws, seed=seed, sensitivities=sensitivities)


def _shown(column, value):
    """A cell of the Markdown table: w to 1e-6 rad/s, other numbers to 4 digits."""
    if isinstance(value, float):
        return f"{value:.6f}" if column == "omega" else f"{value:.4g}"
    return value


def main(inp, params, threads, out):
    check = params.check
    segment, found = read_json(inp.segment), read_json(inp.band)
    fields = read_model_with_covariance(inp.model)[1][0]
    parts = max(1, int(threads))
    shares = [len(a) for a in np.array_split(np.arange(check["draws"]), parts)]
    jobs, index = [], []
    for row in found["points"]:
        row["se"] = math.nan if row["se"] is None else row["se"]  # JSON writes nan as null
    for i, (point, row) in enumerate(zip(segment["special_points"], found["points"])):
        if not math.isfinite(row["se"]):
            continue  # a fold, or a point not located: no se to check (the table says why)
        sens = {f: row[f"d_{f}"] for f in fields}
        for k, n in enumerate(shares):
            jobs.append((inp.model, point, n, 1000 * check["seed"] + 97 * i + k, sens))
            index.append(i)
    start = time.perf_counter()
    with ProcessPoolExecutor(parts) as pool:
        results = list(pool.map(_part, jobs))
    relocated = {i: np.concatenate([r[0] for j, r in zip(index, results) if j == i]) for i in set(index)}
    linear = {i: np.concatenate([r[1] for j, r in zip(index, results) if j == i]) for i in set(index)}
    rows = []
    for i, row in enumerate(found["points"]):
        if i in relocated:
            rows.append(check_row(row, relocated[i], found["points"], linear=linear[i], agree=check["agree"],
                                  near=check["near"]))  # fmt: skip
            logging.info("%s at w = %.6f: se %.4g, spread %.4g", row["kind"], row["omega"], row["se"],
                         rows[-1]["spread_monte_carlo"])  # fmt: skip
        else:
            rows.append({"kind": row["kind"], "omega": row["omega"], "verdict": "not checked", "near": row["note"]})
    columns = ["kind", "omega", "se_delta", "spread_monte_carlo", "ratio", "spread_sampling_error",
               "nonlinearity_in_se", "mean_shift_in_se", "draws", "relocated", "verdict", "near"]  # fmt: skip
    table = [{c: r.get(c, "") for c in columns} for r in rows]
    shown = [{c: _shown(c, v) for c, v in r.items()} for r in table]
    write_csv(out.csv, table, sources=[inp.segment, inp.band, inp.model])
    write_text(
        out.md,
        f"# Monte Carlo check of the predicted points of segment {check['segment']}\n\n"
        f"Model: {params.model_source['description']}. {check['draws']} parameter sets drawn from the model file's "
        "covariance; each located point relocated for every draw (a test function's root bisected, or a grazing "
        "from two near-miss orbits); the spread of the relocated points (sd) against the delta method's standard "
        f"error. Verdict: agree within {check['agree']:.0%}; the spread of {check['draws']} draws is itself uncertain "
        "by its sampling error (relative, 1 / sqrt(2 (n - 1))). nonlinearity_in_se: the rms distance of the "
        "relocated points from the delta method's prediction of each draw, in standard errors (near 0: the point "
        "is linear in the parameters, and a ratio off 1 is sampling). 'near' names other located points within "
        f"{check['near']:g} standard errors: there the point is not linear in the parameters over its uncertainty "
        f"(a codimension-2 point, a fold) and the two may differ. {time.perf_counter() - start:.0f} s on {parts} "
        "processes.\n\n" + to_markdown(shown, columns) + "\n",
    )


main(snakemake.input, snakemake.params, snakemake.threads, snakemake.output)
