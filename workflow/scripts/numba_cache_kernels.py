"""Compile the kernels of record extraction and of the mixture fits once into the shared cache.

Reads input.sources (the kernels' source files); writes output.marker (JSON: the seconds it took).

It runs beside the core's compile (rule numba_cache), before the jobs that read records start.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("numba_cache_kernels")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_json
from impactosc.records.warm_up import warm_up_kernels

seconds = warm_up_kernels()
logging.info("record and mixture kernels ready in %.2f s", seconds)
write_json(snakemake.output.marker, {"seconds": seconds}, final_newline=True)
