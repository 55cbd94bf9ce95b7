"""Paper-vs-replication rows of the experimental panels (Figs 8b, 9b, 10 lower, noise remark).

Reads input.second (statistics JSON of the record's train), input.model (the model's) and input.noise
(noise-study JSON) and params.dynamic (the dynamic-noise study's summary, None where the beyond tier
has not made it); writes output.rows.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_rows")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json
from impactosc_study.paper.rows.measured import measured_rows
from impactosc_study.paper.table import write_rows

rows = measured_rows(
    read_json(snakemake.input.second[0]),
    read_json(snakemake.input.model[0]),
    read_json(snakemake.input.noise)["rows"],
    is_surrogate=snakemake.params.is_surrogate,
    command=snakemake.params.command,
    dynamic=snakemake.params.dynamic,
)
write_rows(snakemake.output.rows, rows, sources=snakemake.input)
logging.info("".join(f"{r['agrees']:>4}  {r['quantity']}: {r['replication']}\n" for r in rows))
