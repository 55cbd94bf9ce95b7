"""Measure one work-precision scene over the tolerance sweep, for one group of contestants.

Reads input.cache, input.shim, input.reference (rule wp_reference), optionally input.benchmark, params and
wildcards.contestants (compiled: core and peers; scipy); writes output.csv (one row per solver and rtol).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("wp_measure", wp_scene="chaotic", contestants="compiled")
configure_logging(snakemake)

import logging
import math

from impactosc.io.files import read_json, read_table, write_table
from impactosc.model.parameters import ModelParams
from impactosc_bench.workprecision import Case, sweep_case
from impactosc_bench.wp_attractor import known_long_runs
from impactosc_bench.wp_solvers import CORE, peer_solvers


def main(model, wp, name, contestants, entry, reference, benchmark, out):
    case = Case(name, entry["omega"], entry["settle"], entry["horizon"], entry["starts"], entry["spacing"])
    pc = wp["peers"]
    with_peers = contestants == "compiled" and name in pc["scenes"]
    if contestants == "compiled":
        solvers = [CORE, *(peer_solvers(pc["methods"]) if with_peers else [])]
    else:
        solvers = list(wp["scipy_methods"])
    known = known_long_runs(read_table(benchmark)) if benchmark else {}
    if known:
        logging.info("%d runs of 500 s taken from %s", len(known), benchmark)
    rows = sweep_case(
        case,
        ModelParams(**model),
        wp["rtols"],
        wp["atol_ratio"],
        solvers,
        wp["reference"],
        core_repeats=wp["core_repeats"],
        scipy_repeats=wp["scipy_repeats"],
        repeat_below=wp["scipy_repeat_below"],
        time_cap=math.inf if wp["exhaustive"] else wp["scipy_time_cap"],
        peer_repeats=pc["repeats"],
        attractor_check=with_peers and pc["attractor_check"],
        floor=with_peers and pc["heyoka"],
        known_500s=known,
        reference=read_json(reference),
        log=logging.info,
    )
    write_table(out, rows, sources=[reference, benchmark] if benchmark else [reference])


main(
    snakemake.params.model,
    snakemake.params.wp,
    snakemake.wildcards.wp_scene,
    snakemake.wildcards.contestants,
    snakemake.params.entry,
    snakemake.input.reference,
    snakemake.input.get("benchmark"),
    snakemake.output.csv,
)
