"""Compile the numba core once into the shared cache before parallel jobs start.

Reads input.sources (the core's source files); writes output.marker (JSON: the seconds it took, timed
as impactosc_bench.core_speed.JIT_PROBE times them; whether the core was compiled or loaded from cache).

A compile into an empty cache is the cold JIT time, which wp_jit then reports instead of compiling again.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("numba_cache")
configure_logging(snakemake)

import logging
import time

_t0 = time.perf_counter()  # before the core's imports, as JIT_PROBE

from impactosc.core.driver import run
from impactosc.core.simulation import warm_up
from impactosc.io.files import write_json


def main(marker: str) -> None:
    warm_up()
    seconds = time.perf_counter() - _t0
    compiled = sum(run.stats.cache_misses.values()) > 0  # numba compiled run, not loaded it
    logging.info("numba core %s in %.2f s", "compiled" if compiled else "loaded from the cache", seconds)
    write_json(marker, {"seconds": seconds, "compiled": compiled}, final_newline=True)


main(snakemake.output.marker)
