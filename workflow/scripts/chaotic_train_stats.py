"""Statistics of one impact train (model run or measured/surrogate record).

Reads input.kernels (compiled kernels), input.events (HDF5 run file) and params.analysis; writes output.json
(impactosc.statistics.train_analysis.analyse_train).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("chaotic_train_stats", train="model")
configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_json
from impactosc.statistics.impact_train import AnalysisOptions, load_train
from impactosc.statistics.train_analysis import analyse_train

t0 = time.perf_counter()
train = load_train(snakemake.input.events, label=snakemake.params.label)
stats = analyse_train(train, AnalysisOptions.from_config(snakemake.params.analysis))
write_json(snakemake.output.json, stats, sources=snakemake.input.events)
logging.info(
    f"{train.label}: {train.times.size} impacts on [{train.t_start}, {train.t_stop}] s "
    f"({train.span_source}); {time.perf_counter() - t0:.2f} s"
)
