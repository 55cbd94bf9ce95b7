"""The explorer in a real browser: headless Chromium (Debian's chromium and chromedriver, never a
downloaded one) drives `impactosc explore` served on a free port.

It loads the page (its address with the token), zooms the diagram, types a w, moves the xI
slider, locates the period-1 branch's points, writes the config, types bad values and loads a
record that does not parse; then it kills the workers a diagram waits for and types w = 1e9 (the
core stalls): the page says what failed, and the next requests draw. It reads the plots' data
from the page's Bokeh document and keeps a screenshot in tests/artifacts/explorer.png (the docs
show it). Without Chromium the test is skipped, except under CI (CI set), where it fails.
"""

from __future__ import annotations

import os
import signal
import time
from pathlib import Path

import pytest
import yaml

pytest.importorskip("bokeh")
pytest.importorskip("selenium")

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from test_explorer import start_explorer, stop_explorer

CHROMIUM, CHROMEDRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
ARTIFACT = Path(__file__).parent / "artifacts" / "explorer.png"

# JS: every element below `root`, through shadow roots (Bokeh 3 draws its widgets in them)
DEEP = """
const found = [];
const walk = (n) => { found.push(n); if (n.shadowRoot) walk(n.shadowRoot); for (const c of n.children || []) walk(c); };
walk(document.body);
"""


@pytest.fixture(scope="module")
def browser():
    if not (CHROMIUM.exists() and CHROMEDRIVER.exists()):
        message = f"needs {CHROMIUM} and {CHROMEDRIVER} (apt-get install chromium chromium-driver)"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--window-size=1400,1250",
    ):
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("explore")
    args = ("--columns", "40", "--w-range", "30", "42", "--omega", "35", "--snippet", str(tmp / "view.yaml"))
    proc, url = start_explorer(*args, cwd=tmp)
    yield proc, url, tmp
    out = stop_explorer(proc)
    # the killed worker is one line of the log, nothing else failed loudly
    assert "Traceback" not in out and out.count("workers restarted") == 1, out


def _workers(pid: int) -> list[int]:
    """The worker processes of the server `pid` (its children that run spawn_main), whichever of
    its threads started them: a pool replaced or grown from a callback thread has its workers listed
    under that thread's task, not the main thread's."""
    found = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            children = (task / "children").read_text().split()
        except OSError:  # the thread ended meanwhile
            continue
        for c in children:
            try:
                if b"spawn_main" in Path(f"/proc/{c}/cmdline").read_bytes():
                    found.append(int(c))
            except OSError:  # the child ended meanwhile
                pass
    return found


def _model(driver, name: str, attr: str):
    return driver.execute_script(
        f"const v = Bokeh.documents[0].get_model_by_name('{name}')['{attr}'];"
        "return (v && v.length !== undefined && typeof v !== 'string') ? Array.from(v) : v;"
    )


def _range(driver) -> tuple[float, float]:
    r = driver.execute_script(
        "const r = Bokeh.documents[0].get_model_by_name('diagram_figure').x_range; return [r.start, r.end]"
    )
    return float(r[0]), float(r[1])


def _data(driver, source: str, column: str) -> list:
    return driver.execute_script(
        f"return Array.from(Bokeh.documents[0].get_model_by_name('{source}').data['{column}'] || [])"
    )


