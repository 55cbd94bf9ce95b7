"""Shared fixtures: the model variants the core tests need."""

import dataclasses

import pytest

from impactosc.integration.model import ModelParams


@pytest.fixture(scope="session")
def linear_params():
    """Model BC without dry friction and with the obstacle out of reach: a linear oscillator."""
    return dataclasses.replace(ModelParams(), T=0.0, xI=1.0)


@pytest.fixture(scope="session")
def cyrk():
    """The peers module with CyRK's shim built; skips where CyRK or a C++ compiler is missing."""
    from impactosc.benchmarks import peers

    pytest.importorskip("CyRK")
    try:
        peers.load_cyrk_shim()
    except peers.PeerUnavailable as e:
        pytest.skip(str(e))
    return peers
