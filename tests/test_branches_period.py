"""Reading a diagram on synthetic data: periods, impacts per orbit, transitions, grazing.

Synthetic Poincare sequences have a known answer: a fixed point (period 1), period 2,
period 4, a quasi-periodic rotation (no period), noise (no period) and a periodic
orbit blurred by noise below / above the tolerance.
"""

import math

import numpy as np
import pytest

from impactosc.dynamics.diagram import BranchTable, differing_windows, find_grazings, segments, transitions
from impactosc.statistics.periods import FAILED, NONPERIODIC, detect_period, impacts_per_orbit

TOL = 1e-6  # m, the workflow's default x_tol
RNG = np.random.default_rng(2024)


def _orbit(levels, n=100):
    return np.resize(np.asarray(levels, dtype=float), n)


def test_fixed_point():
    assert detect_period(np.full(100, -4.2e-3) + RNG.normal(0, 1e-9, 100), TOL) == 1


def test_period_2():
    assert detect_period(_orbit([-9e-3, -6e-3]), TOL) == 2


def test_period_4_is_not_reported_as_2():
    # a period-4 orbit near its doubling: pairs differ by 5 um only, above the tolerance
    x = _orbit([-9e-3, -6e-3, -9e-3 + 5e-6, -6e-3 - 5e-6])
    assert detect_period(x, TOL) == 4


def test_period_4_below_tolerance_reads_as_2():
    # the same orbit whose splitting (0.5 um) is below the tolerance: read as period 2
    x = _orbit([-9e-3, -6e-3, -9e-3 + 5e-7, -6e-3 - 5e-7])
    assert detect_period(x, TOL) == 2


def test_quasi_periodic_rotation_has_no_period():
    golden = (math.sqrt(5) - 1) / 2
    x = -5e-3 + 1e-3 * np.cos(2 * math.pi * golden * np.arange(100))
    assert detect_period(x, TOL) == NONPERIODIC


def test_noise_has_no_period():
    assert detect_period(RNG.normal(-5e-3, 1e-3, 100), TOL) == NONPERIODIC


def test_periodic_orbit_with_noise_below_and_above_tolerance():
    x = _orbit([-9e-3, -6e-3, -7e-3])
    assert detect_period(x + RNG.normal(0, 1e-8, x.size), TOL) == 3
    assert detect_period(x + RNG.normal(0, 1e-5, x.size), TOL) == NONPERIODIC


def test_two_columns_with_own_tolerances():
    x = np.full(60, -3e-3)
    v = _orbit([0.1, 0.2], 60)  # period 2 only in v
    assert detect_period(np.column_stack([x, v]), (TOL, 1e-4)) == 2
    assert detect_period(x, TOL) == 1


def test_max_period_and_repeats():
    x = _orbit(np.linspace(-9e-3, -2e-3, 40), 100)  # period 40: only 2.5 repeats in 100
    assert detect_period(x, TOL) == NONPERIODIC  # default max_period = 100 // 3 = 33
    assert detect_period(x, TOL, max_period=40) == 40


@pytest.mark.parametrize(
    "bad, match",
    [
        (dict(points=[1.0, np.nan, 1.0]), "finite"),
        (dict(points=[1.0]), "n >= 2"),
        (dict(points=[1.0, 1.0, 1.0], tol=0.0), "tol"),
        (dict(points=[1.0, 1.0, 1.0], max_period=3), "max_period"),
    ],
)
def test_detect_period_rejects_bad_input(bad, match):
    kw = {"tol": TOL, **bad}
    with pytest.raises(ValueError, match=match):
        detect_period(kw.pop("points"), **kw)


def test_impacts_per_orbit_counts_whole_orbits():
    T = 0.2728  # s, forcing period near w = 23.03
    # 4 impacts every 3 forcing periods, one of them exactly on the orbit boundary
    phases = np.array([0.0, 0.7, 1.5, 2.2]) * T
    t = (phases[None, :] + 3 * T * np.arange(33)[:, None]).ravel()
    assert impacts_per_orbit(t, T, 100, 3) == 4
    assert impacts_per_orbit(t, T, 100, 6) == 8
    with pytest.raises(ValueError, match="period"):
        impacts_per_orbit(t, T, 2, 3)


def _table(omega, period, impacts, gaps=None):
    omega = np.asarray(omega, dtype=float)
    period = np.asarray(period)
    impacts = np.asarray(impacts)
    rate = np.where(period > 0, impacts / np.maximum(period, 1), 1.3)
    gaps = np.full(omega.size, np.nan) if gaps is None else np.asarray(gaps, dtype=float)
    return BranchTable(omega, period, impacts, rate, np.zeros(omega.size, dtype=int), gaps)


