"""Logging of the workflow's scripts: every script calls ``configure_logging(snakemake)`` first.

Reads nothing; writes the rule's log file (``snakemake.log[0]``, truncated at the start of the
job). Log records go there and to stderr, Python warnings become log records, and an uncaught
exception (an import error included, since scripts call this before their other imports) is
logged with its traceback before the job fails, so the rule's log says why it failed. Not a
rule's script (the leading underscore): Snakemake puts this folder on the scripts' sys.path.
"""

import logging
import sys
from pathlib import Path

FORMAT = "%(asctime)s %(levelname)s %(name)s: %(message)s"
# libraries that log routine detail at INFO (fontTools: every glyph subset of a PDF)
QUIET = ("fontTools", "matplotlib", "PIL", "numba", "h5py")


def configure_logging(snakemake=None, level=logging.INFO):
    """Log to the rule's log file and stderr; route uncaught exceptions and warnings there.

    ``snakemake`` is the object Snakemake injects into a script; without one (a script run by
    hand) or without a ``log:`` path, records go to stderr only.
    """
    handlers = [logging.StreamHandler(sys.stderr)]
    log = list(snakemake.log) if snakemake is not None else []
    if log:
        Path(log[0]).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(logging.FileHandler(log[0], mode="w"))
    logging.basicConfig(level=level, format=FORMAT, handlers=handlers, force=True)
    for name in QUIET:
        logging.getLogger(name).setLevel(max(level, logging.WARNING))
    logging.captureWarnings(True)
    name = getattr(snakemake, "rule", None) or "script"
    logger = logging.getLogger(name)

    def log_uncaught(exc_type, exc, tb):
        if issubclass(exc_type, KeyboardInterrupt):
            sys.__excepthook__(exc_type, exc, tb)
            return
        logger.error("uncaught exception, the job fails", exc_info=(exc_type, exc, tb))

    sys.excepthook = log_uncaught
    return logger
