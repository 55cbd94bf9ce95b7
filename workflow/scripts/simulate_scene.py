"""Run one configured scene through the core and write its HDF5 run file.

Reads the scene entry (omega, transient, duration, events, window) and the model/solver
config from snakemake.params; writes snakemake.output.run (atomically) and a log.
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.files import write_run
from impactosc.integration.model import ModelParams
from impactosc.integration.simulate import Window, simulate


def run_scene(model: dict, solver: dict, scene: dict, output: str) -> None:
    window = Window(**scene["window"]) if scene.get("window") else None

    def progress(t, t_end, n_imp):
        logging.info("t = %.1f / %.1f s, %d impacts", t, t_end, n_imp)

    res = simulate(
        scene["omega"],
        scene["transient"],
        scene["duration"],
        x0=scene["x0"],
        v0=scene["v0"],
        params=ModelParams(**model),
        rtol=solver["rtol"],
        atol=solver["atol"],
        window=window,
        record=scene["events"],
        progress=progress,
    )
    write_run(output, res.events, res.attrs, res.trajectory)
    logging.info(
        "%s: %d impacts, wall time %.3f s",
        output,
        len(res.events.get("impacts", {}).get("t", [])),
        res.attrs["wall_time"],
    )


run_scene(
    snakemake.params.model,
    snakemake.params.solver,
    snakemake.params.scene,
    snakemake.output.run,
)
