"""Shared fixtures: the model variants the core tests need."""

import dataclasses

import pytest

from impactosc.integration.model import ModelParams


@pytest.fixture(scope="session")
def linear_params():
    """Model BC without dry friction and with the obstacle out of reach: a linear oscillator."""
    return dataclasses.replace(ModelParams(), T=0.0, xI=1.0)
