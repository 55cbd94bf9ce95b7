"""Shared fixtures: the model variants the core tests need.

Also the parallel run's set-up (``pytest -n 2``, pytest-xdist, as ``make test`` runs it): the
numba core and the record and mixture kernels are compiled into their on-disk cache once, in the
controller, before the workers start, and the longest files are handed out first.
"""

import dataclasses
import time

import pytest

from impactosc.model.parameters import ModelParams

# The longest files of the default run (per-file totals of `pytest -n 2 --dist loadfile`): each is
# one unit of work for a worker (--dist loadfile), so they start first, and the short files fill
# the other worker meanwhile, instead of one of them starting last and running alone at the end.
LONGEST_FIRST = ("test_workflow_tiny.py",)


def pytest_configure(config):
    """In the controller of a parallel run, before the workers start: the core compiled (or loaded)
    once. The workers share numba's cache directory (impactosc keys it on the core's sources);
    numba writes each cache file atomically, but two workers compiling into an empty cache would
    each spend the compile (about 20 s) and could number two signatures' files alike, and one
    would overwrite the other's."""
    if hasattr(config, "workerinput") or not config.getoption("numprocesses", None):
        return  # a worker, or a run without workers
    from impactosc.core.simulation import warm_up
    from impactosc.records.warm_up import warm_up_kernels

    t0 = time.perf_counter()
    warm_up()
    warm_up_kernels()  # the record and mixture kernels, which both workers' tests use too
    config.stash[_WARM] = time.perf_counter() - t0


_WARM = pytest.StashKey[float]()


def pytest_report_header(config):
    if _WARM in config.stash:
        return (
            f"numba core and kernels ready in the shared cache before the workers started: {config.stash[_WARM]:.1f} s"
        )
    return None


def pytest_collection_modifyitems(config, items):
    """The files of LONGEST_FIRST first, in that order, the others as collected (a stable sort)."""
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))


@pytest.fixture(scope="session")
def linear_params():
    """Model BC without dry friction and with the obstacle out of reach: a linear oscillator."""
    return dataclasses.replace(ModelParams(), T=0.0, xI=1.0)


@pytest.fixture(scope="session")
def cyrk():
    """The CyRK runs module with CyRK's shim built; skips where CyRK or a C++ compiler is missing."""
    from impactosc_bench import cyrk_runs, cyrk_shim

    pytest.importorskip("CyRK")
    try:
        cyrk_shim.load_cyrk_shim()
    except cyrk_shim.PeerUnavailable as e:
        pytest.skip(str(e))
    return cyrk_runs
