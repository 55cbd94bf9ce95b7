"""One job of a chunked continuation sweep (rules bifurcation_coarse: the seeding pass, bifurcation_chunk).

Reads input.cache, params (grid, per-w settings, model, solver, stride, chunking) and, for a chunk after
the first, input.seeds (the coarse pass); writes output.seeds or output.chunk (sweep HDF5, with timing).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_chunk", sweep="decreasing", chunk=0)
configure_logging(snakemake)

import logging
import time

from impactosc.dynamics.sweep import SweepSettings, load_sweep, regular_grid, save_sweep
from impactosc.dynamics.sweep_chunks import coarse_pass, plan_chunks, run_chunk


def main(params, seeds_path, output):
    grid = regular_grid(params.grid["start"], params.grid["stop"], params.grid["step"])
    settings = SweepSettings.from_config(params.per_w, params.model, params.solver)
    started = time.time()

    def progress(i, n, w):
        if i % 25 == 0 or i == n - 1:
            logging.info("w %d/%d = %.4f rad/s", i + 1, n, w)

    def failed(i, w, message):
        logging.warning("w = %.6f rad/s abandoned: %s", w, message)

    if params.part == "coarse":
        result = coarse_pass(grid, settings, params.stride, progress=progress, on_failure=failed)
        info = {"part": "coarse"}
    else:
        k = int(params.part)
        chunk = plan_chunks(grid.size, params.chunks, params.stride)[k]
        seeds = load_sweep(seeds_path)[0] if seeds_path else None
        result = run_chunk(grid, settings, chunk, params.stride, seeds, progress=progress, on_failure=failed)
        info = {"part": f"chunk {k}", "chunk_start": chunk[0], "chunk_stop": chunk[1]}
    finished = time.time()
    save_sweep(output, result, sources=seeds_path, started=started, finished=finished, **info)
    logging.info(
        "%s: %d w in %.1f s (%.2f w/s), %d abandoned",
        info["part"],
        len(result),
        finished - started,
        len(result) / (finished - started),
        int((result.status != 0).sum()),
    )


seeds = snakemake.input.get("seeds") or None
main(snakemake.params, seeds if isinstance(seeds, (str, type(None))) else seeds[0], snakemake.output[0])
