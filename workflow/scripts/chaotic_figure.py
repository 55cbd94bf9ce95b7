"""Draw one of the paper's Figs 6-11, the chaotic regime (rules fig06 to fig11; params.figure).

Reads input.run (Figs 6, 7: the scene's run file) or input.stats (Figs 8-11: statistics JSONs, model
first); writes output.png, output.pdf (drawing in impactosc_study.figures.chaotic).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("fig06")
configure_logging(snakemake)

import logging

from impactosc_study.figures import save_figure
from impactosc_study.figures.chaotic import make_figure

inputs = snakemake.input
# a Snakemake Namedlist: `in` looks at its values, .keys() at its names
run = inputs.run if "run" in inputs.keys() else None  # noqa: SIM118
stats = list(inputs.stats) if "stats" in inputs.keys() else []  # noqa: SIM118
fig = make_figure(
    snakemake.params.figure,
    run=run,
    stats=stats,
    portrait_span=snakemake.params.portrait_span,
)
save_figure(fig, snakemake.output.png, snakemake.output.pdf)
logging.info(f"figure {snakemake.params.figure}: {run or ', '.join(stats)}")
