"""Statistics of one impact train (model run or measured/surrogate record).

Reads snakemake.input.events (HDF5 run-file contract) and the analysis options in
snakemake.params.analysis; writes snakemake.output.json (impactosc.chaotic.analyse_train).
"""

import time
from pathlib import Path

from impactosc.analysis.chaotic import AnalysisOptions, analyse_train, load_train, write_json

t0 = time.perf_counter()
train = load_train(snakemake.input.events, label=snakemake.params.label)  # noqa: F821
stats = analyse_train(train, AnalysisOptions.from_config(snakemake.params.analysis))  # noqa: F821
write_json(snakemake.output.json, stats)  # noqa: F821
Path(snakemake.log[0]).write_text(  # noqa: F821
    f"{train.label}: {train.times.size} impacts on [{train.t_start}, {train.t_stop}] s "
    f"({train.span_source}); {time.perf_counter() - t0:.2f} s\n"
)
