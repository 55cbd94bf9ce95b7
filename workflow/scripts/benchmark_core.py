"""Benchmark the core against the compiled peers (CyRK, heyoka's floor) and SciPy DOP853, chaotic scene.

Reads input.cache, input.shim, input.jit and params.bc (config benchmark_core); writes output.csv (one row
per solver and rtol), output.headline (the core's lead at equal impact-time error) and output.md.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("benchmark_core")
configure_logging(snakemake)

import logging
import math

from impactosc.io.files import read_json, write_table, write_text
from impactosc_bench.core_revision import revision_lines
from impactosc_bench.core_speed import (
    CORE,
    DURATION,
    HEADLINE_COLUMNS,
    SCIPY,
    TABLE_COLUMNS,
    TRANSIENT,
    core_speed_headline,
    headline_sentence,
    markdown_table,
    measure_core_speed,
)


def scipy_ratios(rows) -> list[str]:
    """Core against SciPy at the same rtol (the comparison of earlier versions of this table)."""
    lines = []
    for sp in (r for r in rows if r["solver"] == SCIPY):
        core = [r for r in rows if r["solver"] == CORE and r["rtol"] == sp["rtol"]]
        if core and not math.isnan(sp["wall_time"]):
            c = core[0]
            lines.append(
                f"- rtol {sp['rtol']:g}: core {sp['wall_time'] / c['wall_time']:.0f}x faster than SciPy "
                f"(impact-time error over 1.5 s: core {c['impact_time_error_1p5s']:.1e} s, "
                f"SciPy {sp['impact_time_error_1p5s']:.1e} s)"
            )
    return lines


def main(bc, jit_path, csv_path, headline_path, md_path):
    jit = read_json(jit_path)  # measured once, by the work-precision group's wp_jit
    logging.info("JIT (from %s): %s", jit_path, jit)
    peers = bc["peers"]
    rows, skipped = measure_core_speed(
        rtols=bc["rtols"],
        repeats=bc["repeats"],
        scipy_rtols=bc["scipy_rtols"],
        peer_methods=peers["methods"],
        peer_rtols=peers["rtols"],
        heyoka=peers["heyoka"],
        against=bc["against"],
        log=logging.info,
    )
    write_table(csv_path, rows)
    head = core_speed_headline(rows, bc["max_error"])
    write_table(headline_path, head)
    reference = rows[0]["reference_impacts"]
    cold = "not measured" if jit.get("cold") is None else f"{jit['cold']:.1f} s"
    lines = [
        f"# Core speed: chaotic scene (w = 40.86, from rest, {TRANSIENT:g} s + {DURATION:g} s)",
        "",
        headline_sentence(head),
        "",
        *markdown_table(head, HEADLINE_COLUMNS),
        "",
        f"Wall time: median of {bc['repeats']} timing rounds in which the core and every compiled peer run "
        "once each (round-robin, serpentine order); SciPy: one run. JIT compilation of the core "
        f"({cold} cold, from cache {jit['cached']:.2f} s) and of the peers is excluded. "
        "Impact-time error: max |t - t_ref| over the first 1.5 s against SciPy DOP853 at rtol 1e-13 "
        "(inf: a different impact count). On the attractor: reached 500 s with an impact count in "
        f"100-500 s within 10 % of the core's at rtol 1e-10 ({reference:.0f}). Free-flight rows: the same "
        "oscillator without contact (obstacle out of reach), a floor, not a competitor.",
        "",
        *markdown_table(rows, TABLE_COLUMNS),
        "",
        *scipy_ratios(rows),
    ]
    revision = revision_lines(rows, CORE)
    if revision:
        lines += ["", f"## This core against revision {bc['against']}, in the same rounds", "", *revision]
    if not bc["scipy_rtols"]:
        lines += [
            "",
            "SciPy's 500 s runs (1.5-2.5 min each) are opt-in (benchmark_core.scipy_rtols); SciPy's speed "
            "at equal error is in the work-precision table (results/<study>/tables/work_precision/).",
        ]
    if skipped:
        lines += ["", "Peers not measured:", *(f"- {m.splitlines()[0]}" for m in skipped)]
    write_text(md_path, "\n".join(lines) + "\n")
    logging.info("%s", headline_sentence(head))


main(
    snakemake.params.bc,
    snakemake.input.jit,
    snakemake.output.csv,
    snakemake.output.headline,
    snakemake.output.md,
)
