"""What the sweep jobs share (rules bifurcation_coarse, bifurcation_chunk): the grid and settings from
their params, their progress in the log, and the sweep file with its timing.

Not a rule's script (the leading underscore): Snakemake puts this folder on the scripts' sys.path.
"""

import logging
import time

from impactosc.dynamics.sweep import SweepSettings, regular_grid, save_sweep
from impactosc.model.model_file import resolve_model


def grid_and_settings(params, inputs):
    """The sweep's w grid and its per-w settings, from a sweep job's params; the model is the
    model file input.model when the job has one (a model a job of the build made, as the laws
    study's matched laws), else params.model."""
    grid = regular_grid(params.grid["start"], params.grid["stop"], params.grid["step"])
    model_file = inputs.get("model")
    model = resolve_model(model_file)[0].to_dict() if model_file else params.model
    return grid, SweepSettings.from_config(params.per_w, model, params.solver)


def progress(i, n, w):
    if i % 25 == 0 or i == n - 1:
        logging.info("w %d/%d = %.4f rad/s", i + 1, n, w)


def failed(i, w, message):
    logging.warning("w = %.6f rad/s abandoned: %s", w, message)


def save_part(output, sweep_part, started, sources=None, **info):
    """Write one part of a sweep with its timing (what rule bifurcation_benchmark reads) and log its rate."""
    finished = time.time()
    save_sweep(output, sweep_part, sources=sources, started=started, finished=finished, **info)
    logging.info(
        "%s: %d w in %.1f s (%.2f w/s), %d abandoned",
        info["part"],
        len(sweep_part),
        finished - started,
        len(sweep_part) / (finished - started),
        int((sweep_part.status != 0).sum()),
    )
