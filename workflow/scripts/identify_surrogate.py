"""Write the surrogate records identification uses while no rig records are configured.

Reads input.cache and params (identification.surrogate, measured.surrogate, model, solver); writes
output.records (a record set, one record per w, labelled "surrogate (model + noise)").

The sensor-realism options are left out: the identified model has no sensor chain, so a filter's
delay would only bias it.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify_surrogate")
configure_logging(snakemake)

import logging

from impactosc.model.parameters import ModelParams
from impactosc.records.formats import write_record_set
from impactosc.records.surrogate import SurrogateOptions, surrogate_record

p = snakemake.params
g, s = p.identification["surrogate"], p.surrogate
params = ModelParams(**p.model)
records = []
for i, w in enumerate(g["omegas"]):
    opts = SurrogateOptions(rate=s["rate"], noise=s["noise"], mismatch=s["mismatch"], seed=s["seed"] + i)
    rec, _ = surrogate_record(w, g["transient"], g["duration"], opts, params=params, **p.solver)
    records.append(rec)
    logging.info(f"w = {w:g} rad/s: {rec.t.size} samples at {opts.rate:g} Hz, noise {opts.noise:g} m")
write_record_set(snakemake.output.records, records)
