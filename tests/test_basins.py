"""Basins of attraction at w = 23.05 (impactosc.dynamics.basins): the classifier with early exit
against direct long simulations, rest (0, 0), chunked = unchunked, the fractions and their
standard error, and the refusal of bad input."""

import math

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.dynamics.basins import (
    FAILED,
    UNRESOLVED,
    Attractor,
    BasinGrid,
    BasinSettings,
    basin_fractions,
    chunk_rows,
    class_names,
    classify_rows,
    classify_state,
    load_basins,
    merge_basins,
    reference_attractors,
    save_basins,
)
from impactosc.dynamics.branch_segments import seed_from_rest

OMEGA = 23.05
SEEDS = {
    "period1": {"n_periods": 1, "guess": [-3.89e-3, -2.06e-2]},
    "period3": {"n_periods": 3, "guess": [-3.96e-3, -1.74e-2]},
}
SETTINGS = BasinSettings(OMEGA)  # x_tol 1 um, v_tol 20 um/s, confirm 6, cap 400, blocks of 10, rtol 1e-10
# cells of the coarse default grid (config basins): two in the thin period-1 set, one beside it
# in the period-3 basin, one far from both attractors (in contact with the obstacle at t = 0)
CELLS = [(-6.0e-3, -0.03), (-6.25e-3, 0.135), (-6.5e-3, 0.135), (3.0e-3, -0.21)]


@pytest.fixture(scope="module")
def attractors():
    return reference_attractors(OMEGA, SEEDS)


def _on(attractor: Attractor, x, v, s=SETTINGS) -> bool:
    return all(attractor.index_of(xi, vi, s.x_tol, s.v_tol) >= 0 for xi, vi in zip(x, v))


def test_reference_attractors_are_the_two_coexisting_orbits(attractors):
    p1, p3 = attractors
    assert (p1.n_periods, p1.impacts, p3.n_periods, p3.impacts) == (1, 1, 3, 4)
    assert p1.x[0] == pytest.approx(-3.88988e-3, abs=1e-8) and p1.v[0] == pytest.approx(-2.06308e-2, abs=1e-6)
    assert np.abs(p1.multipliers) == pytest.approx([0.40, 0.40], abs=0.01)
    assert np.all(np.abs(p3.multipliers) < 1)
    # the period-3 orbit is the one the simulation from rest settles on
    from_rest = seed_from_rest(OMEGA, 3)
    assert p3.index_of(from_rest.x0, from_rest.v0, 1e-9, 1e-7) >= 0


def test_classes_agree_with_direct_long_simulation(attractors):
    period = 2 * math.pi / OMEGA
    seen = set()
    for x0, v0 in CELLS:
        cell = classify_state(x0, v0, attractors, SETTINGS)
        assert cell.cls in (1, 2), (x0, v0, cell)
        assert SETTINGS.confirm <= cell.periods < SETTINGS.max_periods
        seen.add(cell.cls)
        run = simulate(OMEGA, 394 * period, 6 * period, x0=x0, v0=v0, record=("poincare",))  # 400 periods
        x, v = run.events["poincare"]["x"][-6:], run.events["poincare"]["v"][-6:]  # periods 395..400
        named, other = attractors[cell.cls - 1], attractors[2 - cell.cls]
        assert _on(named, x, v), (x0, v0, cell.cls)
        assert not any(other.index_of(xi, vi, 1e-5, 1e-3) >= 0 for xi, vi in zip(x, v))  # 10 x the box
    assert seen == {1, 2}  # both basins are represented


def test_tolerance_boxes_lie_inside_their_basins(attractors):
    # a state on a corner of any point's box stays on that attractor over 200 periods
    period = 2 * math.pi / OMEGA
    for a in attractors:
        for x, v in zip(a.x, a.v):
            for sx, sv in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
                x0, v0 = x + 0.999 * sx * SETTINGS.x_tol, v + 0.999 * sv * SETTINGS.v_tol
                run = simulate(OMEGA, 197 * period, 3 * period, x0=x0, v0=v0, record=("poincare",))
                assert _on(a, run.events["poincare"]["x"][-3:], run.events["poincare"]["v"][-3:]), (a.name, sx, sv)


def test_rest_lands_on_the_period3_orbit(attractors):
    cell = classify_state(0.0, 0.0, attractors, SETTINGS)
    assert class_names(attractors)[cell.cls] == "period3"
    assert cell.periods < 60  # early exit: about 33 periods, not the cap


def test_an_unknown_attractor_is_reported_not_forced(attractors):
    # with only the period-1 orbit known, rest reaches nothing known: unresolved, period-3 tail
    cell = classify_state(0.0, 0.0, attractors[:1], SETTINGS)
    assert (cell.cls, cell.periods, cell.tail_period) == (UNRESOLVED, SETTINGS.max_periods, 3)


