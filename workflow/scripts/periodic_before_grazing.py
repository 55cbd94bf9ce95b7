"""Fig 4a scene: the attractor on the decreasing branch at w = 23.05, just before grazing.

Reads input.branch (the followed branch, whose end state at that w it restarts from) and params (scene,
model, solver); writes output.run (HDF5 run file with a trajectory window).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("periodic_before_grazing")
configure_logging(snakemake)

import logging

from impactosc.core.simulation import Window, simulate
from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import write_run
from impactosc.model.parameters import ModelParams
from impactosc.statistics.periodic_train import branch_state


def main(branch: str, scene: dict, model: dict, solver: dict, out: str):
    sweep, _ = load_sweep(branch)
    x0, v0 = branch_state(sweep, scene["omega"])
    end = scene["transient"] + scene["duration"]
    res = simulate(
        scene["omega"],
        scene["transient"],
        scene["duration"],
        x0=x0,
        v0=v0,
        params=ModelParams(**model),
        rtol=solver["rtol"],
        atol=solver["atol"],
        window=Window(scene["transient"], end, scene["dt"]),
    )
    res.attrs["start_from"] = f"branch end state at w = {scene['omega']} ({branch})"
    write_run(out, res.events, res.attrs, res.trajectory, sources=branch)
    logging.info("%s: %d impacts from (x0, v0) = (%.6e, %.6e)", out, res.impact_times.size, x0, v0)


main(
    snakemake.input.branch,
    snakemake.params.scene,
    snakemake.params.model,
    snakemake.params.solver,
    snakemake.output.run,
)
