"""Follow the attractor with decreasing w and bracket the grazing w by bisection.

Reads input.cache and params (branch grid and lengths, grazing tolerance, model, solver); writes
output.branch (sweep HDF5, branch order) and output.bisection (JSON: the bracket and every trial).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("periodic_branch")
configure_logging(snakemake)

import logging

from impactosc.dynamics.grazing import locate_grazing
from impactosc.dynamics.sweep import SweepSettings, branch_grid, continuation, save_sweep
from impactosc.io.files import write_json
from impactosc.model.parameters import ModelParams


def main(branch: dict, grazing: dict, model: dict, solver: dict, out_branch: str, out_bisection: str):
    settings = SweepSettings(
        n_transient=branch["n_transient"],
        n_record=branch["n_record"],
        n_initial=branch["n_initial"],
        params=ModelParams(**model),
        rtol=solver["rtol"],
        atol=solver["atol"],
    )
    grid = branch_grid(branch["start"], branch["fine_from"], branch["stop"], branch["coarse_step"], branch["fine_step"])
    logging.info("branch: %d w values from %g down to %g", grid.size, grid[0], grid[-1])

    def progress(i, n, w):
        if i % 50 == 0 or i == n - 1:
            logging.info("w %d/%d = %.4f", i + 1, n, w)

    result = continuation(grid, settings, progress=progress)
    save_sweep(out_branch, result, direction="decreasing")
    bracket = locate_grazing(result, settings, grazing["tol"])
    logging.info(
        "grazing bracket [%.7f, %.7f] after %d trials", bracket.omega_contact, bracket.omega_miss, len(bracket.trials)
    )
    write_json(out_bisection, bracket.to_dict(), final_newline=True)


main(
    snakemake.params.branch,
    snakemake.params.grazing,
    snakemake.params.model,
    snakemake.params.solver,
    snakemake.output.branch,
    snakemake.output.bisection,
)
