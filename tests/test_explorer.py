"""The explorer's parts without a browser: the page's input parsing, the view as a config (and
the workflow's validation of it), the scheduler's lanes and its dropping of stale requests, the
worker pool that heals, records read only from the directories allowed, the server's token, and
the command's errors."""

from __future__ import annotations

import asyncio
import dataclasses
import itertools
import math
import os
import pickle
import re
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
import yaml

from impactosc.cli.main import main
from impactosc.core.simulation import StallError
from impactosc.dynamics.shooting import ShootingError
from impactosc.dynamics.variational import UnsupportedTrajectory
from impactosc.explorer import scheduler as sched
from impactosc.explorer import work
from impactosc.explorer.view import (
    InputError,
    RecordAccess,
    View,
    config_snippet,
    parse_columns,
    parse_omega,
    parse_range,
    record_error,
    shown_parameters,
    snakemake_command,
    with_law,
    with_parameter,
    write_config,
)
from impactosc.model.model_file import write_model_file
from impactosc.model.parameters import ModelParams

ROOT = Path(__file__).resolve().parent.parent
STARTUP = 900.0  # s: the workers load the compiled core (a machine without numba's cache compiles it first)


def start_explorer(*args: str, cwd) -> tuple[subprocess.Popen, str]:
    """`impactosc explore --port 0 --no-browser *args` started in `cwd`: the process and the
    address it prints (with its token); fails the test if it does not start."""
    cmd = [sys.executable, "-m", "impactosc.cli.main", "explore", "--port", "0", "--no-browser", *args]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd=cwd)
    deadline, lines = time.monotonic() + STARTUP, []
    while time.monotonic() < deadline:
        lines.append(proc.stdout.readline())
        if "serving http://localhost:" in lines[-1] or proc.poll() is not None:
            break
    if proc.poll() is not None or "serving" not in lines[-1]:
        stop_explorer(proc)
        pytest.fail("the explorer did not start:\n" + "".join(lines))
    return proc, re.search(r"http://\S+", lines[-1]).group(0)


def stop_explorer(proc: subprocess.Popen) -> str:
    """Stop the explorer; returns what it printed since it started serving."""
    proc.terminate()  # the server shuts its worker pool down on SIGTERM
    try:
        out, _ = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, _ = proc.communicate(timeout=10)
    return out


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

    def fake_batch(omegas, settings, state, first_transient):
        calls.append(float(omegas[0]))
        if omegas[0] < 100:  # the first request's windows lie below 100 rad/s
            release.wait(5)
        cols = [{"omega": float(w), "x": [0.0], "isi": [], "state_end": (0.0, 0.0, math.nan)} for w in omegas]
        return {"columns": cols, "state_end": cols[-1]["state_end"]}

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


# ---------------------------------------------------------------------- errors cross the process boundary


@pytest.mark.parametrize(
    "error",
    [
        StallError("core stalled at t = 1 s", {"t": 1.0, "piece": "contact", "attempts": 3}),
        ShootingError("Newton did not converge"),
        UnsupportedTrajectory("sticking"),
        InputError("w must be > 0"),
        work.WorkerError("KeyError: 'x'"),
    ],
)
def test_errors_survive_pickling(error):
    back = pickle.loads(pickle.dumps(error))
    assert type(back) is type(error) and str(back) == str(error)
    assert getattr(back, "state", None) == getattr(error, "state", None)


def test_a_real_stall_pickles_with_its_state():
    """w = 1e9 stalls the core (step-size underflow): the error a worker raises comes back whole."""
    with pytest.raises(StallError) as caught:
        work.attractor(1e9, ModelParams(), (0.0, 0.0, math.nan), 600, 60)
    back = pickle.loads(pickle.dumps(caught.value))
    assert str(back) == str(caught.value) and back.state == caught.value.state and back.state["t"] > 0


class _Unpicklable(Exception):
    def __init__(self, a, b):
        super().__init__(f"{a} and {b}")


