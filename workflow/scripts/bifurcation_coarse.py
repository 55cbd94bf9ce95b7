"""The coarse sequential pass of a chunked continuation sweep: every stride-th w, whose states seed the chunks.

Reads input.cache, params (grid, per-w settings, model, solver, stride) or, for the model, the model file
input.model (a laws study's law); writes output.seeds (sweep HDF5, with timing).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_coarse", sweep="decreasing", law="bc")
configure_logging(snakemake)

import time

from _sweep_job import failed, grid_and_settings, progress, save_part

from impactosc.dynamics.sweep_chunks import coarse_pass

p = snakemake.params
started = time.time()
grid, settings = grid_and_settings(p, snakemake.input)
result = coarse_pass(grid, settings, p.stride, progress=progress, on_failure=failed)
save_part(snakemake.output.seeds, result, started, part="coarse")
