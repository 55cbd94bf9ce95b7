"""Synthetic impact trains with known statistics, shared by the statistics tests."""

import numpy as np
import pytest

POISSON_RATE = 7.0  # impacts per second, close to the chaotic scene (2875 / 400 s)
POISSON_SPAN = 1000.0  # s
PERIOD4_LEVELS = np.array([0.1, 0.25, 0.18, 0.2884])  # s; sum 0.8184 s as in paper Fig. 5


@pytest.fixture(scope="session")
def poisson_params():
    """(rate in 1/s, span in s) of :func:`poisson_train`."""
    return POISSON_RATE, POISSON_SPAN


@pytest.fixture(scope="session")
def period4_levels():
    """The 4 interval levels (s) of :func:`period4_times`."""
    return PERIOD4_LEVELS.copy()


@pytest.fixture(scope="session")
def poisson_train():
    """Poisson train, rate 7/s on [0, 1000] s (about 7000 impacts), fixed seed."""
    rng = np.random.default_rng(20240601)
    n = rng.poisson(POISSON_RATE * POISSON_SPAN)
    return np.sort(rng.uniform(0.0, POISSON_SPAN, n))


@pytest.fixture(scope="session")
def periodic_train():
    """Strictly periodic train, period 0.1 s, phase 0.05 s (no impact on a window edge)."""
    return 0.05 + 0.1 * np.arange(1000)


@pytest.fixture(scope="session")
def period4_times():
    """489 impacts whose 488 intervals cycle through 4 levels with 1e-7 s jitter."""
    rng = np.random.default_rng(7)
    s = np.tile(PERIOD4_LEVELS, 122) + rng.normal(0.0, 1e-7, 488)
    return 200.0 + np.concatenate([[0.0], np.cumsum(s)])


@pytest.fixture(scope="session")
def gamma_mixture_sample():
    """n=3000 from 0.4 Gamma(6, 0.01 s) + 0.6 Gamma(21, 0.01 s): modes 0.05 s and 0.2 s."""
    rng = np.random.default_rng(11)
    n = 3000
    first = rng.random(n) < 0.4
    return np.where(first, rng.gamma(6.0, 0.01, n), rng.gamma(21.0, 0.01, n))
