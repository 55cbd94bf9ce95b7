"""A sweep split into chunks (coarse seeding pass + chunk jobs + merge) equals the sequential one.

The range 38.0 -> 36.6 rad/s (decreasing, 29 w) crosses the period-doubling 2 -> 1 near
37.2 rad/s, where convergence is slowest, so a badly seeded chunk would show there.
"""

import itertools

import numpy as np
import pytest

from impactosc.dynamics import sweep as sweep_mod
from impactosc.dynamics.diagram import classify_sweep
from impactosc.dynamics.sweep import (
    CORE_ERROR,
    OK,
    STALLED,
    SweepSettings,
    continuation,
    load_sweep,
    omega_grid,
    save_sweep,
)
from impactosc.dynamics.sweep_chunks import coarse_pass, merge_chunks, plan_chunks, run_chunk, sweep_chunked

SETTINGS = SweepSettings(n_transient=100, n_record=24, n_initial=300)
GRID = omega_grid(38.0, 36.6, 29)


@pytest.fixture(scope="module")
def sequential():
    return continuation(GRID, SETTINGS)


@pytest.fixture(scope="module")
def chunked():
    return sweep_chunked(GRID, SETTINGS, n_chunks=3, stride=4)


def test_chunked_equals_sequential(sequential, chunked):
    np.testing.assert_array_equal(chunked.omega, sequential.omega)
    a, b = classify_sweep(sequential), classify_sweep(chunked)
    np.testing.assert_array_equal(a.period, b.period)
    np.testing.assert_array_equal(a.impacts, b.impacts)
    assert set(a.period.tolist()) >= {1, 2}  # the range does cross the doubling
    # 1e-9 m: a chunk's seed differs from the sequential state, but after the warm-up w
    # values and >= 100 transient periods each the difference has contracted onto the
    # attractor (measured: ~1e-13 m); 1e-9 m is 1000x below the period tolerance (1 um).
    np.testing.assert_allclose(chunked.poincare_x, sequential.poincare_x, rtol=0, atol=1e-9)
    np.testing.assert_allclose(chunked.poincare_v, sequential.poincare_v, rtol=0, atol=1e-7)
    np.testing.assert_array_equal(chunked.impact_offsets, sequential.impact_offsets)
    np.testing.assert_allclose(chunked.impact_t, sequential.impact_t, rtol=0, atol=1e-9)


def test_first_chunk_is_the_sequential_sweep_bit_for_bit(sequential):
    (a, b), *_ = plan_chunks(GRID.size, 3, 4)
    first = run_chunk(GRID, SETTINGS, (a, b), 4, None)
    np.testing.assert_array_equal(first.poincare_x, sequential.poincare_x[a:b])


def test_chunks_start_on_the_coarse_grid_and_cover_the_sweep():
    for n, k, stride in [(1001, 4, 10), (1044, 4, 10), (29, 3, 4), (10, 1, 3)]:
        plan = plan_chunks(n, k, stride)
        assert len(plan) == k and plan[0][0] == 0 and plan[-1][1] == n
        assert all(a % stride == 0 and a < b for a, b in plan)
        assert all(p[1] == q[0] for p, q in itertools.pairwise(plan))
    with pytest.raises(ValueError, match="coarse points"):
        plan_chunks(10, 5, 4)


def test_continuation_chains_states_and_records_whole_periods(sequential):
    assert sequential.poincare_x.shape == (GRID.size, SETTINGS.n_record)
    np.testing.assert_array_equal(sequential.x_start[1:], sequential.x_end[:-1])
    np.testing.assert_array_equal(sequential.v_start[1:], sequential.v_end[:-1])
    assert np.all(sequential.status == OK)
    for i in range(len(sequential)):
        t = sequential.impacts(i)
        assert np.all((t >= 0) & (t < SETTINGS.n_record * 2 * np.pi / GRID[i]))


