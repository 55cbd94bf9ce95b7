"""Spread of the key statistics over realisations of the chaotic attractor.

Reads input.kernels (compiled kernels), input.runs (the scene and its re-runs with other tolerances or initial
states); writes output.json (ensemble_summary) and output.csv (one row of key numbers per run).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("chaotic_ensemble")
configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_csv, write_json
from impactosc.statistics.ensemble import ensemble_summary, ensemble_table
from impactosc.statistics.impact_train import AnalysisOptions
from impactosc.statistics.train_analysis import ensemble_members

t0 = time.perf_counter()
members = ensemble_members(snakemake.input.runs, AnalysisOptions.from_config(snakemake.params.analysis))
summary = ensemble_summary(members)
write_json(snakemake.output.json, summary, sources=snakemake.input.runs)
write_csv(snakemake.output.csv, ensemble_table(members), sources=snakemake.input.runs)
logging.info(f"{len(members)} runs; {time.perf_counter() - t0:.2f} s")
