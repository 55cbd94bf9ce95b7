"""The speed benchmark's table and headline (benchmarks/core_speed.py) and the round-robin
timing it shares with the peers (timing_rounds.measure_contestants). No solver runs here: the
contestants are stand-ins."""

import math

import numpy as np
import pytest

from impactosc.io.files import read_table, write_table
from impactosc_bench import core_speed as cs
from impactosc_bench import scene, timing_rounds


def _row(solver, rtol, wall, error, on=True, kind="scene", **extra):
    return dict(
        solver=solver,
        kind=kind,
        rtol=rtol,
        wall_time=wall,
        wall_time_min=wall * 0.9,
        repeats=3,
        impact_time_error_1p5s=error,
        n_impacts=2898,
        on_attractor=on,
        **extra,
    )


def _rows():
    return [
        _row(cs.CORE, 1e-8, 0.35, 6e-8),  # fastest core run, too inaccurate
        _row(cs.CORE, 1e-9, 0.38, 3e-9),  # just above the bound
        _row(cs.CORE, 1e-10, 0.41, 1.8e-9),  # the core's headline run
        _row(cs.CORE, 1e-11, 0.47, 2e-10),
        _row("CyRK DOP853", 1e-11, 1.10, 2.2e-9),
        _row("CyRK Vern7", 1e-10, 1.05, 1.2e-10),  # the fastest compiled peer
        _row("CyRK Vern8", 1e-12, 0.70, 3e-11, on=False),  # fast and accurate, but stopped at 263 s
        _row(cs.SCIPY, 1e-8, 48.0, 3.6e-8),
        _row(cs.SCIPY, 1e-10, 66.6, 3.9e-9),
        dict(solver="heyoka Taylor (order 13) free flight", kind="floor", rtol=1e-10, wall_time=0.02),
    ]


def test_headline_compares_the_fastest_runs_at_the_error_bound():
    head = {h["role"]: h for h in cs.core_speed_headline(_rows(), max_error=2.5e-9)}
    assert head["core"]["rtol"] == 1e-10 and head["core"]["time_over_core"] == 1.0
    peer = head["fastest compiled peer"]
    assert (peer["solver"], peer["rtol"]) == ("CyRK Vern7", 1e-10)
    assert peer["time_over_core"] == pytest.approx(1.05 / 0.41)
    # no SciPy run reaches 2.5e-9: SciPy at the core's rtol, as the table always compared
    assert head["SciPy"]["rtol"] == 1e-10 and "at the core's rtol" in head["SciPy"]["note"]
    assert head["SciPy"]["time_over_core"] == pytest.approx(66.6 / 0.41)
    assert head["free-flight floor"]["solver"].startswith("heyoka")
    # a looser bound: SciPy at equal error, and the core's faster rtol
    loose = {h["role"]: h for h in cs.core_speed_headline(_rows(), max_error=1e-7)}
    assert loose["core"]["rtol"] == 1e-8 and loose["SciPy"]["rtol"] == 1e-8
    assert loose["SciPy"]["note"] == "at equal error (<= 1e-07 s)"


def test_headline_without_qualifying_rows_says_none():
    rows = [r for r in _rows() if not r["solver"].startswith("CyRK")]
    head = {h["role"]: h for h in cs.core_speed_headline(rows, max_error=2.5e-9)}
    assert head["fastest compiled peer"]["solver"] == "none"
    assert head["fastest compiled peer"]["note"].startswith("no run with error <= 2.5e-09 s")
    no_scipy = {h["role"]: h for h in cs.core_speed_headline([r for r in rows if r["solver"] != cs.SCIPY])}
    assert no_scipy["SciPy"]["note"] == "not measured"
    assert "no compiled peer" in cs.headline_sentence(list(head.values()))
    none = cs.core_speed_headline(rows, max_error=1e-15)
    assert none[0]["solver"] == "none" and cs.headline_sentence(none).startswith("No run of the core")


def test_headline_reads_its_rows_back_from_csv(tmp_path):
    """benchmark_core.csv says on_attractor yes/no; best_peer reads either form."""
    back = read_table(write_table(tmp_path / "b.csv", _rows()))
    head = {h["role"]: h for h in cs.core_speed_headline(back, max_error=2.5e-9)}
    assert head["fastest compiled peer"]["solver"] == "CyRK Vern7"
    sentence = cs.headline_sentence(cs.core_speed_headline(back, max_error=2.5e-9))
    assert "CyRK Vern7 at rtol 1e-10" in sentence and "2.56x the core's time" in sentence
    assert sentence.index("CyRK") < sentence.index("SciPy")  # the peer first, then SciPy


def test_markdown_table_marks_what_does_not_apply():
    rows = [
        dict(
            solver="heyoka free flight",
            rtol=1e-10,
            wall_time=0.02,
            steps_per_period=15.5,
            impact_time_error_1p5s=None,
            n_impacts=math.nan,
            on_attractor=None,
            status="ok",
        ),
        dict(
            solver="CyRK DOP853",
            rtol=1e-12,
            wall_time=0.8,
            impact_time_error_1p5s=2.9e-11,
            n_impacts=1177.0,
            on_attractor=False,
            status="stopped at t = 263.8 s: step | size",
        ),
    ]
    lines = cs.markdown_table(rows, cs.TABLE_COLUMNS)
    assert lines[0].startswith("| solver | rtol |") and len(lines) == 4
    cells = [c.strip() for c in lines[2].split("|")[1:-1]]
    assert cells[cs.TABLE_COLUMNS.index(("n_impacts", "impacts 100-500 s", "d"))] == "-"
    cells = [c.strip() for c in lines[3].split("|")[1:-1]]
    assert "1177" in cells and "no" in cells and "step / size" in lines[3]  # a '|' would split the cell


