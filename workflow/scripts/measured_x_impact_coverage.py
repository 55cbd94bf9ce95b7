"""Merge the noise levels of the obstacle-estimate coverage study.

Reads input.parts (JSON draws per noise level); writes output.csv (one row per level) and output.draws
(every draw).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_x_impact_coverage")
configure_logging(snakemake)

import logging

from impactosc.io.files import read_json, write_csv
from impactosc_study.coverage import coverage_summary

levels = [read_json(path)["draws"] for path in snakemake.input.parts]
summaries = [coverage_summary(rows) for rows in levels]
write_csv(snakemake.output.csv, summaries, sources=snakemake.input.parts)
write_csv(snakemake.output.draws, [r for rows in levels for r in rows], sources=snakemake.input.parts)
for s in summaries:
    logging.info(
        f"{s['noise_m'] * 1e6:g} um, exponent {s['exponent']}: mean error {s['mean_error_m'] * 1e6:+.2f} +- {s['mean_error_se_m'] * 1e6:.2f} um, "
        f"sd {s['sd_error_m'] * 1e6:.2f} um vs median sigma {s['median_sigma_m'] * 1e6:.2f} um, "
        f"within 1 / 2 sigma {s['within_1_sigma']} / {s['within_2_sigma']} of {s['n_draws']}"
    )
