"""JIT compile time of the core, cold (empty cache) and from cache, in fresh processes.

Reads nothing; writes snakemake.output.json ({"cold": s, "cached": s}), which the
work-precision figure and table report apart from the (compile-free) timings.
"""

import json
from pathlib import Path

from impactosc.benchmarks.core_speed import jit_times


def main(out, log_path):
    jit = jit_times()
    Path(log_path).write_text(f"JIT compile: {jit}\n")
    Path(out).write_text(json.dumps(jit) + "\n")


main(snakemake.output.json, snakemake.log[0])  # noqa: F821
