"""JIT compile time of the core, cold (empty cache) and from cache, in fresh processes.

Reads input.cache (the numba_cache marker: when that job found the cache empty, its compile is the cold
time) and params.cold; writes output.json ({"cold": s, "cached": s, "cold_source": ...}).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("wp_jit")
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
