"""Run every w of a grid from rest (x = v = 0 at t = 0) around the grazing.

Reads input.cache and params (scan, n_record, model, solver); writes output.sweep (sweep HDF5,
impactosc.dynamics.sweep format).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("periodic_from_rest")
configure_logging(snakemake)

import logging

from impactosc.dynamics.grazing import scan_from_rest
from impactosc.dynamics.sweep import SweepSettings, regular_grid, save_sweep
from impactosc.model.parameters import ModelParams


def main(scan: dict, n_record: int, model: dict, solver: dict, out: str):
    settings = SweepSettings(
        n_transient=0,
        n_record=n_record,
        n_initial=0,
        params=ModelParams(**model),
        rtol=solver["rtol"],
        atol=solver["atol"],
    )
    grid = regular_grid(scan["start"], scan["stop"], scan["step"])
    result = scan_from_rest(
        grid, settings, scan["transient"], progress=lambda i, n, w: logging.info("w %d/%d = %.4f", i + 1, n, w)
    )
    save_sweep(out, result, direction="from rest", transient_s=scan["transient"])


main(
    snakemake.params.scan,
    snakemake.params.n_record,
    snakemake.params.model,
    snakemake.params.solver,
    snakemake.output.sweep,
)
