"""Compile the numba core once into the shared cache before parallel jobs start.

Reads nothing; writes snakemake.output.marker (JSON): the seconds it took, timed as
impactosc_bench.core_speed.JIT_PROBE times them (import, then compile or load), and
whether the core was compiled (an empty cache: that is the cold JIT time, which wp_jit
then reports instead of compiling a second time) or loaded from the cache.
"""

import time

_t0 = time.perf_counter()  # before the imports, as JIT_PROBE

from _logging import configure_logging

configure_logging(globals().get("snakemake"))  # None when run by hand

import logging
import sys

from impactosc.core.driver import run
from impactosc.core.simulation import warm_up
from impactosc.io.files import write_json


def main(marker: str) -> None:
    warm_up()
    seconds = time.perf_counter() - _t0
    compiled = sum(run.stats.cache_misses.values()) > 0  # numba compiled run, not loaded it
    logging.info("numba core %s in %.2f s", "compiled" if compiled else "loaded from the cache", seconds)
    write_json(marker, {"seconds": seconds, "compiled": compiled}, final_newline=True)


if __name__ == "__main__" and "snakemake" not in globals():
    main(sys.argv[1])
else:
    main(snakemake.output.marker)