def test_chunks_join_to_the_unchunked_classification(attractors, tmp_path):
    grid = BasinGrid(np.array([-6.5e-3, -6.25e-3, -6.0e-3]), np.array([-0.03, 0.0, 0.12, 0.135]))
    whole = classify_rows(grid, np.arange(4), attractors, SETTINGS)
    paths = []
    for part in range(3):
        m = classify_rows(grid, chunk_rows(4, 3, part), attractors, SETTINGS)
        paths.append(tmp_path / f"part{part}.h5")
        save_basins(paths[-1], m, n_rows_total=4)
    loaded = [load_basins(p) for p in paths]
    assert all(int(extra["n_rows_total"]) == 4 for _, extra in loaded)
    joined = merge_basins([m for m, _ in loaded])
    for k in ("rows", "v0", "classes", "periods", "x_end", "v_end", "tail_period"):
        assert np.array_equal(getattr(joined, k), getattr(whole, k)), k
    assert set(np.unique(joined.classes)) == {1, 2}
    assert joined.settings == SETTINGS.to_attrs()
    assert [a.name for a in joined.attractors] == ["period1", "period3"]
    assert np.array_equal(joined.attractors[1].x, attractors[1].x)
    with pytest.raises(ValueError, match="rows"):
        merge_basins([loaded[0][0], loaded[2][0]])  # a missing chunk


def test_fractions_and_standard_error_on_a_hand_made_grid():
    classes = np.array([[1, 1, 2, 2, 2], [2, 2, 2, 0, 0], [-1, 2, 2, 2, 0]])
    tails = np.zeros_like(classes)
    tails[1, 3] = tails[1, 4] = 2
    names = {1: "a", 2: "b", UNRESOLVED: "unresolved", FAILED: "failed"}
    rows = basin_fractions(classes, names, tails)
    assert [(r["class"], r["name"], r["cells"]) for r in rows] == [
        (1, "a", 2),
        (2, "b", 9),
        (0, "unresolved", 3),
        (-1, "failed", 1),
        (0, "unresolved, period-2 tail", 2),
    ]
    for r in rows:
        p = r["cells"] / 15
        assert r["fraction"] == pytest.approx(p) and r["se"] == pytest.approx(math.sqrt(p * (1 - p) / 15))
    assert sum(r["fraction"] for r in rows[:4]) == pytest.approx(1.0)
    assert basin_fractions(np.ones((2, 2), int), names)[0]["se"] == 0.0  # every cell one class


def test_bad_input_is_refused(attractors):
    with pytest.raises(ValueError, match="start < stop"):
        BasinGrid.linspace((4e-3, -8e-3), (-0.3, 0.3), 4, 4)
    with pytest.raises(ValueError, match="finite"):
        BasinGrid.linspace((-8e-3, math.nan), (-0.3, 0.3), 4, 4)
    with pytest.raises(ValueError, match="integer >= 1"):
        BasinGrid.linspace((-8e-3, 4e-3), (-0.3, 0.3), 0, 4)
    with pytest.raises(ValueError, match="non-empty"):
        BasinGrid(np.array([]), np.array([0.0]))
    with pytest.raises(ValueError, match="increasing"):
        BasinGrid(np.array([1e-3, 0.0]), np.array([0.0]))
    with pytest.raises(ValueError, match="empty class grid"):
        basin_fractions(np.zeros((0, 3), int), class_names(attractors))
    with pytest.raises(ValueError, match=r"codes \[7\]"):
        basin_fractions(np.array([[1, 7]]), class_names(attractors))
    with pytest.raises(ValueError, match="no rows"):
        chunk_rows(3, 4, 0)
    with pytest.raises(ValueError, match="part"):
        chunk_rows(4, 2, 2)
    with pytest.raises(ValueError, match="x_tol"):
        BasinSettings(OMEGA, x_tol=-1e-6)
    with pytest.raises(ValueError, match="confirm"):
        BasinSettings(OMEGA, confirm=10, max_periods=5)
    with pytest.raises(ValueError, match="x0"):
        classify_state(math.nan, 0.0, attractors, SETTINGS)
    with pytest.raises(ValueError, match="no reference attractors"):
        classify_state(0.0, 0.0, [], SETTINGS)
    with pytest.raises(ValueError, match="no reference attractors"):
        reference_attractors(OMEGA, {})
    grid = BasinGrid.linspace((-8e-3, 4e-3), (-0.3, 0.3), 2, 2)
    with pytest.raises(ValueError, match="no grid rows"):
        classify_rows(grid, [], attractors, SETTINGS)
    with pytest.raises(ValueError, match="overlap"):  # boxes so wide that period 1 and 3 touch
        classify_rows(grid, [0], attractors, BasinSettings(OMEGA, x_tol=1e-4, v_tol=1e-2))
    with pytest.raises(ValueError, match="no basin chunks"):
        merge_basins([])


def test_a_guess_that_falls_onto_a_lower_period_is_refused(attractors):
    p1 = attractors[0]
    with pytest.raises(ValueError, match="converged to a period-1 orbit"):
        reference_attractors(OMEGA, {"fake3": {"n_periods": 3, "guess": [p1.x[0], p1.v[0]]}})
