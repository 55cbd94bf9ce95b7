"""Every value on the command line gets a clean answer: the command runs (exit 0), or it refuses in
one line naming the command (and the option), exit 2 (3: the core stopped, naming where), with
no traceback, in bounded time, and nothing written (no output, no temporary file).

"One line" for argparse's own refusals (a value that is not a number, a missing argument): its
usage lines, then the one ``impactosc <command>: error: argument --option: ...`` line; the
usage is argparse's help, not an error of its own. Warnings (a parameter outside the tested
ranges) come as one ``impactosc: warning:`` line each before the answer.

The commands run in this process (``main([...])``, stderr captured) on tiny scenes; a value
that would run long (a valid hour of simulated time) is not drawn, since that is not an error.
"""

import contextlib
import io
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from impactosc.cli.main import main
from impactosc.core.simulation import MAX_T_END
from impactosc.model.model_file import write_model_file
from impactosc.model.parameters import ModelParams
from impactosc.records.formats import write_record
from impactosc.records.surrogate import SurrogateOptions, surrogate_ramp, surrogate_record

#: Longest a refusal or a tiny run may take, s (a stall spends the watchdog's 1e6 attempts in
#: about 1 s; the first call of a kind loads the compiled kernels).
CALL_TIMEOUT = 20.0
#: Values no check may let through untreated.
NASTY = (1e300, -1e300, 1e-300, -1e-300, 0.0, -0.0, math.nan, math.inf, -math.inf, 1e12, -1e12, 5e-324)
MODEL_NAMES = ("m", "m0e", "k", "c", "T", "eps", "kI", "b", "n1", "n2", "n3", "xI")


class CallTimeout(BaseException):
    """A command ran past CALL_TIMEOUT."""


def _alarm(signum, frame):
    raise CallTimeout()


def run(argv, out):
    """(exit status, stderr lines, seconds) of ``impactosc argv``, checked for a clean answer."""
    err = io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, CALL_TIMEOUT)
    t0 = time.perf_counter()
    try:
        # Python's own warning filters, as on the command line (pytest's turn warnings into errors)
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
            warnings.resetwarnings()
            try:
                code = main([str(a) for a in argv])
            except SystemExit as exc:  # argparse's refusals
                code = exc.code
    except BaseException as exc:
        chain = exc
        while chain is not None and not isinstance(chain, CallTimeout):
            chain = chain.__cause__ or chain.__context__
        if chain is not None:
            pytest.fail(f"impactosc {' '.join(map(str, argv))}: no answer within {CALL_TIMEOUT:g} s")
        raise
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    seconds = time.perf_counter() - t0
    lines = err.getvalue().splitlines()
    assert_clean(argv, code, lines, out)
    return code, lines, seconds


def assert_clean(argv, code, lines, out):
    command = argv[0]
    said = f"impactosc {' '.join(map(str, argv))}: exit {code}, stderr {lines}"
    assert code in (0, 2, 3), said
    assert not any("Traceback" in line for line in lines), said
    assert all(line.startswith("impactosc: warning:") for line in lines if "Warning" in line), said
    leftovers = [p for p in os.listdir(out.parent) if p.endswith(".tmp")]
    assert not leftovers, said
    if code == 0:
        assert out.exists(), said
        out.unlink()
        return
    errors = [line for line in lines if line.startswith(f"impactosc {command}: error:")]
    assert len(errors) == 1 and lines[-1] == errors[0], said
    assert not out.exists(), said


