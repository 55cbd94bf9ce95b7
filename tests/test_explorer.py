"""The explorer's parts without a browser: the page's input parsing, the view as a config, the
scheduler's lanes and its dropping of stale requests, and the command's errors."""

from __future__ import annotations

import itertools
import subprocess
import sys
import threading
from concurrent.futures import ThreadPoolExecutor

import pytest
import yaml

from impactosc.cli.main import main
from impactosc.explorer import scheduler as sched
from impactosc.explorer import work
from impactosc.explorer.view import (
    InputError,
    View,
    config_snippet,
    parse_columns,
    parse_omega,
    parse_range,
    snakemake_command,
    with_parameter,
)
from impactosc.model.parameters import ModelParams


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: parse_omega("abc"), "is not a number"),
        (lambda: parse_omega("0"), "must be > 0"),
        (lambda: parse_omega("-3"), "must be > 0"),
        (lambda: parse_omega("nan"), "not finite"),
        (lambda: parse_range("40", "30"), "low to high"),
        (lambda: parse_range("30", "x"), "is not a number"),
        (lambda: parse_columns("2.5"), "whole number"),
        (lambda: parse_columns("1"), "whole number"),
        (lambda: with_parameter(ModelParams(), "m", "-1"), "must be > 0"),
        (lambda: with_parameter(ModelParams(), "zz", "1"), "unknown model parameter"),
    ],
)
def test_bad_input_is_refused_with_a_message(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_good_input():
    assert parse_omega(" 40.86 ") == 40.86
    assert parse_range("20", "45") == (20.0, 45.0)
    assert parse_columns("400") == 400
    assert with_parameter(ModelParams(), "xI", "-1.5e-3").xI == -1.5e-3


def test_config_snippet_is_the_view():
    view = View(
        w_lo=36.5, w_hi=38.5, n_columns=41, quantity="isi", direction="decreasing",
        params=with_parameter(ModelParams(), "xI", "-1.8e-3"),
    )  # fmt: skip
    config = yaml.safe_load(config_snippet(view))
    assert config["model"] == {"xI": -1.8e-3}
    sweep = config["bifurcation"]["sweeps"]["decreasing"]
    assert (sweep["start"], sweep["stop"]) == (38.5, 36.5)
    assert sweep["step"] == pytest.approx(0.05)
    assert config["bifurcation"]["fig03b"] == {"sweep": "decreasing"}
    assert config["bifurcation"]["per_w"] == {"n_transient": 100, "n_record": 50, "n_initial": 600}
    assert snakemake_command(view, "v.yaml").endswith("fig03b --configfile config/config.yaml v.yaml")


def test_config_snippet_names_the_model_file_unless_changed():
    rig = ModelParams(k=1500.0)
    view = View(params=rig, file_params=rig, model_file="rig.yaml")
    assert yaml.safe_load(config_snippet(view))["model"] == {"file": "rig.yaml"}
    changed = view.replace(params=with_parameter(rig, "m0e", "0.02"))
    model = yaml.safe_load(config_snippet(changed))["model"]
    assert "file" not in model and model["k"] == 1500.0 and model["m0e"] == 0.02 and len(model) == 12


def test_lanes_cover_the_grid_in_small_first_batches():
    assert sched.lane_plan(400, 2) == [(0, 200), (200, 400)]
    assert sched.lane_plan(3, 8) == [(0, 1), (1, 2), (2, 3)]
    batches = sched._batches(0, 20)
    assert batches[0] == (0, sched.FIRST_BATCH) and batches[-1][1] == 20
    assert all(b[1] == c[0] for b, c in itertools.pairwise(batches))


def test_a_newer_diagram_drops_the_older_one(monkeypatch):
    """The first request's batch is held until the second request is made: its columns are
    never delivered, its lane starts no successor, and the second request completes."""
    release = threading.Event()
    calls = []

    def fake_batch(omegas, settings, x0, v0, first_transient):
        calls.append(float(omegas[0]))
        if omegas[0] < 100:  # the first request's windows lie below 100 rad/s
            release.wait(5)
        cols = [{"omega": float(w), "x": [0.0], "isi": [], "x_end": 0.0, "v_end": 0.0} for w in omegas]
        return {"columns": cols, "x_end": 0.0, "v_end": 0.0}

    monkeypatch.setattr(work, "diagram_batch", fake_batch)
    s = sched.Scheduler(2, pool=ThreadPoolExecutor(2))
    delivered, done = [], threading.Event()
    old = s.diagram(View(w_lo=20, w_hi=45, n_columns=40), lambda g, c: delivered.append((g, c)))
    new = s.diagram(
        View(w_lo=120, w_hi=145, n_columns=40),
        lambda g, c: delivered.append((g, c)),
        on_done=lambda g, sec: done.set(),
    )
    release.set()
    assert done.wait(5)
    assert not s.is_current(sched.DIAGRAM, old) and s.is_current(sched.DIAGRAM, new)
    assert {g for g, _ in delivered} == {new}
    assert sum(len(c) for _, c in delivered) == 40
    assert sum(w < 100 for w in calls) == 2  # one first batch per lane of the old request, no successor
    s.close()


def test_explore_command_errors(tmp_path, capsys):
    assert main(["explore", "--no-browser", "--model", str(tmp_path / "missing.yaml")]) == 2
    assert "missing.yaml" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text("format: nothing we know\n")
    assert main(["explore", "--no-browser", "--model", str(bad)]) == 2
    assert "explore: error" in capsys.readouterr().err
    assert main(["explore", "--no-browser", "--w-range", "40", "30"]) == 2
    assert "low to high" in capsys.readouterr().err
    assert main(["explore", "--no-browser", "--record", str(tmp_path / "none.csv")]) == 2
    assert "none.csv" in capsys.readouterr().err


def test_the_library_and_its_commands_import_without_bokeh():
    code = (
        "import sys; sys.modules['bokeh'] = None\n"  # import bokeh now raises ImportError
        "import impactosc, impactosc.cli.main, impactosc.dynamics, impactosc.explorer.view\n"
        "from impactosc.cli.main import main\n"
        "print(main(['explore', '--no-browser']))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "2" and "needs Bokeh" in out.stderr


@pytest.mark.parametrize("n", [2, 3, 5, 9, 39, 40, 400])
def test_config_snippet_chunks_fit_its_grid(n):
    from impactosc.dynamics.sweep import regular_grid
    from impactosc.dynamics.sweep_chunks import plan_chunks

    b = yaml.safe_load(config_snippet(View(w_lo=30.0, w_hi=31.0, n_columns=n)))["bifurcation"]
    sweep = b["sweeps"]["increasing"]
    grid = regular_grid(sweep["start"], sweep["stop"], sweep["step"])
    assert grid.size == n
    assert len(plan_chunks(grid.size, b["chunks"], b["stride"])) == b["chunks"]


def test_located_points_of_a_window():
    """Model BC's first period doubling, located in a window around it (as the page's button does)."""
    points = work.located_points(ModelParams(), 36.9, 37.5)
    assert [p["kind"] for p in points] == ["period doubling"]
    assert points[0]["omega"] == pytest.approx(37.2843239, abs=1e-6)
