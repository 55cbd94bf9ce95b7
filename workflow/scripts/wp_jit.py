"""JIT compile time of the core, cold (empty cache) and from cache, in fresh processes.

Reads nothing; writes snakemake.output.json ({"cold": s, "cached": s}), which the
work-precision figure and table report apart from the (compile-free) timings.
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.benchmarks.core_speed import jit_times
from impactosc.files import write_json


def main(cold, out):
    jit = jit_times(cold)
    logging.info(f"JIT compile: {jit}")
    write_json(out, jit, final_newline=True)


main(snakemake.params.cold, snakemake.output.json)
