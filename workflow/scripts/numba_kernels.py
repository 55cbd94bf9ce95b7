"""Compile the numba kernels outside the core (the obstacle fit's, the mixtures') into the
shared cache, beside the core's compile at the start of a build.

Reads nothing; writes snakemake.output.marker (JSON: the seconds it took). Without it, the
noise study's and identification's jobs that start together would each compile them.
"""

import time

_t0 = time.perf_counter()

from _logging import configure_logging

configure_logging(snakemake)

import logging

import numpy as np

from impactosc.files import write_json
from impactosc.measured import obstacle
from impactosc.statistics import FAMILIES, fit_mixture

obstacle.warm_up()
sample = np.random.default_rng(0).lognormal(-2.0, 0.3, 200)
for family in FAMILIES:
    fit_mixture(sample, family, 2)
seconds = time.perf_counter() - _t0
logging.info("numba kernels compiled or loaded in %.2f s", seconds)
write_json(snakemake.output.marker, {"seconds": seconds}, final_newline=True)
