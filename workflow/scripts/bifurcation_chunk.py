"""One chunk of a chunked continuation sweep, started from the coarse pass (the first chunk from x0, v0).

Reads input.cache, params (grid, per-w settings, model or the model file input.model, solver, stride,
chunking) and, for a chunk after the first, input.seeds (the coarse pass); writes output.chunk (sweep
HDF5, with timing).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_chunk", sweep="decreasing", chunk=0, law="bc")
configure_logging(snakemake)

import time

from _sweep_job import failed, grid_and_settings, progress, save_part

from impactosc.dynamics.sweep import load_sweep
from impactosc.dynamics.sweep_chunks import plan_chunks, run_chunk

p = snakemake.params
started = time.time()
grid, settings = grid_and_settings(p, snakemake.input)
k = int(p.part)
chunk = plan_chunks(grid.size, p.chunks, p.stride)[k]
seeds_path = snakemake.input.seeds[0] if snakemake.input.seeds else None
seeds = load_sweep(seeds_path)[0] if seeds_path else None
result = run_chunk(grid, settings, chunk, p.stride, seeds, progress=progress, on_failure=failed)
info = {"part": f"chunk {k}", "chunk_start": chunk[0], "chunk_stop": chunk[1]}
save_part(snakemake.output.chunk, result, started, sources=seeds_path, **info)
