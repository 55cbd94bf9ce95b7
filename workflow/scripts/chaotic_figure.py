"""Draw one of the paper's Figs 6-11 (chaotic regime).

Reads snakemake.input.run (Figs 6, 7: the scene's run file) or snakemake.input.stats
(Figs 8-11: statistics JSONs, model first, then an optional second train); writes
snakemake.output.png and .pdf.  All drawing lives in impactosc.plotting.chaotic.
"""

from _logging import configure_logging

configure_logging(snakemake)  # noqa: F821

import logging

from impactosc.plotting import save_figure
from impactosc.plotting.chaotic import make_figure

inputs = snakemake.input  # noqa: F821
run = inputs.run if "run" in inputs.keys() else None
stats = list(inputs.stats) if "stats" in inputs.keys() else []
fig = make_figure(snakemake.params.figure, run=run, stats=stats,  # noqa: F821
                  portrait_span=snakemake.params.portrait_span)  # noqa: F821
save_figure(fig, snakemake.output.png, snakemake.output.pdf)  # noqa: F821
logging.info(f"figure {snakemake.params.figure}: {run or ', '.join(stats)}")  # noqa: F821