def test_work_functions_hand_back_errors_that_would_not_unpickle():
    @work._plain_errors
    def bad():
        raise _Unpicklable(1, 2)

    @work._plain_errors
    def fine():
        raise ShootingError("no convergence")

    with pytest.raises(work.WorkerError, match="_Unpicklable: 1 and 2"):
        bad()
    with pytest.raises(ShootingError):
        fine()


# ---------------------------------------------------------------------- the pool heals


@pytest.fixture(scope="module")
def pool():
    p = sched.WorkerPool(2)
    sched.Scheduler(2, pool=p).warm()
    yield p
    p.shutdown(wait=True, cancel_futures=True)


def _wait_for(events: list, timeout: float = 60.0):
    deadline = time.monotonic() + timeout
    while not events and time.monotonic() < deadline:
        time.sleep(0.02)
    assert events, "no answer in time"
    return events[0]


def _attractor(s: sched.Scheduler, omega: float) -> tuple[str, object]:
    """('ok', result) or ('error', message) of one attractor request."""
    out = []
    s.attractor(View(), omega, lambda _g, r: out.append(("ok", r)), on_error=lambda _g, m: out.append(("error", m)))
    return _wait_for(out)


def test_a_stall_in_a_worker_is_a_message_not_a_broken_pool(pool):
    s = sched.Scheduler(2, pool=pool)
    restarts = pool.restarts
    kind, message = _attractor(s, 1e9)
    assert kind == "error" and "StallError" in message and "step size underflow" in message
    assert pool.restarts == restarts
    kind, result = _attractor(s, 35.0)
    assert kind == "ok" and result["omega"] == 35.0


def test_a_killed_worker_is_replaced_and_the_next_request_runs(pool):
    """One worker killed (SIGKILL) while a diagram runs: the diagram's page is told why, the
    pool is recreated, and the next request of the same scheduler computes."""
    s = sched.Scheduler(2, pool=pool)
    restarts, first, errors = pool.restarts, threading.Event(), []
    s.diagram(
        View(w_lo=20, w_hi=45, n_columns=200), lambda _g, _c: first.set(), on_error=lambda _g, m: errors.append(m)
    )
    assert first.wait(60)
    victim = pool.pids()[0]
    os.kill(victim, signal.SIGKILL)
    message = _wait_for(errors)
    assert f"worker {victim} killed by SIGKILL" in message and "restarted" in message
    assert pool.restarts == restarts + 1 and victim not in pool.pids()
    kind, result = _attractor(s, 35.0)
    assert kind == "ok" and result["period"] >= 0


def test_a_worker_killed_between_requests_is_replaced_at_once(pool):
    """A worker killed while idle (no request holds it) is replaced without waiting for a request:
    its death is known and logged when it happens, and the next request runs on the new workers."""
    s = sched.Scheduler(2, pool=pool)
    assert _attractor(s, 35.0)[0] == "ok"  # the pool is up and idle
    restarts, victim = pool.restarts, pool.pids()[0]
    os.kill(victim, signal.SIGKILL)
    deadline = time.monotonic() + 30
    while pool.restarts == restarts and time.monotonic() < deadline:
        time.sleep(0.02)
    assert pool.restarts == restarts + 1 and pool.last_death == f"worker {victim} killed by SIGKILL"
    assert victim not in pool.pids()
    kind, result = _attractor(s, 35.0)
    assert kind == "ok" and result["omega"] == 35.0


def test_a_broken_pool_names_the_worker_that_died_not_those_it_stopped():
    """A broken executor stops its other workers with SIGTERM: seen ended together, the cause is
    the one that ended otherwise; a worker that was itself sent SIGTERM is named so."""

    class Ended:  # a worker process seen ended
        def __init__(self, pid: int, code: int):
            self.pid, self.exitcode = pid, code

        def join(self, timeout=None):
            pass

    dead = [Ended(11, -signal.SIGTERM), Ended(12, -signal.SIGKILL)]
    assert sched._death(None, None, dead) == "worker 12 killed by SIGKILL"
    assert sched._death(None, None, dead[:1]) == "worker 11 killed by SIGTERM"


# ---------------------------------------------------------------------- records


