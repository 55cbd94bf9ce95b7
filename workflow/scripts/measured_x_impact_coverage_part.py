"""One noise level of the obstacle-estimate coverage study.

Reads input.kernels (compiled kernels), input.cache, params (coverage, surrogate, model, solver) and
wildcards.level (an exponent and noise pair); writes output.json (impactosc_study.coverage.x_impact_draws).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_x_impact_coverage_part", level=0)
configure_logging(snakemake)

import logging

from impactosc.io.files import write_json
from impactosc.model.parameters import ModelParams
from impactosc_study.coverage import coverage_summary, x_impact_draws

p = snakemake.params
cov, sur = p.coverage, p.surrogate
# job number level = (exponent index) x (number of noise levels) + noise index
exponent, noise = [(e, n) for e in cov["exponents"] for n in cov["noise"]][int(snakemake.wildcards.level)]
exponent = None if exponent == "free" else float(exponent)


def progress(i, n, row):
    logging.info(
        f"draw {i}/{n}: segment {row['segment']} seed {row['seed']}: error {row['error_m'] * 1e6:+.2f} um, "
        f"sigma {row['sigma_m'] * 1e6:.2f} um"
    )


rows = x_impact_draws(
    noise,
    omega=sur["chaos"]["omega"],
    transient=sur["chaos"]["transient"],
    duration=cov["duration"],
    segment=cov["segment"],
    seeds=cov["seeds"],
    rate=sur["rate"],
    mismatch=sur["mismatch"],
    params=ModelParams(**p.model),
    exponent=exponent,
    progress=progress,
    **p.solver,
)
write_json(snakemake.output.json, {"draws": rows})
logging.info("summary: %s", coverage_summary(rows))
