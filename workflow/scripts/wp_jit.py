"""JIT compile time of the core, cold (empty cache) and from cache, in fresh processes.

Reads snakemake.input.cache (the numba_cache job's JSON marker: when that job found the cache
empty, its compile is the cold time, not measured a second time); writes
snakemake.output.json ({"cold": s, "cached": s, "cold_source": ...}), which the
work-precision figure and table report apart from the (compile-free) timings.
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

from impactosc.io.files import read_json, write_json
from impactosc_bench.core_speed import jit_times


def main(cold, marker, out):
    cache = read_json(marker)
    if cache["compiled"]:
        jit = {**jit_times(cold_seconds=cache["seconds"]), "cold_source": "the numba_cache job (empty cache)"}
    else:
        jit = {**jit_times(cold), "cold_source": "a fresh process, empty temporary cache" if cold else "not measured"}
    logging.info(f"JIT compile: {jit}")
    write_json(out, jit, final_newline=True)


main(snakemake.params.cold, snakemake.input.cache, snakemake.output.json)