def test_save_load_roundtrip(tmp_path, sequential):
    path = save_sweep(tmp_path / "s.h5", sequential, name="test")
    back, attrs = load_sweep(path)
    assert attrs["name"] == "test" and back.settings == SETTINGS
    for k in ("poincare_x", "impact_t", "impact_offsets", "status", "min_gap"):
        np.testing.assert_array_equal(getattr(back, k), getattr(sequential, k))


def test_merge_rejects_mixed_settings(sequential):
    other = SweepSettings(n_transient=50, n_record=24, n_initial=300)
    part = continuation(GRID[:2], other)
    with pytest.raises(ValueError, match="settings"):
        merge_chunks([sequential.subset(0, 2), part])


def test_seeds_must_match_the_grid():
    seeds = coarse_pass(omega_grid(30.0, 31.0, 9), SETTINGS, 4)
    with pytest.raises(ValueError, match="seeds do not belong"):
        run_chunk(GRID, SETTINGS, (4, 8), 4, seeds)


def test_a_stuck_w_is_abandoned_and_the_sweep_goes_on(monkeypatch):
    # Budget 120 steps per period, checked every 100 steps: w = 16 needs ~177 per period,
    # w = 30 about 43 (measured with these settings and an unlimited budget).
    monkeypatch.setattr(sweep_mod, "_CHUNK_STEPS", 100)
    monkeypatch.setattr(sweep_mod, "_STALL_PACE", 1e9)  # test the total budget alone
    tight = SweepSettings(n_transient=20, n_record=6, n_initial=20, max_steps_per_period=120)
    messages = []
    res = continuation([16.0, 30.0, 30.5], tight, on_failure=lambda i, w, m: messages.append((i, m)))
    assert res.status.tolist() == [STALLED, OK, OK]
    assert np.all(np.isnan(res.poincare_x[0])) and res.impacts(0).size == 0
    assert res.x_start[1] == tight.x0 and res.x_end[0] == tight.x0  # the next w starts where this one did
    assert res.x_start[2] == res.x_end[1]
    assert messages and messages[0][0] == 0 and "step budget" in messages[0][1]


def test_a_creeping_integration_is_abandoned_quickly():
    # A state on the w = 41.39 attractor where the core before commit 19ba11d crept in a
    # sticking contact at ~5e-12 s per step (the stall that first left 112 w of Fig 2 empty).
    # Whether or not a core gets past it, the sweep must neither hang nor take long: the
    # pace check abandons a creeping run after one 20000-step call.
    s = SweepSettings(n_transient=0, n_record=3, n_initial=0)
    res = continuation([41.385542168674704], s, x0=-0.002101904203450328, v0=-0.018444033329564975)
    assert res.status[0] in (OK, STALLED)
    # the work, not the wall time: at most one call of the core beyond what 3 periods may take
    assert res.n_steps[0] <= sweep_mod._CHUNK_STEPS + 3 * s.max_steps_per_period


def test_a_core_error_is_abandoned(monkeypatch):
    real = sweep_mod.simulate

    def flaky(omega, *a, **kw):
        if omega == 30.5:
            raise RuntimeError("implicit step size underflow in the sticking phase")
        return real(omega, *a, **kw)

    monkeypatch.setattr(sweep_mod, "simulate", flaky)
    s = SweepSettings(n_transient=10, n_record=4, n_initial=10)
    res = continuation([30.0, 30.5, 31.0], s)
    assert res.status.tolist() == [OK, CORE_ERROR, OK]
    w, _x = res.poincare_points()
    assert w.size == 8 and not np.any(w == 30.5)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(n_record=0), "n_record"),
        (dict(n_transient=1.5), "integer"),
        (dict(max_steps_per_period=10), "max_steps_per_period"),
    ],
)
def test_settings_reject_bad_values(kw, match):
    with pytest.raises(ValueError, match=match):
        SweepSettings(**kw)


@pytest.mark.parametrize("omegas, match", [([30.0, 29.0, 29.5], "monotone"), ([30.0, -1.0], "> 0"), ([], "non-empty")])
def test_continuation_rejects_bad_grids(omegas, match):
    with pytest.raises(ValueError, match=match):
        continuation(omegas, SETTINGS)
