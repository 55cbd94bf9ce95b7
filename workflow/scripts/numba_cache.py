"""Compile the numba core once into the shared cache before parallel jobs start.

Reads nothing; writes snakemake.output.marker with the compile time (cold or cached).
"""

from _logging import configure_logging

configure_logging(globals().get("snakemake"))  # None when run by hand

import logging
import sys
from pathlib import Path

from impactosc.integration.simulate import warm_up


def main(marker: str) -> None:
    seconds = warm_up()
    text = f"numba core ready in {seconds:.2f} s"
    logging.info(text)
    Path(marker).write_text(text + "\n")


if __name__ == "__main__" and "snakemake" not in globals():
    main(sys.argv[1])
else:
    main(snakemake.output.marker)
