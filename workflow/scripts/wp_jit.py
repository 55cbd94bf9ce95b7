"""JIT compile time of the core, cold (empty cache) and from cache, in fresh processes.

Reads nothing; writes snakemake.output.json ({"cold": s, "cached": s}), which the
work-precision figure and table report apart from the (compile-free) timings.
"""

from _logging import configure_logging

configure_logging(snakemake)  # noqa: F821

import json
import logging
from pathlib import Path

from impactosc.benchmarks.core_speed import jit_times


def main(out):
    jit = jit_times()
    logging.info(f"JIT compile: {jit}")
    Path(out).write_text(json.dumps(jit) + "\n")


main(snakemake.output.json)  # noqa: F821
