"""Run configured scenes through the core and write their HDF5 run files (rules simulate_scene, chaotic_members).

Reads input.cache, params.scenes and params.solvers (lists of the same length) and params.model; writes
one run file per scene, in order (output.run, or output.runs for the chaotic ensemble's members).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("simulate_scene", scene="period4")
configure_logging(snakemake)

import logging

from impactosc.core.simulation import Window, simulate
from impactosc.io.files import write_run
from impactosc.model.parameters import ModelParams


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


p = snakemake.params
for scene_, solver_, output_ in zip(p.scenes, p.solvers, snakemake.output, strict=True):
    run_scene(p.model, solver_, scene_, output_)
