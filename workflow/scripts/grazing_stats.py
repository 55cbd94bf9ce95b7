"""Statistics of the grazing: bracket, gap extrapolation, attractors at the paper's w.

Reads input.branch, input.from_rest (sweep HDF5) and input.bisection (JSON); writes output.stats (JSON: the
claim and the per-w arrays the supplementary figure plots).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("grazing_stats")
configure_logging(snakemake)

import logging

from impactosc.io.files import write_json
from impactosc_study.grazing_evidence import grazing_summary_file

write_json(
    snakemake.output.stats,
    grazing_summary_file(
        snakemake.input.branch,
        snakemake.input.bisection,
        snakemake.input.from_rest,
        snakemake.params.paper_omegas,
        snakemake.params.n_fit,
    ),
    final_newline=True,
    sources=snakemake.input,
)
logging.info(f"wrote {snakemake.output.stats}")
