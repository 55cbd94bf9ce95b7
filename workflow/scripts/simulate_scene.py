"""Run one configured scene through the core and write its HDF5 run file.

Reads input.cache, params.scene (the scene's config entry), params.solver, params.model and params.noise; writes
output.run.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("simulate_scene", scene="period4")
configure_logging(snakemake)

from _scene_run import run_scene

p = snakemake.params
run_scene(p.model, p.solver, p.scene, snakemake.output.run, p.noise)
