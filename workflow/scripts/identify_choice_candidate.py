"""Fit one candidate of the model choice (contact law x friction) on the configured records.

Reads input.kernels, input.cache, input.records, params (identification, model, solver), wildcards.candidate
(a number of impactosc.identification.choice.candidates()); writes output.json (fit, held-out error, residuals
by block for the AIC and BIC; a fit that failed: the row saying why, which the table shows unranked).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_choice_candidate", candidate=0)
configure_logging(snakemake)

import logging

from impactosc.identification.choice import candidates, fit_failed, try_candidate
from impactosc.identification.report import configured_inputs
from impactosc.io.files import write_json

p = snakemake.params
g = p.identification
base, records = configured_inputs(g, p.model, snakemake.input.records)
law, friction = candidates()[int(snakemake.wildcards.candidate)]
logging.info(f"candidate: {law}, {friction}")
row = try_candidate(
    records,
    law,
    friction,
    base=base,
    every=g["choice"]["every"],
    stages=tuple(g["stages"]),
    rtol=p.solver["rtol"],
    progress=logging.info,
)
if fit_failed(row):
    logging.warning(row["failure"])
else:
    logging.info(
        f"rms {row['rms_m'] * 1e6:.3f} um on {row['n']} samples, held out {row['held_out_rms_m'] * 1e6:.3f} um"
    )
write_json(snakemake.output.json, {"row": row}, sources=list(snakemake.input.records))
