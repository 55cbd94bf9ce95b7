"""Join the chunks of one sweep into the sweep file the figures and tables read.

Reads input.chunks (chunk sweep files, in order) and input.coarse (the seeding pass: only its timing is
kept); writes output.sweep (impactosc.dynamics.sweep format, every job's start, finish and w count).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_merge", sweep="decreasing", law="bc")
configure_logging(snakemake)

import logging

import numpy as np

from impactosc.dynamics.sweep import load_sweep, save_sweep
from impactosc.dynamics.sweep_chunks import merge_chunks


def main(chunk_paths, coarse_paths, name, grid, output):
    coarse_paths = [coarse_paths] if isinstance(coarse_paths, str) else list(coarse_paths)
    chunk_paths = [chunk_paths] if isinstance(chunk_paths, str) else list(chunk_paths)
    parts = [load_sweep(p) for p in coarse_paths + chunk_paths]
    merged = merge_chunks([r for r, _ in parts[len(coarse_paths) :]])
    timing = {
        "job_part": np.array([str(a["part"]) for _, a in parts], dtype="S"),
        "job_started": np.array([a["started"] for _, a in parts]),
        "job_finished": np.array([a["finished"] for _, a in parts]),
        "job_n_omega": np.array([len(r) for r, _ in parts]),
        "job_core_seconds": np.array([float(r.wall_time.sum()) for r, _ in parts]),
        "job_cpu_seconds": np.array([float(r.cpu_time.sum()) for r, _ in parts]),
    }
    direction = "increasing" if grid["stop"] > grid["start"] else "decreasing"
    save_sweep(
        output,
        merged,
        sources=coarse_paths + chunk_paths,
        name=name,
        direction=direction,
        grid_start=grid["start"],
        grid_stop=grid["stop"],
        grid_step=grid["step"],
        **timing,
    )
    logging.info(
        "%s: %d w (%s), %d abandoned, %d jobs",
        name,
        len(merged),
        direction,
        int((merged.status != 0).sum()),
        len(parts),
    )


main(
    snakemake.input.chunks,
    snakemake.input.get("coarse", []),
    snakemake.wildcards.sweep,
    snakemake.params.grid,
    snakemake.output.sweep,
)
