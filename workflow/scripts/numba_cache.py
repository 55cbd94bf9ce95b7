"""Compile the numba core once into the shared cache before parallel jobs start.

Reads nothing; writes snakemake.output.marker with the compile time (cold or cached).
"""

import sys
from pathlib import Path

from impactosc.integration.simulate import warm_up


def main(marker: str, log: str) -> None:
    seconds = warm_up()
    text = f"numba core ready in {seconds:.2f} s\n"
    Path(log).write_text(text)
    Path(marker).write_text(text)


if __name__ == "__main__" and "snakemake" not in globals():
    main(sys.argv[1], sys.argv[2])
else:
    main(snakemake.output.marker, snakemake.log[0])  # noqa: F821