def text(value):
    """A float as a user types it; repr keeps every digit (1e-300, -0.0, nan, -inf)."""
    return repr(float(value)) if not isinstance(value, str) else value


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A constant-w record, a slow-sweep record with its phase and a model file, each tiny."""
    d = tmp_path_factory.mktemp("records")
    rec, _ = surrogate_record(40.86, 5.0, 2.0, SurrogateOptions(rate=2000.0))
    write_record(d / "rec.csv", rec.t, rec.x, omega=rec.omega, meta=rec.meta)
    ramp, _ = surrogate_ramp(40.0, 40.5, 20.0, SurrogateOptions(rate=500.0), n_initial=20)
    write_record(d / "sweep.h5", ramp.t, ramp.x, meta=ramp.meta, phase=ramp.phase)
    write_model_file(d / "bc.yaml", ModelParams())
    return d


# --- what is drawn: for each option, a value that runs a tiny scene or one drawn anywhere; an
# option whose valid values include long runs (durations, rates, windows) draws anywhere only among
# the values the command must refuse


def anywhere():
    return st.one_of(st.sampled_from(NASTY), st.floats(allow_nan=True, allow_infinity=True))


def refused_time():
    """Durations and times a run cannot take: beyond MAX_T_END, negative, not finite."""
    return st.one_of(
        st.sampled_from((1e300, -1e300, -1.0, math.nan, math.inf, -math.inf)),
        st.floats(min_value=MAX_T_END * 1.0001, max_value=1e308),
        st.floats(max_value=-1e-300),
    )


def tiny_or(lo, hi, refused):
    return st.one_of(st.floats(min_value=lo, max_value=hi), refused)


def assignment(names):
    return st.tuples(st.sampled_from(names), anywhere()).map(lambda nv: f"{nv[0]}={text(nv[1])}")


def values(*strategies):
    return st.tuples(*strategies)


def narrow(w_range):
    """A valid w range moved into model BC's band (20..45 rad/s) and made 0.01 rad/s wide: predict's
    work grows with the range's width and, below it, with the forcing period (measured, 2..2.002
    rad/s takes over 20 s), which is long work, not an error. Refused ranges stay as drawn."""
    lo, hi = w_range
    if not 0 < lo < hi:
        return w_range
    lo = 20.0 + lo % 25.0
    return (lo, lo + 0.01)


#: Per command: the arguments of a tiny scene (FILES stands for the fixture's folder), and each
#: numeric option with what is drawn for it (a tuple: the option's several values).
COMMANDS = {
    "simulate": (
        ["--omega", "40.86", "--transient", "0", "--duration", "0.05", "--quiet"],
        {
            "--omega": anywhere(),
            "--transient": tiny_or(0.0, 0.05, refused_time()),
            "--duration": tiny_or(1e-6, 0.05, refused_time()),
            "--x0": anywhere(),
            "--v0": anywhere(),
            "--rtol": anywhere(),
            "--atol": anywhere(),
            "--step-budget": tiny_or(100.0, 1e6, st.one_of(st.sampled_from(NASTY), st.floats(max_value=99.0))),
            "--window": values(anywhere(), anywhere(), st.one_of(st.sampled_from(NASTY), st.floats(max_value=1e-3))),
            "--param": assignment(MODEL_NAMES),
        },
    ),
    "surrogate": (
        ["--transient", "0", "--duration", "0.2"],  # --omega 40.86 unless --ramp is drawn
        {
            "--omega": anywhere(),
            "--ramp": values(anywhere(), anywhere()),
            "--transient": tiny_or(0.0, 0.1, refused_time()),
            "--duration": tiny_or(0.01, 0.2, refused_time()),
            "--rate": tiny_or(100.0, 1e5, st.one_of(st.sampled_from(NASTY), st.floats(min_value=1e13))),
            "--noise": anywhere(),
            "--lowpass": anywhere(),
            "--lowpass-order": st.integers(-100, 100),
            "--drift": anywhere(),
            "--drift-time": anywhere(),
            "--clock-jitter": anywhere(),
            "--quantum": anywhere(),
            "--encoder-counts": st.integers(-(10**9), 10**9),
            "--seed": st.integers(-(10**30), 10**30),
            "--mismatch": assignment(MODEL_NAMES),
            "--param": assignment(MODEL_NAMES),
        },
    ),
    "extract": (
        ["FILES/rec.csv"],
        {
            "--x-impact": anywhere(),
            "--omega": anywhere(),
            "--noise": anywhere(),
            "--sensor-delay": anywhere(),
            "--contact-exponent": anywhere(),
            "--param": assignment(("xI",)),
        },
    ),
    "sweep-extract": (
        ["FILES/sweep.h5"],
        {
            "--bin-width": anywhere(),
            "--settle": anywhere(),
            "--min-points": st.integers(-(10**30), 10**30),
        },
    ),
    "predict": (
        ["FILES/bc.yaml", "--w-range", "20", "20.01", "--quiet"],
        {
            "--w-range": values(anywhere(), anywhere()).map(narrow),
            "--seed-omega": anywhere(),
            "--max-period": st.one_of(st.integers(max_value=0), st.integers(min_value=65)),
        },
    ),
    "identify": (
        ["FILES/rec.csv", "--quiet"],
        {
            "--mass": anywhere(),
            "--stages": values(anywhere()),
            "--duration": anywhere(),
        },
    ),
}
#: The file each command writes.
OUTPUT = {"predict": "out.csv", "identify": "out.yaml"}
#: Examples drawn per command, in the default run and in the slow one: identify fits the record
#: when a value is valid (about 1.5 s a fit), the others answer in milliseconds.
EXAMPLES = {"identify": 6}
EXAMPLES_SLOW = {"identify": 100}


def command_line(command, files, option, value, out):
    base, _ = COMMANDS[command]
    argv = [command, *(str(a).replace("FILES", str(files)) for a in base)]
    if command == "surrogate" and option != "--ramp":
        argv += ["--omega", "40.86"]
    given = value if isinstance(value, tuple) else (value,)
    return [*argv, option, *map(text, given), "--output", out]


def option_values(command):
    options = COMMANDS[command][1]
    return st.sampled_from(sorted(options)).flatmap(lambda o: st.tuples(st.just(o), options[o]))


SWEEP = settings(
    max_examples=60,
    deadline=None,  # CALL_TIMEOUT bounds each call; the first call of a kind loads kernels
    derandomize=True,  # the same examples on every run (CI)
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


def sweep(command, files, tmp_path, budget):
    out = tmp_path / OUTPUT.get(command, "out.h5")

    @budget
    @given(option_values(command))
    def check(drawn):
        run(command_line(command, files, *drawn, out), out)

    check()


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_drawn_values_get_a_clean_answer(command, files, tmp_path):
    sweep(command, files, tmp_path, settings(SWEEP, max_examples=EXAMPLES.get(command, SWEEP.max_examples)))


@pytest.mark.slow
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_more_drawn_values_get_a_clean_answer(command, files, tmp_path):
    sweep(command, files, tmp_path, settings(SWEEP, max_examples=EXAMPLES_SLOW.get(command, 1000)))


# --- the held-out list: each numeric option of each command, given each nasty value

HUGE_WINDOWS = [(0, 0.05, 1e-300), (0, 0.05, 1e-12), (-1e300, 1e300, 1e-300), (0, 1e300, 1), (0.05, 0, 1e-3)]


def nasty_cases(fits=False):
    """(command, option, value) of every numeric option and nasty value; identify's valid values
    (which fit the record) only with ``fits``."""
    for command, (_, options) in sorted(COMMANDS.items()):
        if command == "identify":
            yield from (("identify", o, v) for o in sorted(options) for v in NASTY if fits or not v > 0)
            continue
        for option in sorted(options):
            if option == "--window":
                yield from ((command, option, w) for w in HUGE_WINDOWS)
            elif option in ("--param", "--mismatch"):
                names = ("xI",) if command == "extract" else MODEL_NAMES
                yield from ((command, option, f"{n}={text(v)}") for n in names for v in NASTY)
            elif option in ("--ramp", "--w-range"):
                # a valid wide w range is long work, not an error: predict's lower end stays at 20
                yield from ((command, option, (v, 40.0)) for v in NASTY if option == "--ramp" or not 0 < v < 20)
                yield from ((command, option, (20.0, v)) for v in NASTY)
            elif option in ("--lowpass-order", "--encoder-counts", "--seed", "--min-points", "--max-period"):
                yield from ((command, option, v) for v in (0, -1, 10**12, "1e300", "nan"))
            else:
                yield from ((command, option, v) for v in NASTY)


@pytest.mark.parametrize("fits", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_nasty_values_get_a_clean_answer(files, tmp_path, fits):
    """Every case of :func:`nasty_cases` (some 850 calls, most refused at once)."""
    codes = []
    for command, option, value in nasty_cases(fits):
        out = tmp_path / OUTPUT.get(command, "out.h5")
        codes.append(run(command_line(command, files, option, value, out), out)[0])
    # the list holds values that run (0, a tiny time) and values that are refused
    assert codes.count(2) > len(codes) / 2 and 0 in codes


def test_reported_values_are_refused_by_option(files, tmp_path, monkeypatch):
    """The values that once ended in a traceback, a hang or the kernel's kill: each refused in
    one line naming its option, before the compiled core runs (every integration goes through
    driver.run: a call to it fails the case, whatever the machine's speed)."""
    from impactosc.core import driver

    def no_integration(*args):
        raise AssertionError("the core ran before the value was refused")

    monkeypatch.setattr(driver, "run", no_integration)
    out = tmp_path / "out.h5"
    sim = ["simulate", "--omega", "40.86", "--transient", "0", "--duration", "1", "--output", out]
    sur = ["surrogate", "--omega", "40.86", "--transient", "0", "--duration", "1", "--output", out]
    cases = [
        ([*sim, "--x0", "1e300"], "--x0"),
        ([*sim, "--v0", "-1e300"], "--v0"),
        ([*sim, "--param", "eps=1e300"], "--param"),
        ([*sim, "--param", "eps=1e-300"], "--param"),
        ([*sim, "--param", "n3=1e-300"], "--param"),
        ([*sim, "--window", "0", "1", "1e-12"], "--window"),
        ([*sim, "--window", "0", "1", "1e-10"], "--window"),  # 10 G samples, 320 GB
        ([*sim, "--transient", "1e300"], "--transient/--duration"),
        ([*sim, "--duration", "1e300"], "--transient/--duration"),
        ([*sim, "--duration", "1e9"], "--transient/--duration"),
        ([*sim, "--step-budget", "1e300"], "--step-budget"),
        ([*sur, "--rate", "1e12"], "--rate"),
        (["extract", files / "rec.csv", "--sensor-delay", "1e300", "--output", out], "--sensor-delay"),
        ([*sur, "--rate", "1e-300"], "--rate"),  # one sample: a file no command could read
        ([*sur, "--seed", "-1"], "--seed"),
        (["predict", files / "bc.yaml", "--w-range", "36.9", "37.6", "--seed-omega", "1e300"], "--seed-omega"),
    ]
    for argv, option in cases:
        code, lines, _ = run(argv, out)
        assert code == 2 and lines[-1].startswith(f"impactosc {argv[0]}: error: {option}: "), (argv, lines)
    code, lines, _ = run([*sim, "--window", "0", "1", "1e-12"], out)
    assert "GB" in lines[-1] and "coarser step" in lines[-1]
    # a forcing faster than the samples (numpy's own error before): named with the record
    code, lines, _ = run(["extract", files / "rec.csv", "--omega", "1e300", "--output", out], out)
    assert code == 2 and "shorter than two sample intervals" in lines[-1], lines


def test_negative_numbers_in_any_notation_follow_their_option(tmp_path):
    out = tmp_path / "out.h5"
    argv = ["simulate", "--omega", "40.86", "--transient", "0", "--duration", "0.1", "--quiet", "--output", out]
    code, lines, _ = run([*argv, "--x0", "-2e-3", "--v0", "-.5E-1", "--window", "-1e-3", "0.1", "1e-2"], out)
    # the window's start is before the run's: refused by the window check, not taken for an option
    assert code == 2 and "error: --window: window [-0.001, 0.1] s must lie inside" in lines[-1]
    code, lines, _ = run([*argv, "--x0", "-2e-3", "--v0", "-.5E-1", "--window", "1e-3", "0.1", "1e-2"], out)
    assert code == 0
    code, lines, _ = run([*argv, "--x0", "-inf"], out)
    assert code == 2 and lines[-1].endswith("argument --x0: '-inf' is not finite")
    code, lines, _ = run([*argv, "--x0", "-2e-3x"], out)  # not a number: argparse's own refusal
    assert code == 2 and "--x0" in lines[-1]


# --- SIGTERM and SIGINT: the process stops, its temporary file goes with it

#: ``impactosc`` whose run-file writer announces itself and waits inside atomic_write's block:
#: the signal then surely arrives while the temporary file exists, without timing guesses.
SLOW_WRITER = textwrap.dedent(
    """
    import signal, sys, time
    # as a command typed in a terminal: a shell without job control starts its background jobs
    # (a CI runner's, or `make test &`) with SIGINT ignored, and Python then keeps it ignored
    signal.signal(signal.SIGINT, signal.default_int_handler)
    import impactosc.io.files as files
    stamp = files.stamp_h5
    def stamp_slowly(f, **kwargs):
        print("writing", flush=True)
        time.sleep(120)
        stamp(f, **kwargs)
    files.stamp_h5 = stamp_slowly
    from impactosc.cli.main import main
    sys.exit(main(sys.argv[1:]))
    """
)


def _wait_for(proc, stream, marker, timeout=120.0):
    """Read ``stream`` of ``proc`` until a line holds ``marker`` (fails if the process ends first)."""
    import selectors

    sel = selectors.DefaultSelector()
    sel.register(stream, selectors.EVENT_READ)
    end = time.monotonic() + timeout
    seen = []
    while time.monotonic() < end:
        if sel.select(timeout=0.5):
            line = stream.readline()
            seen.append(line)
            if marker in line:
                return
            if not line and proc.poll() is not None:
                break
    proc.kill()
    pytest.fail(f"no {marker!r} from the command; it said {seen}")


@pytest.mark.parametrize(("sig", "status"), [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_while_writing_leaves_no_file(tmp_path, sig, status):
    out = tmp_path / "run.h5"
    argv = ["simulate", "--omega", "40.86", "--transient", "0", "--duration", "1", "--quiet", "--output", out]
    proc = subprocess.Popen(
        [sys.executable, "-c", SLOW_WRITER, *map(str, argv)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    _wait_for(proc, proc.stdout, "writing")
    written = [p.name for p in tmp_path.iterdir()]
    assert len(written) == 1 and written[0].endswith(".tmp")  # the write is under way
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err
    assert list(tmp_path.iterdir()) == [], err
    assert err.splitlines()[-1].endswith("nothing written")


def test_sigterm_while_running_stops_with_nothing_written(tmp_path):
    """A run of about a minute says its expected wall time after 3 s, and SIGTERM then stops it."""
    out = tmp_path / "run.h5"
    argv = ["simulate", "--omega", "40.86", "--transient", "0", "--duration", "1e5", "--output", out]
    proc = subprocess.Popen(
        [sys.executable, "-m", "impactosc.cli.main", *map(str, argv)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    _wait_for(proc, proc.stderr, "impactosc simulate: expected wall time ~")
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err
    assert list(tmp_path.iterdir()) == []
    assert err.splitlines()[-1] == "impactosc simulate: terminated (SIGTERM), nothing written"


def test_the_expected_wall_time_is_said_once_and_not_when_quiet(capsys):
    from impactosc.cli.progress import WallTimeForecast

    said = WallTimeForecast("simulate")
    said.start -= 10.0  # as if 10 s had passed
    said(0.001)
    said(0.002)
    assert capsys.readouterr().err == "impactosc simulate: expected wall time ~2.8 h (0.1 % done after 10 s)\n"
    quiet = WallTimeForecast("simulate", quiet=True)
    quiet.start -= 10.0
    quiet(0.001)
    nearly_done = WallTimeForecast("simulate")
    nearly_done.start -= 10.0
    nearly_done(0.9)
    assert capsys.readouterr().err == ""


def test_sigterm_to_a_workflow_script_leaves_no_file(tmp_path):
    """The workflow's scripts start with configure_logging, which makes SIGTERM (Snakemake
    stopping a job) unwind as the command line does."""
    scripts = os.path.join(os.path.dirname(__file__), os.pardir, "workflow", "scripts")
    script = textwrap.dedent(
        f"""
        import sys, time
        sys.path.insert(0, {scripts!r})
        from _logging import configure_logging
        configure_logging()
        from impactosc.io.files import atomic_write
        with atomic_write({str(tmp_path / "table.csv")!r}) as tmp:
            open(tmp, "w").write("half a table")
            print("writing", flush=True)
            time.sleep(120)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _wait_for(proc, proc.stdout, "writing")
    assert len(list(tmp_path.iterdir())) == 1
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143, err
    assert list(tmp_path.iterdir()) == []
