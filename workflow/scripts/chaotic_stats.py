"""Section 2.2 rows of the paper-vs-replication table and the ISI mixture table.

Reads input.kernels (compiled kernels), input.model (statistics JSON of the scene's train), input.ensemble
(spread over realisations) and input.run (its trajectory window, for Fig 6b's spectrum); writes output.rows
and output.mixture (CSV).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("chaotic_stats")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json, read_run, write_csv
from impactosc.statistics.spectral_lines import trajectory_spectrum
from impactosc.statistics.train_analysis import mixture_table
from impactosc_study.paper.rows.chaotic import chaotic_rows as paper_rows
from impactosc_study.paper.table import write_rows

model = read_json(snakemake.input.model[0])
ensemble = read_json(snakemake.input.ensemble)
_, attrs, traj = read_run(snakemake.input.run)
if traj is None:
    raise ValueError(f"{snakemake.input.run} has no trajectory window (needed for Fig 6b)")
spectrum = trajectory_spectrum(traj["t"], traj["x"], attrs["omega"])
rows = paper_rows(model, ensemble, spectrum, snakemake.params.command)
write_rows(snakemake.output.rows, rows, sources=snakemake.input)
write_csv(snakemake.output.mixture, mixture_table(model), sources=snakemake.input.model)
logging.info(
    "".join(f"{r['agrees']:>4}  {r['quantity']}: paper {r['paper']} | ours {r['replication']}\n" for r in rows)
)
