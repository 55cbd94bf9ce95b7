"""Fit one candidate of the model choice (contact law x friction) on the configured records.

Reads snakemake.input.records, params.identification (read, mass, stages, choice.every),
params.model, params.solver; wildcards.candidate numbers impactosc.identification.choice.candidates();
writes snakemake.output.json with the candidate's row (fit, held-out error, AIC, BIC).
"""

from _logging import configure_logging

configure_logging(snakemake)

import dataclasses
import logging

from impactosc.files import write_json
from impactosc.identification.choice import candidates, fit_candidate
from impactosc.integration.model import ModelParams
from impactosc.measured.records import read_records

p = snakemake.params
g = p.identification
base = ModelParams(**p.model)
if g["mass"] is not None:
    base = dataclasses.replace(base, m=float(g["mass"]))
read = {k: v for k, v in g["read"].items() if v is not None}
records = read_records(list(snakemake.input.records), **read)
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
