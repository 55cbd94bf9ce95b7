"""The grazing-location pieces on synthetic gap curves with known answers."""

import math

import numpy as np
import pytest

from impactosc.dynamics.grazing import GrazingBracket, Trial, bisect_transition, extrapolate_gap_zero, find_grazing_step
from impactosc.dynamics.sweep import branch_grid, regular_grid
from impactosc_study.grazing_evidence import grazing_statistics

W_G = 23.0441234  # synthetic grazing w (rad/s)
SLOPE = 1.1e-3  # m per rad/s, like the model's near miss


def synthetic_branch():
    """Decreasing w: a decoy transition at 23.20 (a period change with a large gap), then a
    near miss closing linearly on W_G, contact below it (impacts per period 1 -> 4/3)."""
    w = np.round(np.arange(23.30, 22.999, -0.001), 9)
    gap = np.where(w > W_G, SLOPE * (w - W_G), np.nan)
    ipp = np.where(w > W_G, 1.0, 4 / 3)
    ipp[w > 23.2] = 2.0  # decoy: impacts per period change at 23.20 but the gap there is 1.7e-4 m
    return w, gap, ipp


def test_find_grazing_step_skips_decoy():
    w, gap, ipp = synthetic_branch()
    i = find_grazing_step(w, gap, ipp)
    assert w[i] > W_G > w[i + 1]
    assert w[i] - w[i + 1] == pytest.approx(0.001)


def test_find_grazing_step_errors():
    with pytest.raises(ValueError, match="differ in length"):
        find_grazing_step([1.0, 2.0], [1.0], [1.0, 1.0])
    with pytest.raises(ValueError, match="no step"):
        find_grazing_step([3.0, 2.0, 1.0], [1e-4, 1e-4, 1e-4], [1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="non-finite"):
        find_grazing_step([3.0, np.inf], [1e-4, 1e-4], [1.0, 2.0])


def threshold_trial(w_true):
    """Synthetic model: contact below w_true; the 'state' records the w it came from."""

    def trial(w, state):
        contact = w < w_true
        gap = math.nan if contact else SLOPE * (w - w_true)
        return Trial(
            omega=w, contact=contact, min_gap=gap, impacts_per_period=2.0 if contact else 1.0, x_end=w, v_end=0.0
        )

    return trial


@pytest.mark.parametrize("tol", [3e-4, 1e-5, 1e-7])
def test_bisection_brackets_truth(tol):
    b = bisect_transition(threshold_trial(W_G), 23.045, 23.044, (23.045, 0.0), tol)
    assert isinstance(b, GrazingBracket)
    assert b.width <= tol
    assert b.omega_contact <= W_G <= b.omega_miss
    # bisection halves the bracket each trial: ceil(log2(width / tol)) trials, no more
    assert len(b.trials) == math.ceil(math.log2((23.045 - 23.044) / tol))


def test_bisection_starts_each_trial_from_latest_miss():
    seen = []

    def trial(w, state):
        seen.append(state[0])
        return threshold_trial(W_G)(w, state)

    b = bisect_transition(trial, 23.045, 23.044, (23.045, 0.0), 1e-5)
    misses = [23.045] + [t.omega for t in b.trials if not t.contact]
    # the state handed to each trial is the end state of the closest miss so far
    for k, s in enumerate(seen):
        assert s == min(m for m in misses if m in [23.045] + [t.omega for t in b.trials[:k]])


def test_bisection_errors():
    with pytest.raises(ValueError, match="tol"):
        bisect_transition(threshold_trial(W_G), 23.045, 23.044, None, 0.0)
    with pytest.raises(ValueError, match="differ"):
        bisect_transition(threshold_trial(W_G), 23.0, 23.0, None, 1e-3)
    with pytest.raises(ValueError, match="did not reach"):
        bisect_transition(threshold_trial(W_G), 23.045, 23.044, None, 1e-12, max_trials=5)


def test_gap_extrapolation_exact_on_a_line():
    w, gap, ipp = synthetic_branch()
    i = find_grazing_step(w, gap, ipp)
    fit = extrapolate_gap_zero(w[: i + 1], gap[: i + 1], 5)
    assert fit.omega_zero == pytest.approx(W_G, abs=1e-9)
    assert fit.slope == pytest.approx(SLOPE, rel=1e-9)
    assert fit.rms < 1e-15


def test_gap_extrapolation_errors():
    with pytest.raises(ValueError, match="> 0"):
        extrapolate_gap_zero([3.0, 2.0, 1.0], [1.0, 0.0, -1.0], 3)
    with pytest.raises(ValueError, match="at least"):
        extrapolate_gap_zero([2.0, 1.0], [1.0, 0.5], 5)
    with pytest.raises(ValueError, match="non-finite"):
        extrapolate_gap_zero([3.0, 2.0, 1.0], [1.0, np.nan, 0.5], 3)


def test_grids_hit_round_values():
    g = branch_grid(40.86, 23.3, 22.95, 0.05, 0.001)
    assert g[0] == 40.86 and g[-1] == 22.95
    assert np.all(np.diff(g) < 0)
    for w in (23.05, 23.03):
        assert np.any(g == w)
    r = regular_grid(22.95, 23.3, 0.005)
    assert r.size == 71 and r[-1] == 23.3 and np.any(r == 23.05)
    with pytest.raises(ValueError, match="decreasing"):
        branch_grid(20.0, 23.3, 22.95, 0.05, 0.001)


def test_grazing_statistics_on_synthetic_branch():
    w, gap, ipp = synthetic_branch()
    b = bisect_transition(threshold_trial(W_G), 23.045, 23.044, (23.045, 0.0), 1e-5)
    summary = {"omega": w, "min_gap": gap, "impacts_per_period": ipp, "min_impact_v": np.full(w.size, 0.05)}
    rest = {
        "omega": w[::5],
        "min_gap": gap[::5],
        "impacts_per_period": ipp[::5],
        "min_impact_v": np.full(w[::5].size, 0.05),
    }
    st = grazing_statistics(summary, b.to_dict(), rest, (23.05, 23.03), 5)
    assert st["between_paper_omegas"] and st["fit_inside_bracket"]
    assert st["branch_at_paper_omegas"]["23.05"]["impacts_per_period"] == 1.0
    assert st["branch_at_paper_omegas"]["23.03"]["impacts_per_period"] == pytest.approx(4 / 3)
    assert min(st["from_rest_on_pre_grazing_orbit"]["omega"]) > W_G
