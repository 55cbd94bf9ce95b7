"""The core of another git revision as a contestant: old and new timed in the same rounds.

Why: a change to the core must keep its speed (within 5 % on the chaotic scene) and, for model
BC, its results bit for bit. Timings on a shared machine drift by more than that between two
runs, so the revision's core runs beside this one, round-robin in the same timing rounds
(:func:`impactosc_bench.timing_rounds.measure_contestants`), and its impacts are compared with
this core's.

Two modules of one name cannot live in one process, so the revision's ``src/`` is exported
(``git archive``) into a temporary folder and its core runs in a worker process of its own,
with its own numba cache, fed one run at a time over a pipe. The worker times its own
``simulate`` call, as :func:`impactosc_bench.core_speed.run_core_from_rest` does, so the pipe's
milliseconds are not counted. The worker uses only ``simulate(omega, transient, duration,
rtol=, atol=, record=("impacts",))``, which every revision has.

By hand, without the peers (against the last commit a clean tree measures the method's own
noise)::

    python -m impactosc_bench.core_speed --against HEAD~1 --repeats 7
"""

from __future__ import annotations

import atexit
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from impactosc_bench.scene import ERR_HORIZON, OMEGA
from impactosc_bench.timing_rounds import Contestant, PeerRun

__all__ = ["export_revision", "revision_env", "RevisionCore", "revision_contestants", "revision_lines", "same_impacts"]

#: the worker: one JSON request per line (rtol, atol, transient, duration), one JSON answer per line
_WORKER = r"""
import json, sys, time
import numpy as np
from impactosc.core.simulation import simulate
for line in sys.stdin:
    q = json.loads(line)
    t0 = time.perf_counter()
    try:
        res = simulate(q["omega"], q["transient"], q["duration"], rtol=q["rtol"], atol=q["atol"], record=("impacts",))
    except Exception as e:  # a stall of the old core is a row, not a crash
        print(json.dumps({"wall": time.perf_counter() - t0, "error": f"{type(e).__name__}: {e}"}), flush=True)
        continue
    wall = time.perf_counter() - t0
    a = res.attrs
    print(json.dumps({
        "wall": wall, "steps": int(a["n_steps"] + a["n_implicit_steps"]),
        "impacts_t": np.asarray(res.events["impacts"]["t"], float).tolist(),
        "state": [float(v) for v in res.final_state[1:3]], "t_end": q["transient"] + q["duration"],
    }), flush=True)
"""


def _git(*args: str, cwd: Path) -> str:
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True, text=True).stdout.strip()


def export_revision(rev: str, path: str = "src", repo: Path | None = None) -> tuple[str, Path]:
    """``path`` of git revision `rev` exported into a new temporary folder (removed at exit):
    (its short commit, the folder). A run with :func:`revision_env` imports from it."""
    repo = Path(repo or Path(__file__).resolve().parents[2])
    try:
        commit = _git("rev-parse", "--short", f"{rev}^{{commit}}", cwd=repo)
    except (subprocess.CalledProcessError, FileNotFoundError):
        raise ValueError(f"--against {rev!r}: not a git revision of {repo}") from None
    folder = Path(tempfile.mkdtemp(prefix=f"core-{commit}-"))
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    archive = subprocess.run(["git", "archive", commit, path], cwd=repo, check=True, capture_output=True)
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive.stdout, check=True)
    return commit, folder


def revision_env(folder: Path) -> dict:
    """The environment of a process that imports the exported revision's packages before the
    installed ones, with a numba cache of its own."""
    return {**os.environ, "PYTHONPATH": str(folder / "src"), "NUMBA_CACHE_DIR": str(folder / "numba")}


class RevisionCore:
    """A worker process running the core of git revision `rev` of the repository at `repo`."""

    def __init__(self, rev: str, repo: Path | None = None):
        self.commit, self.folder = export_revision(rev, "src", repo)
        self.label = f"impactosc core at {self.commit}"
        atexit.register(self.close)
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _WORKER],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            env=revision_env(self.folder),
        )

    def run(self, rtol: float, atol: float, transient: float, duration: float) -> PeerRun:
        """One run of the revision's core from rest, as a PeerRun (its own wall time)."""
        request = {"omega": OMEGA, "rtol": rtol, "atol": atol, "transient": transient, "duration": duration}
        self.proc.stdin.write(json.dumps(request) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"the worker of {self.label} ended (exit code {self.proc.wait()})")
        a = json.loads(line)
        if "error" in a:
            return PeerRun(a["wall"], 0, np.empty(0), math.nan, np.full(2, math.nan), False, a["error"])
        t = np.asarray(a["impacts_t"], float)
        return PeerRun(a["wall"], a["steps"], t[t >= transient], a["t_end"], np.asarray(a["state"]), True, "")

    def close(self) -> None:
        if getattr(self, "proc", None) is not None and self.proc.poll() is None:
            self.proc.stdin.close()
            self.proc.wait(timeout=60)
        shutil.rmtree(self.folder, ignore_errors=True)


def revision_contestants(core: RevisionCore, rtols, transient: float, duration: float) -> list[Contestant]:
    """The revision's core at each rtol (atol = rtol/100), rows of the scene like the core's own."""
    core.run(1e-8, 1e-10, 0.0, 1.0)  # compiles the revision's core before any timing
    return [
        Contestant(
            core.label,
            "scene",
            rtol,
            rtol * 1e-2,
            run=lambda r=rtol: core.run(r, r * 1e-2, transient, duration),
            short=lambda r=rtol: core.run(r, r * 1e-2, 0.0, ERR_HORIZON),
        )
        for rtol in rtols
    ]


def same_impacts(core: RevisionCore, this_run, rtol: float, transient: float, duration: float) -> bool:
    """Are the impact times of the revision's core and of `this_run(rtol, atol, transient,
    duration)` (this core's PeerRun) bit for bit the same (one untimed run each)?"""
    old = core.run(rtol, rtol * 1e-2, transient, duration).impacts_t
    return bool(np.array_equal(old, this_run(rtol, rtol * 1e-2, transient, duration).impacts_t))


def revision_lines(rows: list[dict], this: str) -> list[str]:
    """Markdown: per revision row (solver "<this> at <commit>") and rtol, this core's median wall
    time over the revision's and whether their impacts are the same bit for bit; [] without one."""
    lines = []
    for old in (r for r in rows if r["solver"].startswith(f"{this} at ")):
        new = next((r for r in rows if r["solver"] == this and r["rtol"] == old["rtol"]), None)
        if new is not None:
            lines.append(
                f"| {old['solver']} | {old['rtol']:.0e} | {new['wall_time']:.4f} | {old['wall_time']:.4f} | "
                f"{new['wall_time'] / old['wall_time']:.3f} | {'yes' if old.get('bit_for_bit') else 'no'} |"
            )
    if not lines:
        return []
    head = f"| revision | rtol | {this}, median (s) | revision, median (s) | this / revision | impacts bit for bit |"
    return [head, "|---|---|---|---|---|---|", *lines]
