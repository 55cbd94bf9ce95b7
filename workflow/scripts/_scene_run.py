"""What the scene jobs share (rules simulate_scene, chaotic_members): one configured scene through the
core into its HDF5 run file, its progress in the log.

Not a rule's script (the leading underscore): Snakemake puts this folder on the scripts' sys.path.
"""

import logging

from impactosc.core.simulation import Window, simulate
from impactosc.io.files import write_run
from impactosc.model.noise import Noise
from impactosc.model.parameters import ModelParams


def run_scene(model: dict, solver: dict, scene: dict, output: str, noise: dict | None = None) -> None:
    """Simulate ``scene`` (a validated config entry) with ``solver``'s tolerances and the config's
    noise in the dynamics; write ``output``."""
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
        noise=Noise.from_dict(noise),
    )
    write_run(output, res.events, res.attrs, res.trajectory)
    logging.info(
        "%s: %d impacts, wall time %.3f s",
        output,
        len(res.events.get("impacts", {}).get("t", [])),
        res.attrs["wall_time"],
    )