@pytest.fixture
def data(tmp_path):
    """A data directory with a good record, a bad one, and links to a file outside it."""
    inside, outside = tmp_path / "data", tmp_path / "elsewhere"
    inside.mkdir()
    outside.mkdir()
    secret = outside / "secret.csv"
    secret.write_text("TOP SECRET first line\n1,2\n")
    (inside / "link.csv").symlink_to(secret)
    (inside / "bad.csv").write_text("root:x:0:0:root:/root:/bin/bash\n1,2,3\n")
    (inside / "notes.txt").write_text("t,x\n")
    return inside, outside


def test_records_outside_the_data_directories_are_refused(data):
    inside, outside = data
    access = RecordAccess(dirs=(str(inside),), max_bytes=64)
    for typed in ("link.csv", str(inside / "link.csv"), str(outside / "secret.csv"), "../elsewhere/secret.csv"):
        with pytest.raises(InputError, match="outside the directories") as refused:
            access.resolve(typed)
        assert "TOP SECRET" not in str(refused.value)
    assert access.resolve("bad.csv") == os.path.realpath(inside / "bad.csv")
    with pytest.raises(InputError, match="not a record file"):
        access.resolve("notes.txt")
    with pytest.raises(InputError, match="not a regular file"):
        access.resolve(".")
    with pytest.raises(InputError, match="no such file"):
        access.resolve("none.csv")
    (inside / "big.csv").write_text("t,x\n" + "0.0,0.0\n" * 20)
    with pytest.raises(InputError, match=r"big.csv: 0\.0 MiB, more than"):
        access.resolve("big.csv")
    # a file named at start is allowed wherever it lies
    assert RecordAccess(dirs=(str(inside),), files=(str(outside / "secret.csv"),)).resolve(str(outside / "secret.csv"))


def test_a_record_that_does_not_parse_says_where_not_what(data):
    """The reader's message quotes the bad line; the page's names the file and the line only."""
    inside, _ = data
    s = sched.Scheduler(1, pool=ThreadPoolExecutor(1))
    real = RecordAccess(dirs=(str(inside),)).resolve("bad.csv")
    out = []
    s.record(real, lambda _g, p: out.append(p), lambda _g, m: out.append(record_error("bad.csv", real, m)))
    message = _wait_for(out)
    assert message.startswith("record bad.csv: ") and "root:x" not in message and str(inside) not in message
    assert "line" in message


def test_a_record_load_is_killed_when_cancelled_or_late():
    late, cancelled = [], []
    sched.OneShot(time.sleep, (30,), lambda ok, why: late.append((ok, why)), timeout=0.5)
    assert _wait_for(late, 30) == (False, "took more than 0.5 s")
    shot = sched.OneShot(time.sleep, (30,), lambda ok, why: cancelled.append(ok))
    shot.cancel()
    deadline = time.monotonic() + 10
    while not shot.done() and time.monotonic() < deadline:
        time.sleep(0.02)
    assert shot.done() and cancelled == []


def test_a_record_load_ends_with_its_page(tmp_path):
    """A load that would wait forever (opening a FIFO nobody writes) is killed when the page
    closes, and its page hears nothing of it."""
    fifo = tmp_path / "stuck.csv"
    os.mkfifo(fifo)
    s = sched.Scheduler(1, pool=ThreadPoolExecutor(1))
    heard = []
    s.record(str(fifo), lambda _g, p: heard.append(p), lambda _g, m: heard.append(m), load=open)
    (shot,) = s._futures[sched.RECORD]
    time.sleep(0.5)
    assert not shot.done()
    s.close()
    deadline = time.monotonic() + 10
    while not shot.done() and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(0.2)
    assert shot.done() and heard == []


# ---------------------------------------------------------------------- the config written


def _workflow_config(snippet: Path) -> dict:
    """The config the workflow validates for `--configfile config/config.yaml snippet`."""
    from impactosc_study.config import validate_config

    def merge(base, extra):
        for key, value in extra.items():
            base[key] = merge(base.get(key, {}), value) if isinstance(value, dict) else value
        return base

    config = merge(yaml.safe_load((ROOT / "config" / "config.yaml").read_text()), yaml.safe_load(snippet.read_text()))
    return validate_config(config, ROOT / "workflow" / "schemas" / "config.schema.yaml")


