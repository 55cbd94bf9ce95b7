"""impactosc: forced impacting oscillator (model BC) and the statistics of its impact events.

The public API, imported on first use (``import impactosc`` loads neither numba nor SciPy)::

    from impactosc import ModelParams, simulate
    run = simulate(40.86, transient=100.0, duration=400.0)

Each subpackage lists its own public names: model, core, dynamics, statistics, records,
identification, io (and cli, the command line).
"""

import hashlib
import os
import sys
from pathlib import Path

__version__ = "0.1.0"  # the package's one version: pyproject.toml reads it (tool.setuptools.dynamic)

# Sources of the compiled core. numba's on-disk cache (cache=True) only notices edits to the
# file of the function it caches, not to the functions it calls in other modules; keying the
# cache directory on a hash of all of them makes any edit recompile instead of silently
# reusing stale machine code. An explicit NUMBA_CACHE_DIR is respected.
CORE_SOURCES = (
    "model/parameters.py",
    "model/slots.py",
    "model/contact_laws/__init__.py",
    "model/contact_laws/kernel.py",
    "model/noise_kernel.py",
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
            "turn_series",
            "sampling",
            "pieces",
            "band_crossing",
            "closed_flight",
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


from impactosc._lazy import export

# The most used names of each subpackage, by the subpackage that lists them (one home each).
export(
    globals(),
    {
        **dict.fromkeys(["ModelParams", "read_model_file", "write_model_file", "resolve_model"], "impactosc.model"),
        **dict.fromkeys(["simulate", "SimulationResult", "Window", "StallError", "warm_up"], "impactosc.core"),
        **dict.fromkeys(
            [
                "SweepSettings",
                "continuation",
                "load_sweep",
                "read_sweep",
                "shoot",
                "PeriodicOrbit",
                "seed_from_rest",
                "continue_branch",
                "locate",
                "trace_curve",
                "locate_grazing",
                "locate_orbit_grazing",
                "lyapunov_spectrum",
                "classify_state",
            ],
            "impactosc.dynamics",
        ),
        **dict.fromkeys(
            ["ImpactTrain", "AnalysisOptions", "analyse_train", "inter_impact_intervals"], "impactosc.statistics"
        ),
        **dict.fromkeys(
            [
                "Record",
                "read_record",
                "write_record",
                "ExtractOptions",
                "extract_events",
                "estimate_x_impact",
                "SurrogateOptions",
                "surrogate_record",
            ],
            "impactosc.records",
        ),
        **dict.fromkeys(["identify", "Identification", "choose_model"], "impactosc.identification"),
        **dict.fromkeys(["read_run", "write_run"], "impactosc.io"),
    },
)
