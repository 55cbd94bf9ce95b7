"""Fig 3a: construction of the impact map on a stretch of x(t).

Reads input.run (a run file with a trajectory window) and params.start, params.span (s); writes
output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig03a")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_run
from impactosc_study.figures import save_figure
from impactosc_study.figures.periodic import fig03a_impact_construction

events, attrs, traj = read_run(snakemake.input.run)
if traj is None:
    raise ValueError(f"{snakemake.input.run} has no trajectory window; Fig 3a needs x(t)")
fig = fig03a_impact_construction(
    traj["t"], traj["x"], events["impacts"]["t"], attrs["param_xI"], snakemake.params.start, snakemake.params.span
)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"wrote {snakemake.output.png} and {snakemake.output.pdf}")
