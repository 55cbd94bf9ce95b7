"""Identify the model from the configured records (or the surrogate record set).

Reads input.kernels (compiled kernels), input.cache, input.records and params (identification, model, solver);
writes output.model (the model file), output.windows (fitted windows, for the figure), output.csv and
output.md (parameters).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_model")
configure_logging(snakemake)

import logging

from impactosc.identification.report import (
    configured_inputs,
    parameter_markdown,
    parameter_table,
    write_fit_windows,
    write_identified_model,
)
from impactosc.identification.staged_fit import identify
from impactosc.io.files import write_table, write_text
from impactosc.records.surrogate_truth import record_truth

p = snakemake.params
g = p.identification
base, records = configured_inputs(g, p.model, snakemake.input.records)
ident = identify(records, base=base, stages=tuple(g["stages"]), rtol=p.solver["rtol"], progress=logging.info)
write_identified_model(snakemake.output.model, ident)
prediction = ident.prediction()
write_fit_windows(snakemake.output.windows, ident, prediction, sources=list(snakemake.input.records))
rows = parameter_table(ident, truth=record_truth(records))  # a surrogate's truth, else none
write_table(snakemake.output.csv, rows, sources=list(snakemake.input.records))
write_text(snakemake.output.md, parameter_markdown(rows, ident))
for nm, why in ident.fixed.items():
    logging.info(f"{nm}: {why}")
logging.info(f"identified in {ident.seconds:.1f} s: residual rms {ident.noise * 1e6:.3f} um")