def test_a_written_config_with_extreme_values_passes_the_workflow(tmp_path):
    params = with_parameter(with_parameter(ModelParams(), "eps", "1e-5"), "kI", "1e16")
    path = write_config(tmp_path / "view.yaml", config_snippet(View(params=params, n_columns=41)))
    assert "1.0e-05" in path.read_text() and "1.0e+16" in path.read_text()
    config = _workflow_config(path)
    assert config["model"]["eps"] == 1e-5 and config["model"]["kI"] == 1e16
    assert [p.name for p in tmp_path.iterdir()] == ["view.yaml"]  # written in place of a temporary file


def test_a_model_path_with_yaml_syntax_round_trips(tmp_path):
    rig = ModelParams(k=1500.0)
    model = write_model_file(tmp_path / "rig, v2 #1: {a}.yaml", rig)
    view = View(params=rig, file_params=rig, model_file=str(model))
    config = _workflow_config(write_config(tmp_path / "view.yaml", config_snippet(view)))
    assert config["model_source"]["file"] == str(model) and config["model"]["k"] == 1500.0


def test_the_config_is_never_written_through_a_link(tmp_path):
    target = tmp_path / "target.txt"
    target.write_text("keep me\n")
    (tmp_path / "view.yaml").symlink_to(target)
    with pytest.raises(InputError, match="symbolic link"):
        write_config(tmp_path / "view.yaml", config_snippet(View()))
    assert target.read_text() == "keep me\n"


