"""Assemble the work-precision outputs: merged table, speed ratios at equal error, figure.

Reads input.scenes (per-scene measurements), input.stats (the statistics against tolerance), input.jit;
writes output.table, output.headline (speed ratios), output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("work_precision")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json, read_table, write_table
from impactosc_bench.speed_at_error import speed_at_error_headline
from impactosc_bench.work_precision_figure import plot_work_precision
from impactosc_study.figures import save_figure


def _stats_rows(rows):
    """Window counts come back from CSV as a space-joined string."""
    return [{**r, "window_counts": [float(c) for c in str(r["window_counts"]).split()]} for r in rows]


def main(scene_csvs, stats_csv, jit_json, levels, out):
    rows = [r for path in scene_csvs for r in read_table(path)]
    jit = read_json(jit_json)
    write_table(out.table, rows, sources=scene_csvs)
    head = speed_at_error_headline(rows, {"impact_time_error": levels})
    write_table(
        out.headline,
        [{**h, "jit_cold": jit["cold"], "jit_cached": jit["cached"]} for h in head],
        sources=[scene_csvs, jit_json],
    )
    stats = _stats_rows(read_table(stats_csv))
    save_figure(plot_work_precision(rows, stats, jit=jit), out.png, out.pdf)
    logging.info("%d measurements, %d headline rows; wrote %s", len(rows), len(head), out.png)


main(
    snakemake.input.scenes,
    snakemake.input.stats,
    snakemake.input.jit,
    snakemake.params.levels,
    snakemake.output,
)
