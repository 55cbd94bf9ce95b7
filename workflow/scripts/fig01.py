"""Fig 1: schematic of the rig with the symbols of model BC. Reads nothing; writes
snakemake.output.png and .pdf."""

from pathlib import Path

from impactosc.plotting import save_figure
from impactosc.plotting.schematic import fig01_rig

save_figure(fig01_rig(), snakemake.output.png, snakemake.output.pdf)  # noqa: F821
Path(snakemake.log[0]).write_text(f"wrote {snakemake.output.png} and {snakemake.output.pdf}\n")  # noqa: F821
