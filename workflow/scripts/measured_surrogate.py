"""Write a surrogate record (model sampled like the rig, sensor noise, parameter mismatch).

Reads input.cache, params.surrogate, params.model, params.solver and wildcards.kind (chaos: one record of
the chaotic regime; sweep: one short record per w); writes output.record (measured-record format).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_surrogate", kind="chaos")
configure_logging(snakemake)

import logging
import time

import numpy as np

from impactosc.model.parameters import ModelParams
from impactosc.records.formats import write_record, write_record_set
from impactosc.records.surrogate import REALISM_FIELDS, SurrogateOptions, surrogate_record, surrogate_sweep

p = snakemake.params
s = p.surrogate
opts = SurrogateOptions(
    rate=s["rate"],
    noise=s["noise"],
    mismatch=s["mismatch"],
    seed=s["seed"],
    **{k: s[k] for k in REALISM_FIELDS if k in s},
    dynamics=s.get("dynamics"),
)
params = ModelParams(**p.model)
t0 = time.perf_counter()
if snakemake.wildcards.kind == "chaos":
    c = s["chaos"]
    rec, _ = surrogate_record(c["omega"], c["transient"], c["duration"], opts, params=params, **p.solver)
    write_record(snakemake.output.record, rec.t, rec.x, omega=rec.omega, meta=rec.meta)
    msg = f"chaos: {rec.t.size} samples at {opts.rate:g} Hz"
else:
    g = s["sweep"]
    omegas = np.arange(g["start"], g["stop"] + g["step"] / 2, g["step"])
    recs = surrogate_sweep(
        omegas, g["n_transient"], g["n_record"], opts, params=params, n_initial=g["n_initial"], **p.solver
    )
    write_record_set(snakemake.output.record, recs)
    msg = f"sweep: {len(recs)} records, w = {omegas[0]:g}..{omegas[-1]:g} rad/s"
logging.info(f"{msg}; noise {opts.noise:g} m, mismatch {opts.mismatch}; {time.perf_counter() - t0:.1f} s")
