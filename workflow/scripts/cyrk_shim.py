"""Build the CyRK shim of the compiled peers once (impactosc_bench.cyrk_shim), before the timing jobs.

Reads nothing; writes output.marker (JSON: built and the seconds it took, or why the peers cannot run
here: a missing peers extra is a note, not a failure, and the timing jobs report the peers unavailable).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("cyrk_shim")
configure_logging(snakemake)

import logging
import time

from impactosc.io.files import write_json
from impactosc_bench.cyrk_shim import PeerUnavailable, load_cyrk_shim


def main(marker):
    t0 = time.perf_counter()
    try:
        load_cyrk_shim()
    except PeerUnavailable as e:
        logging.info("CyRK shim not built: %s", e)
        write_json(marker, {"built": False, "reason": str(e)}, final_newline=True)
        return
    seconds = time.perf_counter() - t0
    logging.info("CyRK shim ready in %.1f s", seconds)
    write_json(marker, {"built": True, "seconds": seconds}, final_newline=True)


main(snakemake.output.marker)
