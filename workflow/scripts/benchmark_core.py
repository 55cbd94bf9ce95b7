"""Benchmark the core against SciPy DOP853 on the chaotic scene.

Reads params rtols/repeats; writes snakemake.output.csv (one row per solver and rtol) and
snakemake.output.md (the same table plus JIT times and the speed-up at each rtol).
"""

from _logging import configure_logging

configure_logging(snakemake)  # noqa: F821

import csv
import logging
import math

from impactosc.benchmarks.core_speed import jit_times, measure


def main(rtols, repeats, csv_path, md_path):
    jit = jit_times()
    logging.info("JIT: %s", jit)
    rows = measure(rtols=rtols, repeats=repeats, log=logging.info)
    cols = list(rows[0])
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)
    lines = ["# Core speed: chaotic scene (w = 40.86, 100 s + 400 s)", "",
             f"JIT compile: cold {jit['cold']:.1f} s, from cache {jit['cached']:.2f} s (excluded below).", "",
             "| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        lines.append("| " + " | ".join(f"{r[c]:.4g}" if isinstance(r[c], float) else str(r[c]) for c in cols) + " |")
    lines.append("")
    for rtol in rtols:
        core = [r for r in rows if r["rtol"] == rtol and r["solver"].startswith("impactosc")]
        sp = [r for r in rows if r["rtol"] == rtol and r["solver"].startswith("SciPy")]
        if core and sp and not math.isnan(sp[0]["wall_time"]):
            lines.append(f"- rtol {rtol:g}: core {sp[0]['wall_time'] / core[0]['wall_time']:.0f}x faster than SciPy "
                         f"(impact-time error over 1.5 s: core {core[0]['impact_time_error_1p5s']:.1e} s, "
                         f"SciPy {sp[0]['impact_time_error_1p5s']:.1e} s)")
    with open(md_path, "w") as f:
        f.write("\n".join(lines) + "\n")


main(snakemake.params.rtols, snakemake.params.repeats, snakemake.output.csv,  # noqa: F821
     snakemake.output.md)  # noqa: F821
