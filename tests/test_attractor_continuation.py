"""Attractors matched along w, the sweeps' attractors named among them, and the oscillator's
attractors at w = 23.05 found without shooting (impactosc.dynamics.attractor_continuation,
attractor_survey, stroboscopic; the command impactosc attractors)."""

import math

import h5py
import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.dynamics.attractor_continuation import set_distance, survey_along, sweep_attractor, track
from impactosc.dynamics.attractor_survey import Survey, load_survey, random_starts, survey, survey_rows
from impactosc.dynamics.recurrence import FoundAttractor
from impactosc.dynamics.stroboscopic import oscillator_settings

# the shot orbits at w = 23.05 (config basins.attractors, docs/beyond.md): period 1 with one impact,
# |mu| = 0.40; period 3 with 4 impacts, |mu| = 0.35 per 3 periods
PERIOD1_GUESS = (-3.89e-3, -2.06e-2)


def _orbit(*points):
    return FoundAttractor(len(points), np.array(points, dtype=float), 1.0, -1.0)


def _survey(omega, attractors, labels):
    return Survey(omega, np.zeros((len(labels), 2)), np.array(labels), np.ones(len(labels), int), attractors, None, 0.0)


def test_tracks_follow_moving_orbits_and_name_births_deaths_and_mergers():
    a = lambda w: _orbit((-6e-3 + 1e-3 * w, 0.01))  # moves 10 um per step of 0.01: one attractor
    b = lambda w: _orbit((-2e-3, -0.05), (-3e-3, 0.02))
    surveys = [
        _survey(1.00, [a(1.00)], [1, 1]),
        _survey(1.01, [a(1.01), b(1.01)], [1, 2]),  # b born
        _survey(1.02, [b(1.02), a(1.02)], [1, 2]),  # order swapped: the tracks still follow
        _survey(1.03, [b(1.03)], [1, 1]),  # a dies (2 mm from b: beyond 0.5, the limit at this step)
    ]
    t = track(surveys)
    assert t.ids == [[0], [0, 1], [1, 0], [1]]
    assert [(e["omega"], e["event"], e["track"]) for e in t.events] == [(1.01, "born", 1), (1.03, "died", 0)]
    # a set close to an attractor that continues is absorbed by it: a merger
    near = _orbit((-2e-3 + 1e-4, -0.05))
    merged = track([_survey(1.0, [b(1), near], [1, 2]), _survey(1.01, [b(1.01)], [1, 1])])
    assert merged.events == [{"omega": 1.01, "event": "merged", "track": 1, "into": 0}]
    # an orbit drifting 1 mm per grid step of 0.25 rad/s (the period-1 branch near 26 rad/s) is followed
    drift = track([_survey(26.0, [_orbit((-10e-3, 0.0))], [1]), _survey(26.25, [_orbit((-11e-3, 0.0))], [1])])
    assert drift.ids == [[0], [0]] and drift.events == []


def test_set_distance_and_a_sweeps_points_on_an_attractor():
    p3 = _orbit((-3.96e-3, -1.74e-2), (-5.03e-3, -2.53e-2), (-4.87e-3, -6.5e-3))
    p1 = _orbit(PERIOD1_GUESS)
    # Hausdorff in units of (1 mm, 0.1 m/s): the period-3 point farthest from period 1 is 1.14 mm away in x
    assert set_distance(p1.points, p3.points) == pytest.approx(math.hypot(1.14, 0.047), rel=1e-2)
    sweep = np.tile(p3.points, (5, 1)) + 1e-9  # a sweep's recorded points on period 3, to 1 nm
    assert sweep_attractor(sweep, [p1, p3]) == 1
    assert sweep_attractor(sweep + 1e-5, [p1, p3]) == -1  # 10 um off: on no orbit


def test_oscillator_attractors_at_23_05_without_shooting(tmp_path):
    starts = np.array([[0.0, 0.0], PERIOD1_GUESS])  # rest lands on period 3 (the paper's run from rest)
    s = survey(23.05, starts, boxes=1)
    names = [a.name for a in s.attractors]
    assert names == ["period 3, 4 impacts", "period 1, 1 impact"]
    assert s.labels.tolist() == [1, 2]
    # largest exponent per period = log |mu| of the shot multipliers (0.35 per 3 periods, 0.40 per period);
    # 200 periods of a tangent vector from the settled point: within 0.02
    assert s.attractors[0].exponent == pytest.approx(math.log(0.35) / 3, abs=0.02)
    assert s.attractors[1].exponent == pytest.approx(math.log(0.40), abs=0.02)
    np.testing.assert_allclose(s.attractors[1].points[0], [-3.889885e-3, -2.063079e-2], atol=1e-8)
    rows = survey_rows(s)
    assert [r["cells"] for r in rows[:2]] == [1, 1] and rows[0]["fraction"] == 0.5


def test_attractors_command_writes_the_survey(tmp_path, capsys):
    out = tmp_path / "a.h5"
    assert main(["attractors", "--omega", "23.05", "--samples", "20", "--quiet", "--output", str(out)]) == 0
    text = capsys.readouterr().out
    assert "period 3, 4 impacts" in text and "basin entropy" in text
    s = load_survey(out)
    assert s.labels.size == 20 and np.all(s.labels > 0)
    np.testing.assert_array_equal(s.starts, random_starts(20))
    with h5py.File(out) as f:
        assert f.attrs["recurrence_max_iterations"] == 2000 and f["starts"].attrs["units"] == "m, m/s"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--omega", "-1"], "--omega must be > 0"),
        (["--omega", "23", "--samples", "0"], "--samples must be >= 1"),
        (["--omega", "23", "--x-range", "1", "0"], "--x-range must be LO < HI"),
        (["--omega", "23", "--max-iterations", "5"], "max_iterations"),
    ],
)
def test_attractors_command_names_bad_input(tmp_path, capsys, args, message):
    assert main(["attractors", *args, "--output", str(tmp_path / "a.h5")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "a.h5").exists()


@pytest.mark.slow
def test_fractions_at_23_05_match_the_basin_grid():
    """1000 random starts, no shooting: both orbits, nothing unresolved; the period-1 share agrees
    with the coarse basin grid's (22 of 49 x 41 cells, 1.10 +- 0.23 %, docs/beyond.md) within the
    combined standard error, 2 se wide (about 12 s)."""
    s = survey(23.05, random_starts(1000))
    rows = {r["name"].split(": ", 1)[-1]: r for r in survey_rows(s)}
    assert set(rows) == {"period 3, 4 impacts", "period 1, 1 impact", "unresolved", "stopped by the core"}
    assert rows["unresolved"]["cells"] == 0 and rows["stopped by the core"]["cells"] == 0
    grid, grid_se = 22 / 2009, math.sqrt((22 / 2009) * (1 - 22 / 2009) / 2009)
    p1 = rows["period 1, 1 impact"]
    assert abs(p1["fraction"] - grid) < 2 * math.hypot(p1["se"], grid_se)


def test_a_w_where_nothing_settles_leaves_its_starts_unresolved_and_seeds_nothing():
    # 40 periods cannot settle a start near a period doubling (w = 37.27, 0.01 below it): every
    # start is unresolved, and the continuation goes on past a w with no attractor
    settings = oscillator_settings(max_iterations=40, record=99)
    surveys = survey_along([37.26, 37.27], np.array([[-7.9e-3, -0.13], [-8.0e-3, -0.12]]), settings=settings, boxes=1)
    assert all(s.attractors == [] and np.all(s.labels == 0) for s in surveys)
