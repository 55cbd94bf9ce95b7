"""The attractor summary of the branch run at w = 23.05 (Fig 4a): period, impacts, spectrum's modes.

Reads input.before_grazing_branch (the run file of the branch's attractor) and params.spectrum; writes
output.stats (JSON, keyed by the input's name as periodic_stats keys its runs).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("before_grazing_stats")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_json
from impactosc.statistics.periodic_train import run_summary

run = snakemake.input.before_grazing_branch
summary, _ = run_summary(run, snakemake.params.spectrum)
write_json(snakemake.output.stats, {"before_grazing_branch": summary}, final_newline=True, sources=[run])
logging.info(f"wrote {snakemake.output.stats}")
