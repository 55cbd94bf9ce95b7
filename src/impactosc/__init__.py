"""impactosc: forced impacting oscillator (model BC) and the statistics of its impact events."""

import hashlib
import os
import sys
from pathlib import Path

__version__ = "0.1.0"

# Sources of the compiled core. numba's on-disk cache (cache=True) only notices edits to the
# file of the function it caches, not to the functions it calls in other modules; keying the
# cache directory on a hash of all of them makes any edit recompile instead of silently
# reusing stale machine code. An explicit NUMBA_CACHE_DIR is respected.
CORE_SOURCES = (
    "model/parameters.py",
    "model/equations.py",
    *(
        f"core/{name}.py"
        for name in (
            "layout",
            "tableau",
            "vector_fields",
            "dop853",
            "radau",
            "events",
            "transitions",
            "sampling",
            "pieces",
            "time_pieces",
            "transformed_pieces",
            "implicit",
            "driver",
        )
    ),
)


def _core_cache_dir() -> str:
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    for name in CORE_SOURCES:
        digest.update((here / name).read_bytes())
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "impactosc", "numba-" + digest.hexdigest()[:16])


# Set through the environment, which numba reads when it is imported, so that importing this
# package does not import numba (0.4 s that the plotting and table jobs do not need). Child
# processes inherit it; the companion variable tells an inherited automatic setting (recomputed
# here, for this tree's sources) from one the user chose (respected).
_AUTO_CACHE_DIR = "IMPACTOSC_AUTO_NUMBA_CACHE_DIR"
if os.environ.get("NUMBA_CACHE_DIR", "") in ("", os.environ.get(_AUTO_CACHE_DIR)):
    os.environ["NUMBA_CACHE_DIR"] = os.environ[_AUTO_CACHE_DIR] = _core_cache_dir()
    if "numba" in sys.modules:  # numba has read its settings already: set this one directly
        from numba.core import config as _numba_config

        _numba_config.CACHE_DIR = os.environ["NUMBA_CACHE_DIR"]
