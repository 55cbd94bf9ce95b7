"""Runs chained through a restitution law's contact carry the contact's onset velocity: a chain
split inside a contact is the unbroken run, and the chained products (sweeps in chunks,
surrogate ramps, long surrogates) build for such a law. Model BC's own chains are covered by
their tests (test_sweep_chunks, test_surrogate_cli, test_encoder_sweep, ...)."""

import dataclasses
import math

import numpy as np
import pytest

from impactosc.core.simulation import end_state, simulate, start_of
from impactosc.dynamics.basins import Attractor, BasinSettings, classify_state
from impactosc.dynamics.grazing import settle_orbit
from impactosc.dynamics.shooting import shoot
from impactosc.dynamics.sweep import SweepSettings, continuation
from impactosc.dynamics.sweep_chunks import sweep_chunked
from impactosc.dynamics.variational import variational_monodromy
from impactosc.model.parameters import ModelParams, ParameterError
from impactosc.records.long_surrogate import write_long_surrogate
from impactosc.records.surrogate import SurrogateOptions, surrogate_driven

# Flores' law on a soft obstacle: the period-1 orbit at w = 13.5 rad/s is in contact from phase
# 0.97 to 0.69 of the next period, so every phase-0 restart lies inside a contact
# (tests/test_shooting_contact.py).
FLORES = dataclasses.replace(ModelParams(), law="flores", e=0.6, kI=1e7, T=0.0)
OMEGA = 13.5
PERIOD = 2 * math.pi / OMEGA
ON_ORBIT = np.array([-2.0051e-3, 1.4437e-3, 7.2537e-3])  # (x, v, v0) at phase 0, rounded
TIGHT = dict(rtol=1e-12, atol=1e-14)


def test_a_chain_split_inside_a_contact_is_the_unbroken_run():
    whole = simulate(OMEGA, 0.0, 2 * PERIOD, **start_of(ON_ORBIT), params=FLORES, record=(), **TIGHT)
    first = simulate(OMEGA, 0.0, PERIOD, **start_of(ON_ORBIT), params=FLORES, record=(), **TIGHT)
    split = end_state(first)
    assert split[0] > FLORES.xI and math.isfinite(split[2])  # the split lies inside a contact
    rest = simulate(OMEGA, 0.0, PERIOD, **start_of(split), params=FLORES, record=(), **TIGHT)
    # the restart changes only the step sequence: the solver's error at rtol 1e-12 (measured
    # 4e-16 m, 3e-13 m/s in v and 2e-13 m/s in v0)
    np.testing.assert_allclose(end_state(rest), end_state(whole), rtol=0, atol=1e-12)
    # what carrying v0 buys: the same split with the contact's v0 doubled ends 1e3 times further off
    wrong = split * [1, 1, 2]
    off = simulate(OMEGA, 0.0, PERIOD, **start_of(wrong), params=FLORES, record=(), **TIGHT)
    assert np.max(np.abs(end_state(off) - end_state(whole))) > 1e-9
    # and without it the run is refused, not silently wrong
    with pytest.raises(ParameterError, match="contact_v0"):
        simulate(OMEGA, 0.0, PERIOD, x0=split[0], v0=split[1], params=FLORES, record=())


def test_a_chunked_sweep_is_the_sequential_one_through_contacts():
    settings = SweepSettings(params=FLORES, n_transient=3, n_record=2, n_initial=200)
    omegas = np.round(np.linspace(13.4, 13.6, 5), 9)
    sequential = continuation(omegas, settings)
    assert np.all(np.isfinite(sequential.contact_v0_end))  # every w ends inside a contact
    chunked = sweep_chunked(omegas, settings, n_chunks=2, stride=2)
    # the second chunk restarts from the coarse pass's end state inside a contact, v0 included (a
    # chunk without it would be refused: status CORE_ERROR); the coarse pass took other runs to
    # get there, a difference the orbit contracts by 1e-2 a period (measured 4e-14 m)
    assert np.all(chunked.status == 0)
    np.testing.assert_allclose(chunked.poincare_x, sequential.poincare_x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(chunked.contact_v0_end, sequential.contact_v0_end, rtol=0, atol=1e-11)


def test_a_surrogate_ramp_of_a_restitution_law_follows_the_unbroken_run():
    options = SurrogateOptions(rate=500.0)
    rec, truth = surrogate_driven([OMEGA] * 4, options, params=FLORES, n_initial=200)
    whole = simulate(OMEGA, 199.5 * PERIOD, 4 * PERIOD, params=FLORES, record=("poincare",))
    # per-period restarts inside the contact against one run (rtol 1e-10 on mm states: ~1e-13 m,
    # and the orbit contracts by 1e-2 a period, so the restarts' errors do not grow)
    np.testing.assert_allclose(truth["poincare"]["x"], whole.events["poincare"]["x"][:4], rtol=0, atol=1e-11)
    assert rec.x.size == pytest.approx(4 * PERIOD * options.rate, abs=2)


def test_a_long_surrogate_of_a_restitution_law_builds_in_segments(tmp_path):
    _, truth = write_long_surrogate(
        tmp_path / "flores.h5", OMEGA, 6 * PERIOD, SurrogateOptions(rate=500.0), transient=100 * PERIOD,
        segment=2 * PERIOD, params=FLORES,
    )  # fmt: skip
    whole = simulate(OMEGA, 99.5 * PERIOD, 6.6 * PERIOD, params=FLORES, record=("poincare",))
    n = truth["poincare"]["x"].size
    assert n >= 6
    np.testing.assert_allclose(truth["poincare"]["x"], whole.events["poincare"]["x"][:n], rtol=0, atol=1e-11)


def test_the_variational_check_refuses_other_laws():
    with pytest.raises(ValueError, match="flores"):
        variational_monodromy(ON_ORBIT[:2], OMEGA, 1, FLORES)


def test_a_basin_cell_is_classified_across_blocks_that_end_inside_contacts():
    orbit = shoot(ON_ORBIT, OMEGA, 1, FLORES)
    attractor = Attractor("period 1", 1, 1, np.array([orbit.x0]), np.array([orbit.v0]), orbit.multipliers)
    settings = BasinSettings(omega=OMEGA, block=3, params=FLORES)
    cell = classify_state(-3e-3, 0.0, [attractor], settings)
    # every block ends at phase 0, inside a contact: the cell is known only after several of them
    assert cell.cls == 1 and cell.periods > 2 * settings.block


def test_the_grazing_secant_settles_orbits_through_contacts():
    _, _, state, _ = settle_orbit(OMEGA, ON_ORBIT, FLORES, 2)
    assert math.isfinite(state[2])  # ends inside a contact, and says with which v0
    clearance, _, again, _ = settle_orbit(OMEGA, state, FLORES, 2)
    assert clearance > 0  # the orbit's maximum is a penetration
    # on the periodic orbit (the start rounded to 1e-7 has contracted by 1e-2 a period since)
    np.testing.assert_allclose(again, state, rtol=0, atol=1e-11)