def _wait(predicate, what, timeout: float = 30.0):
    """`predicate()` once true, within `timeout`; else an AssertionError saying `what` (a text, or
    a function giving one that reads the page as it is then)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            value = predicate()
        except Exception:  # the page is still loading: no Bokeh document yet
            value = None
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what() if callable(what) else what}")


def _input(driver, label: str):
    """The text field under `label`, typed into as a user types (then Enter)."""
    return driver.execute_script(
        DEEP + "return found.find(n => n.tagName === 'INPUT' && "
        f"(n.closest('.bk-input-group')?.querySelector('label')?.textContent || '').startsWith({label!r}));"
    )


def _type(driver, label: str, text: str) -> None:
    field = _input(driver, label)
    field.clear()
    field.send_keys(text + "\n")


def _click(driver, text: str) -> None:
    driver.execute_script(
        DEEP + f"found.find(n => n.tagName === 'BUTTON' && n.textContent.trim() === {text!r}).click();"
    )


def _diagram_done(driver, lo: float, hi: float):
    """The diagram's 40 columns, all inside [lo, hi], once the page says they are complete."""
    if not _model(driver, "status", "text").startswith("40 columns in"):
        return None
    w = _data(driver, "diagram", "w")
    cols = sorted(set(w))
    return w if len(cols) == 40 and lo - 1e-9 <= cols[0] and cols[-1] <= hi + 1e-9 else None


