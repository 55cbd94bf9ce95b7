"""The 2-D map's cells checked against two-parameter curves, and the curve tables
(impactosc.dynamics.two_parameter_map), on a synthetic map whose answer is known."""

import numpy as np
import pytest

from impactosc.dynamics.two_parameter_map import (
    codim_two_rows,
    curve_crossings,
    orbit_types,
    point_rows,
    separation,
    summary_rows,
)

OMEGA = np.arange(0.0, 15.0)  # one grid cell = 1 rad/s
VALUES = np.array([0.0, 1.0])


def _curve(kind, n, w_at, impacts, graze_gap=None):
    """A straight curve w = w_at + 0.2 value through the rows, starting at value 0."""
    points = []
    for v in (-0.5, 0.0, 1.5):
        p = {"omega": w_at + 0.2 * v, "value": v, "x0": 0.0, "v0": 0.0, "mu_re": [-1.0, 0.1], "mu_im": [0.0, 0.0],
             "condition": 0.0, "impacts": impacts, "sticks": 0, "stable": False}  # fmt: skip
        if graze_gap is not None:
            p["graze_gap"] = graze_gap
        points.append(p)
    return {"kind": kind, "n_periods": n, "parameter": "xI", "points": points, "codim_two": [],
            "start": {"value": 0.0, "omega": w_at, "table_omega": w_at}, "stops": {"start": "a", "end": "b"},
            "cpu_seconds": 1.0}  # fmt: skip


@pytest.fixture
def scene():
    """Grazing at w = 2.5 (+0.2 per row), doubling 1 -> 2 at 7.5, 2 -> 4 at 10.5: period 3 below the
    grazing, 1 (one impact) up to the first doubling, 2 (two) up to the second, 4 (four) above."""
    curves = {"graze": _curve("grazing", 1, 2.5, 2, graze_gap=-1e-16), "pd1": _curve("period_doubling", 1, 7.5, 1),
              "pd2": _curve("period_doubling", 2, 10.5, 2)}  # fmt: skip
    period, impacts = np.empty((2, OMEGA.size), int), np.empty((2, OMEGA.size), int)
    for i, v in enumerate(VALUES):
        w = OMEGA - 0.2 * v
        period[i] = np.select([w < 2.5, w < 7.5, w < 10.5], [3, 1, 2], 4)
        impacts[i] = np.select([w < 2.5, w < 7.5, w < 10.5], [4, 1, 2], 4)
    return curves, period, impacts


def test_crossings_interpolate_and_a_turning_curve_crosses_twice():
    pts = [{"omega": 1.0, "value": 0.0}, {"omega": 3.0, "value": 2.0}, {"omega": 5.0, "value": 0.0}]
    assert curve_crossings(pts, 1.0) == [2.0, 4.0]
    assert curve_crossings(pts, 3.0) == []


def test_orbit_types_do_not_count_the_grazing_touch(scene):
    curves, _, _ = scene
    assert orbit_types(curves["graze"]) == ((1, 1), None)  # 2 impacts counted at the touch
    assert orbit_types(curves["pd2"]) == ((2, 2), (4, 4))


def test_a_map_that_agrees_passes_every_check(scene):
    curves, period, impacts = scene
    rows = separation(OMEGA, VALUES, period, impacts, curves)
    assert {r["check"] for r in rows} == {"sides", "between"}
    assert len([r for r in rows if r["check"] == "sides"]) == 6  # 3 curves x 2 rows
    assert len([r for r in rows if r["check"] == "between"]) == 4  # period 1 and period 2, 2 rows
    assert all(r["ok"] for r in rows)


def test_a_wrong_cell_beyond_one_grid_cell_is_found_and_one_within_it_is_excused(scene):
    curves, period, impacts = scene
    period[0, 8], impacts[0, 8] = 1, 1  # 0.5 rad/s past the doubling at 7.5: within one cell
    assert all(r["ok"] for r in separation(OMEGA, VALUES, period, impacts, curves))
    period[0, 5] = 0  # inside the period-1 band, 2.5 cells from either curve
    (bad,) = [r for r in separation(OMEGA, VALUES, period, impacts, curves) if not r["ok"]]
    assert bad["check"] == "between" and bad["value"] == 0.0 and "not at w = 5.00" in bad["cells"]
    period[0, 5], period[0, 1], impacts[0, 1] = 1, 1, 1  # below the grazing, 1.5 cells from it: period 1 on both sides
    (bad,) = [r for r in separation(OMEGA, VALUES, period, impacts, curves) if not r["ok"]]
    assert bad["check"] == "sides" and bad["curve"] == "graze"


def test_map_arrays_of_the_wrong_shape_are_refused(scene):
    curves, period, impacts = scene
    with pytest.raises(ValueError, match="map arrays must be"):
        separation(OMEGA, VALUES, period[:, :-1], impacts[:, :-1], curves)


def test_tables_have_a_row_per_point_curve_and_codimension_two_point(scene):
    curves, _, _ = scene
    curves["pd1"]["codim_two"] = [{"what": "cusp", "omega": 7.5, "value": 1e-3, "located": True,
                                   "multipliers": [[1.0, 0.0], [0.07, 0.0]]}]  # fmt: skip
    assert len(point_rows(curves)) == 9
    summary = summary_rows(curves)
    assert [r["curve"] for r in summary] == ["graze", "pd1", "pd2"] and summary[1]["difference_rad_s"] == "+0.0e+00"
    (row,) = codim_two_rows(curves)
    assert row["what"] == "cusp" and row["value"] == "1.000000 mm" and row["multipliers"] == "1, 0.07"
