"""The chaotic ensemble: the chaos scene again with other tolerances and starts x(0), one run file each.

Reads input.cache, params.scenes and params.solvers (one entry per member, in order), params.model and
params.noise (the scenes' noise in the dynamics); writes output.runs (one run file per member, in the same order).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("chaotic_members")
configure_logging(snakemake)

from _scene_run import run_scene

p = snakemake.params
for scene, solver, output in zip(p.scenes, p.solvers, snakemake.output.runs, strict=True):
    run_scene(p.model, solver, scene, output, p.noise)