def test_serpentine_alternates_direction():
    assert timing_rounds.serpentine([1, 2, 3], 0) == [1, 2, 3]
    assert timing_rounds.serpentine([1, 2, 3], 1) == [3, 2, 1]
    assert timing_rounds.serpentine(range(3), 2) == [0, 1, 2]


class _Fake:
    """A contestant's runs: logs the order they are called in, wall times from a list."""

    def __init__(self, name, walls, log, impacts, success=True):
        self.name, self.walls, self.log, self.impacts, self.success = name, list(walls), log, impacts, success

    def run(self):
        self.log.append(self.name)
        return timing_rounds.PeerRun(
            self.walls.pop(0),
            1000,
            self.impacts,
            timing_rounds.T_END if self.success else 263.8,
            np.zeros(2),
            self.success,
            "" if self.success else "step size underflow",
            extra={"rhs": 12000},
        )

    def short(self):
        return timing_rounds.PeerRun(0.0, 10, np.array([0.1, 0.5 + 2e-9]), scene.ERR_HORIZON, np.zeros(2), True, "")


def test_measure_contestants_times_round_robin_and_reports_medians():
    log = []
    attractor = np.linspace(100.0, 500.0, 2900)
    a = _Fake("a", [0.5, 0.1, 0.3], log, attractor)
    b = _Fake("b", [1.0, 2.0, 3.0], log, attractor[:1177], success=False)
    floor = _Fake("floor", [0.02, 0.03, 0.01], log, np.empty(0))
    contestants = [
        timing_rounds.Contestant("core", "scene", 1e-10, 1e-12, a.run, a.short),
        timing_rounds.Contestant("CyRK DOP853", "scene", 1e-12, 1e-14, b.run, b.short),
        timing_rounds.Contestant("floor", "floor", 1e-10, 1e-12, floor.run),
    ]
    rows = timing_rounds.measure_contestants(
        contestants, 3, reference_impacts=2898, ref_times=np.array([0.1, 0.5]), log=lambda _: None
    )
    assert log == ["a", "b", "floor", "floor", "b", "a", "a", "b", "floor"]
    core, cyrk, fl = rows
    assert core["wall_time"] == 0.3 and core["wall_time_min"] == 0.1 and core["repeats"] == 3
    assert core["impact_time_error_1p5s"] == pytest.approx(2e-9) and core["on_attractor"] is True
    assert core["rhs"] == 12000 and core["n_impacts"] == 2900
    assert cyrk["on_attractor"] is False and cyrk["status"].startswith("stopped at t = 263.8 s")
    assert "impact_time_error_1p5s" not in fl and fl["wall_time"] == 0.02
    with pytest.raises(ValueError, match="repeats"):
        timing_rounds.measure_contestants(contestants, 0, reference_impacts=2898, ref_times=np.empty(0))


def test_a_revisions_core_is_no_peer_and_has_its_own_lines():
    """The core of another revision (impactosc_bench.core_revision) runs in the same rounds: it
    is never the headline's compiled peer, and its lines give this core's time over its own."""
    from impactosc_bench.core_revision import revision_lines

    old = f"{cs.CORE} at abc1234"
    rows = [*_rows(), _row(old, 1e-10, 0.05, 1.8e-9, bit_for_bit=True), _row(old, 1e-8, 0.40, 6e-8)]
    head = {h["role"]: h for h in cs.core_speed_headline(rows, max_error=2.5e-9)}
    assert head["fastest compiled peer"]["solver"] == "CyRK Vern7"
    lines = revision_lines(rows, cs.CORE)
    assert len(lines) == 4 and lines[0].startswith("| revision |")
    assert lines[2] == f"| {old} | 1e-10 | 0.4100 | 0.0500 | 8.200 | yes |"
    assert lines[3].endswith("| 0.875 | no |")
    assert revision_lines(_rows(), cs.CORE) == []


def test_a_revision_that_is_none_is_named():
    from impactosc_bench.core_revision import RevisionCore

    with pytest.raises(ValueError, match="--against 'no-such-revision': not a git revision"):
        RevisionCore("no-such-revision")


@pytest.mark.slow
def test_the_core_of_the_last_commit_runs_as_a_contestant():
    """The last commit's core, in its own process, gives this core's impacts bit for bit when the
    core and the model are those of that commit."""
    import subprocess

    from impactosc_bench.core_revision import RevisionCore, same_impacts
    from impactosc_bench.core_speed import run_core_from_rest

    changed = subprocess.run(["git", "diff", "--quiet", "HEAD", "--", "src/impactosc"], check=False).returncode
    if changed:
        pytest.skip("the library differs from the last commit's")
    core = RevisionCore("HEAD")
    try:
        assert same_impacts(core, run_core_from_rest, 1e-8, 0.0, 20.0)
    finally:
        core.close()