# ---------------------------------------------------------------------- the command line


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--port", "70000"], "the port must be a whole number in 0..65535, got '70000'"),
        (["--port", "-1"], "0..65535"),
        (["--workers", "0"], "workers must be a whole number in 1.."),
        (["--workers", str((os.cpu_count() or 1) + 1)], "workers must be a whole number in 1.."),
    ],
)
def test_ports_and_workers_out_of_range_are_refused(args, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(["explore", "--no-browser", *args])
    assert stop.value.code == 2 and message in capsys.readouterr().err


# ---------------------------------------------------------------------- the token


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    proc, url = start_explorer("--columns", "4", "--workers", "1", cwd=tmp_path_factory.mktemp("served"))
    yield url
    stop_explorer(proc)


def _get(url: str) -> tuple[int, dict, str]:
    try:
        with urllib.request.urlopen(url, timeout=60) as r:
            return r.status, dict(r.headers), r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, dict(e.headers), ""


def _websocket(port: str, protocols: list[str], origin: bool = True) -> str:
    """'open' or 'refused <code>': a websocket to the page's /ws with these subprotocols."""
    from tornado.httpclient import HTTPClientError, HTTPRequest
    from tornado.websocket import websocket_connect

    async def connect():
        headers = {"Origin": f"http://localhost:{port}"} if origin else {}
        try:
            ws = await websocket_connect(
                HTTPRequest(f"ws://localhost:{port}/ws", headers=headers), subprotocols=protocols
            )
        except HTTPClientError as exc:
            return f"refused {exc.code}"
        answer = await ws.read_message()
        ws.close()
        return "open" if answer and "ACK" in answer else f"no ACK: {answer!r}"

    return asyncio.run(connect())


def test_the_page_needs_the_token(served):
    base, token = served.split("?token=")
    assert re.fullmatch(r"http://localhost:\d+/", base) and not base.endswith(":0/") and len(token) >= 32
    assert _get(base)[0] == 403
    assert _get(base + "?token=" + token[:-1] + "x")[0] == 403
    status, _, page = _get(served)
    assert status == 200 and "Bokeh" in page
    autoload = base + "autoload.js?bokeh-autoload-element=x"
    for url, expected in ((autoload, 403), (autoload + "&token=" + token, 200)):
        status, headers, _ = _get(url)
        assert status == expected and "Access-Control-Allow-Origin" not in headers


def test_the_websocket_needs_the_signed_session_of_a_page_with_the_token(served):
    from bokeh.util.token import generate_jwt_token, generate_session_id

    base, token = served.split("?token=")
    port = base.rstrip("/").rsplit(":", 1)[1]
    session = re.search(r'"token":"([^"]+)"', _get(served)[2]).group(1)
    forged = generate_jwt_token(generate_session_id(), extra_payload={"arguments": {"token": [token.encode()]}})
    assert _websocket(port, ["bokeh"]) == "refused 403"
    assert _websocket(port, ["bokeh", forged]) == "refused 403"  # not signed by the server
    assert _websocket(port, ["bokeh", session], origin=False) == "refused 403"
    assert _websocket(port, ["bokeh", session]) == "open"


def test_the_law_menu_changes_the_law_and_its_parameters(tmp_path):
    flores = with_parameter(with_law(ModelParams(), "flores"), "e", "0.6")
    assert (flores.law, flores.e, flores.n1) == ("flores", 0.6, 1.5)
    assert shown_parameters("flores")[-1] == "e" and "b" not in shown_parameters("flores")
    assert {"b", "n2", "n3"} <= set(shown_parameters("bc")) and not {"e", "cI"} & set(shown_parameters("bc"))
    kv = with_law(flores, "kelvin-voigt")
    assert kv.n1 == 1.0 and "cI" in shown_parameters("kelvin-voigt")
    assert with_law(kv, "bc").n1 == ModelParams().n1  # leaving the linear law restores the exponent
    with pytest.raises(InputError, match="the bc law has no parameter e"):
        with_parameter(ModelParams(), "e", "0.5")
    with pytest.raises(InputError, match="the flores law has no parameter b"):
        with_parameter(flores, "b", "0.5")
    with pytest.raises(InputError, match="e must be in \\(0, 1\\]"):
        with_parameter(flores, "e", "1.5")
    with pytest.raises(InputError, match="unknown contact law 'hooke'"):
        with_law(flores, "hooke")
    # the view's config names the law as the workflow reads it
    config = _workflow_config(write_config(tmp_path / "view.yaml", config_snippet(View(params=flores, n_columns=41))))
    assert (config["model"]["law"], config["model"]["e"]) == ("flores", 0.6)


def test_the_model_controls_show_the_laws_fields_and_report_only_a_users_edits():
    from impactosc.explorer.model_controls import ModelControls

    calls = []
    controls = ModelControls(ModelParams(), calls.append, lambda name, text: calls.append((name, text)))
    visible = {name for name, text in controls.fields.items() if text.visible}
    assert {"b", "n2", "n3"} <= visible and not {"e", "cI"} & visible
    controls.show(with_law(ModelParams(), "kelvin-voigt"))
    visible = {name for name, text in controls.fields.items() if text.visible}
    assert "cI" in visible and not {"b", "e"} & visible
    assert controls.fields["n1"].value == "1.0" and controls.fields["kI"].title == "kI (N/m)"
    assert calls == []  # the controls' own writes are no edits
    controls.fields["cI"].value = "80"
    controls.law.value = "hertz"
    assert calls == [("cI", "80"), "hertz"]


def test_a_restitution_law_is_explored_through_its_contacts():
    """Flores's period-1 orbit at w = 13.5 (e = 0.6, kI = 1e7, T = 0) has its Poincare point
    inside a contact: the attractor, the diagram's next batch and the shot orbit all start
    there with the contact's onset velocity."""
    flores = dataclasses.replace(ModelParams(), law="flores", e=0.6, kI=1e7, T=0.0)
    out = work.attractor(13.5, flores, (0.0, 0.0, math.nan), 300, 20)
    x, _, contact_v0 = out["state_end"]
    assert x > flores.xI and contact_v0 > 0  # the section lies inside a contact
    again = work.attractor(13.5, flores, out["state_end"], 5, 20)
    assert again["period"] == out["period"] == 1
    orbit = work.periodic_orbit(13.5, flores, out["state_end"], 1)
    assert "error" not in orbit and orbit["stable"]
    settings = View(w_lo=13.4, w_hi=13.6, n_columns=3, params=flores).settings()
    batch = work.diagram_batch(np.array([13.5, 13.55]), settings, out["state_end"], 5)
    assert all(len(c["x"]) == settings.n_record for c in batch["columns"])