def test_explorer_in_browser(browser, server):
    proc, url, tmp = server
    d = browser
    d.get(url)
    first = _wait(lambda: _diagram_done(d, 30, 42), "the first diagram")
    _wait(lambda: "w = 35 rad/s" in _model(d, "orbit", "text"), "the first attractor")

    # zoom: a box drawn with the mouse on the diagram (its active drag tool) sets its w range, and
    # the window is recomputed at full resolution; then a range typed exactly (as a box zoom sets it)
    canvas = d.execute_script(DEEP + "return found.filter(n => n.tagName === 'CANVAS')[0];")
    width, height = canvas.size["width"], canvas.size["height"]
    start = (-int(0.2 * width), -int(0.2 * height))  # offsets from the canvas's centre
    drag = ActionChains(d).move_to_element_with_offset(canvas, *start).click_and_hold()
    drag.move_by_offset(int(0.15 * width), int(0.3 * height)).release().perform()
    lo, hi = _wait(lambda: _range(d) if _range(d)[1] - _range(d)[0] < 6 else None, "the box zoom")
    boxed = _wait(lambda: _diagram_done(d, lo, hi), "the diagram of the drawn box")
    assert boxed != first and float(_model(d, "w_lo", "value")) == pytest.approx(lo, rel=1e-5)
    d.execute_script("Bokeh.documents[0].get_model_by_name('diagram_figure').x_range.setv({start: 36.5, end: 38.5})")
    zoomed = _wait(lambda: _diagram_done(d, 36.5, 38.5), "the zoomed diagram")
    assert zoomed != boxed and _model(d, "w_lo", "value") == "36.5"
    zoomed_y = _data(d, "diagram", "y")

    # a typed w: its attractor, and (period 2 past the doubling at 37.28) the shot orbit's multipliers
    series_before = _data(d, "series", "x")
    _type(d, "attractor at w", "37.6")
    _wait(lambda: "w = 37.6 rad/s" in (t := _model(d, "orbit", "text")) and "Floquet" in t, "the orbit at w = 37.6")
    assert "period 2" in _model(d, "orbit", "text")
    assert _model(d, "chosen_w", "location") == pytest.approx(37.6)
    assert _data(d, "series", "x") != series_before and len(_data(d, "impact_map", "s")) > 10

    # the xI slider: obstacle moved, diagram recomputed for the new model
    d.execute_script("Bokeh.documents[0].get_model_by_name('xI').value = -1.8e-3")
    _wait(lambda: _model(d, "obstacle", "location") == pytest.approx(-1.8e-3), "the obstacle line")
    # the obstacle may be drawn before the old columns are cleared: wait for the new ones
    _wait(
        lambda: _diagram_done(d, 36.5, 38.5) and sorted(_data(d, "diagram", "y")) != sorted(zoomed_y),
        "the diagram for xI = -1.8 mm",
        timeout=40,
    )
    moved = _data(d, "diagram", "w")

    # the located points of the period-1 branch in the window, and the nearest to the w shown
    _click(d, "Locate points")
    _wait(lambda: "located on the period-1 branch" in _model(d, "located", "text"), "the located points", timeout=60)
    assert "period doubling" in _model(d, "located", "text") and len(_data(d, "points", "w")) >= 1
    _wait(lambda: "nearest located points" in _model(d, "orbit", "text"), "the nearest located points")
    ARTIFACT.parent.mkdir(exist_ok=True)
    d.save_screenshot(str(ARTIFACT))

    # the view as a config and the command that draws it
    _click(d, "Write config")
    _wait(lambda: "snakemake -j2 fig02" in _model(d, "snippet", "text"), "the config snippet")
    config = yaml.safe_load((tmp / "view.yaml").read_text())
    assert config["model"] == {"xI": -1.8e-3}
    assert config["bifurcation"]["sweeps"]["increasing"]["start"] == 36.5

    # bad input: a message, nothing changes, the server lives on
    orbit, series = _model(d, "orbit", "text"), _data(d, "series", "x")
    for value, message in (("abc", "is not a number"), ("-2", "must be")):
        _type(d, "attractor at w", value)
        _wait(lambda message=message: message in _model(d, "message", "text"), f"the message for w = {value}")
        assert _model(d, "orbit", "text") == orbit and _data(d, "series", "x") == series
    _type(d, "w from", "40")
    _click(d, "Recompute")
    _wait(lambda: "low to high" in _model(d, "message", "text"), "the message for a reversed range")
    assert _data(d, "diagram", "w") == moved
    (tmp / "bad.csv").write_text("this is not a record\n1,2,3\n")
    _type(d, "record file", str(tmp / "bad.csv"))
    _click(d, "Load record")
    _wait(lambda: "bad.csv" in _model(d, "message", "text"), "the message for a record that does not parse")
    assert _data(d, "record", "w") == [] and "this is not a record" not in _model(d, "message", "text")
    assert proc.poll() is None

    # the workers killed while a diagram waits for them: the page says why the diagram failed. They
    # are stopped (SIGSTOP) before the diagram is asked for, so that its batches cannot end before
    # the kill whatever the timing: the page lags behind the server (under load by 10 s and more,
    # drawing the columns streamed), and a diagram it still showed running had ended, its workers
    # idle, and their death failed no request
    _type(d, "w from", "36.5")
    _type(d, "columns", "2000")
    victims = _wait(lambda: _workers(proc.pid), "the explorer's worker processes")
    for victim in victims:
        os.kill(victim, signal.SIGSTOP)
    try:
        _click(d, "Recompute")
        # the page shows this once the server has run the click's callback, which queued the
        # diagram's first batches on the (stopped) workers
        _wait(lambda: "computing 2000 columns" in _model(d, "status", "text"), "the diagram of 2000 columns asked for")
    finally:
        for victim in victims:  # a stopped worker left alive would hang the server's shutdown
            os.kill(victim, signal.SIGKILL)
    # (the worker named is the one the pool found dead: not always the first listed)
    _wait(
        lambda: "killed by SIGKILL" in _model(d, "status", "text"),
        lambda: (
            f"the failed diagram's status (status: {_model(d, 'status', 'text')!r}, message: {_model(d, 'message', 'text')!r})"
        ),
        timeout=60.0,
    )
    assert "restarted" in _model(d, "message", "text")
    # w = 1e9 stalls the core: a message, and the workers live on
    _type(d, "attractor at w", "1e9")
    _wait(lambda: "StallError" in _model(d, "message", "text"), "the message for w = 1e9")
    # the next requests draw
    _type(d, "attractor at w", "37.6")
    _wait(lambda: "w = 37.6 rad/s" in _model(d, "orbit", "text"), "the attractor after the failures")
    assert _model(d, "message", "text") == ""
    _type(d, "columns", "40")
    _click(d, "Recompute")
    _wait(lambda: _diagram_done(d, 36.5, 38.5), "the diagram after the failures")
    assert proc.poll() is None and not set(victims) & set(_workers(proc.pid))