def test_transitions_of_a_reverse_cascade():
    # decreasing w: chaos, period 4, period 2 (with one unsettled point), period 1
    w = 41.0 - 0.1 * np.arange(16)
    p = [0, 0, 0, 4, 4, 4, 2, 2, 0, 2, 2, 2, 1, 1, 1, 1]
    q = [-1, -1, -1, 4, 4, 4, 2, 2, -1, 2, 2, 2, 1, 1, 1, 1]
    tr = transitions(_table(w, p, q))
    assert [t.kind for t in tr] == ["non-periodic boundary", "period doubling", "period doubling"]
    assert tr[1].detail == "period 4 -> 2"
    # the unsettled point inside the period-2 window does not split it
    assert tr[2].omega_before == pytest.approx(w[11]) and tr[2].omega_after == pytest.approx(w[12])
    assert [s.n_points for s in segments(_table(w, p, q))] == [3, 3, 2, 1, 3, 4]


def test_impact_adding_with_a_closing_near_miss_is_grazing():
    # decreasing w: period 1 with a near miss whose gap closes linearly at w = 23.045,
    # then period 3 with 4 impacts (the paper's w = 23.03 orbit)
    w = np.round(23.2 - 0.02 * np.arange(12), 6)
    p = np.where(w > 23.045, 1, 3)
    q = np.where(w > 23.045, 1, 4)
    gaps = np.where(w > 23.045, 1.1e-3 * (w - 23.045), np.nan)
    t = _table(w, p, q, gaps)
    tr = transitions(t)
    assert [x.kind for x in tr] == ["impact adding"]
    assert tr[0].detail == "impacts per forcing period 1 -> 4/3"
    (g,) = find_grazings(t)
    assert g.omega_zero == pytest.approx(23.045, abs=1e-9)
    assert g.bracket == pytest.approx((23.04, 23.06))
    # the same jump without a near miss is impact adding but no grazing
    assert find_grazings(_table(w, p, q)) == []


def test_differing_windows_flags_coexisting_attractors_only():
    w_up = np.round(30.0 + 0.1 * np.arange(21), 6)
    w_down = w_up[::-1]
    up = _table(w_up, np.where(w_up < 31.2, 1, 2), np.where(w_up < 31.2, 1, 2))
    down = _table(w_down, np.where(w_down < 30.6, 1, 2), np.where(w_down < 30.6, 1, 2))  # hysteresis 30.6-31.1
    assert differing_windows(up, down) == [pytest.approx((30.6, 31.1))]
    same = _table(w_down, np.where(w_down < 31.2, 1, 2), np.where(w_down < 31.2, 1, 2))
    assert differing_windows(up, same) == []
    failed = _table(w_down, np.full(21, FAILED), np.full(21, -1))
    assert differing_windows(up, failed) == []


def _reading(t):
    from impactosc.dynamics.diagram import SweepReading, find_grazings, segments, transitions

    return SweepReading("decreasing", t.direction, t, segments(t), transitions(t), find_grazings(t), [])


def test_paper_rows_judge_the_cascade_and_the_grazing():
    from impactosc_study.paper.rows.bifurcation import bifurcation_rows as paper_rows

    # decreasing w: period 2 down to 37.26, period 1 with a closing near miss down to 23.06,
    # then period 3 with 4 impacts (grid 0.02 rad/s, only the relevant stretches)
    w = np.round(np.concatenate([37.30 - 0.02 * np.arange(6), 23.14 - 0.02 * np.arange(8)]), 6)
    p = np.where(w > 37.25, 2, np.where(w > 23.045, 1, 3))
    q = np.where(w > 37.25, 2, np.where(w > 23.045, 1, 4))
    gaps = np.where((p == 1) & (w < 24), 1.1e-3 * (w - 23.045), np.nan)
    rows = paper_rows(_reading(_table(w, p, q, gaps)), "cmd", reference_grazing={"omega_g": 23.0441})
    assert [r["agrees"] for r in rows] == ["yes", "yes", "yes"]
    assert "period 2 -> 1 at 37.25" in rows[0]["replication"]
    assert "23.045" in rows[1]["replication"] and "difference +0.0009" in rows[2]["replication"]
    # no doubling and no grazing: the rows say so and disagree
    flat = paper_rows(_reading(_table(w, np.ones(w.size, int), np.ones(w.size, int))), "cmd")
    assert [r["agrees"] for r in flat] == ["no", "no"]
