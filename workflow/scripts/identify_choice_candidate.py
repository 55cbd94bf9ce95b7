"""Fit one candidate of the model choice (contact law x friction) on the configured records.

Reads snakemake.input.records, params.identification (read, mass, stages, choice.every),
params.model, params.solver; wildcards.candidate numbers impactosc.identification.choice.candidates();
writes snakemake.output.json with the candidate's row (fit, held-out error, AIC, BIC).
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.identification.choice import candidates, fit_candidate
from impactosc.identification.report import configured_inputs
from impactosc.io.files import write_json

p = snakemake.params
g = p.identification
base, records = configured_inputs(g, p.model, snakemake.input.records)
law, friction = candidates()[int(snakemake.wildcards.candidate)]
logging.info(f"candidate: {law}, {friction}")
row = fit_candidate(
    records,
    law,
    friction,
    base=base,
    every=g["choice"]["every"],
    stages=tuple(g["stages"]),
    rtol=p.solver["rtol"],
    progress=logging.info,
)
logging.info(f"rms {row['rms_m'] * 1e6:.3f} um, held out {row['held_out_rms_m'] * 1e6:.3f} um, BIC {row['bic']:.1f}")
write_json(snakemake.output.json, {"row": row}, sources=list(snakemake.input.records))
