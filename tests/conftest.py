"""Shared fixtures: the model variants the core tests need."""

import dataclasses

import pytest

from impactosc.model.parameters import ModelParams


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
