"""Fig 6: the chaotic attractor's phase portrait and the amplitude spectrum of x.

Reads input.run (the chaos scene's run file, its trajectory window) and params.portrait_span (s of trajectory
in the phase portrait); writes output.png, output.pdf.
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig06")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure

fig = make_figure(6, run=snakemake.input.run, portrait_span=snakemake.params.portrait_span)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"fig06 from {snakemake.input.run}")
