"""A build killed part-way resumes with the same `make`, and a live build's lock is never taken.

What it guards: after SIGKILL (no clean-up by Snakemake) the lock and the incomplete-job markers
stay in .snakemake; `make` removes the lock only when no Snakemake process works in the
directory (workflow/unlock_stale.py) and reruns incomplete jobs (--rerun-incomplete), so the
second `make` finishes the build, with the results of a build that was never interrupted.

The build is a few jobs of config/tiny.yaml in a temporary copy of the workflow (the package
comes from the installed environment): two scenes and two jobs of the noise study. Their
results are deterministic, so they are compared exactly: a scene's events are the numba core's
integration of a fixed model from a fixed state (no randomness, one thread), and the noise
study's rows come from a generator seeded by the config (measured.surrogate.seed), so both
repeat bit for bit on one machine. Run files also hold wall times, so their event datasets are
compared, not the files.

The killed build and its reference build (about 45 s of a worker) run with the slow tests; the
lock's two cases, without a build, in the default run.
"""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]
VENV = Path(sys.executable).parent.parent  # the environment running the tests (make's .venv)
UNLOCK = REPO / "workflow" / "unlock_stale.py"
SCENES = [f"results/paper/runs/scenes/{name}.h5" for name in ("period4", "chaos")]
NOISE = [f"results/paper/stats/measured/noise_study/{part}.csv" for part in ("rate2000Hz", "realism")]
TARGETS = SCENES + NOISE
EVENTS = ("impacts/t", "penetrations/h", "poincare/x", "poincare/v")


def workflow_copy(root: Path) -> Path:
    """The workflow's files (no results, no environment) in a directory of their own."""
    work = root / "work"
    work.mkdir()
    for name in ("Makefile", "Snakefile"):
        shutil.copy2(REPO / name, work / name)
    for name in ("config", "workflow"):
        shutil.copytree(REPO / name, work / name, ignore=shutil.ignore_patterns("__pycache__"))
    return work


def make(work: Path, **popen) -> list[str]:
    """The command line of `make` in work: the default goal, on the tiny config and TARGETS,
    with this environment (taken as installed: -o, so nothing is reinstalled)."""
    args = " ".join([*TARGETS, "--configfile config/config.yaml config/tiny.yaml"])
    return ["make", "-C", str(work), f"VENV={VENV}", "-o", f"{VENV}/.installed", f"SNAKEMAKE_ARGS={args}"]


def run_make(work: Path) -> subprocess.CompletedProcess:
    return subprocess.run(make(work), capture_output=True, text=True, timeout=300)


def events(path: Path) -> dict:
    with h5py.File(path) as f:
        return {name: f[name][()] for name in EVENTS if name in f}


def incomplete_jobs(work: Path) -> list[Path]:
    """Snakemake's markers of the outputs of jobs that have started and not finished."""
    folder = work / ".snakemake" / "incomplete"
    return [p for p in folder.iterdir() if p.name != "migration_underway"] if folder.is_dir() else []


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    work = workflow_copy(tmp_path_factory.mktemp("uninterrupted"))
    run = run_make(work)
    assert run.returncode == 0, f"uninterrupted build failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
    return work


@pytest.mark.slow
def test_killed_build_resumes_with_the_same_results(reference, tmp_path):
    work = workflow_copy(tmp_path)
    build = subprocess.Popen(make(work), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, process_group=0)
    try:
        # mid-way: some results written, others not, and a job running
        deadline = time.monotonic() + 120
        while True:
            done = [t for t in TARGETS if (work / t).is_file()]
            if done and len(done) < len(TARGETS) and incomplete_jobs(work):
                break
            assert build.poll() is None, "the build ended before it could be killed mid-way"
            assert time.monotonic() < deadline, "no result was written within 120 s"
            time.sleep(0.1)
        # while Snakemake runs, its lock is kept
        check = subprocess.run([sys.executable, UNLOCK, str(work)], capture_output=True, text=True, timeout=30)
        assert "kept the Snakemake lock" in check.stderr, check.stderr
        assert list((work / ".snakemake" / "locks").glob("*.lock"))
    finally:
        os.killpg(build.pid, signal.SIGKILL)  # make, Snakemake and its jobs: nothing cleans up
        build.wait(timeout=30)
    assert list((work / ".snakemake" / "locks").glob("*.lock")), "the killed build left no lock"
    missing = [t for t in TARGETS if not (work / t).is_file()]
    assert missing, "every result was there before the kill"

    again = run_make(work)
    assert again.returncode == 0, f"the second make failed:\n{again.stdout[-3000:]}\n{again.stderr[-3000:]}"
    assert "removed the lock an interrupted build left" in again.stderr
    for target in SCENES:
        got, want = events(work / target), events(reference / target)
        assert got.keys() == want.keys() and got["impacts/t"].size > 0, target
        for name in want:
            assert np.array_equal(got[name], want[name]), f"{target}: {name} differs from the uninterrupted build"
    for target in NOISE:
        assert (work / target).read_text() == (reference / target).read_text(), target


def sleeper(cwd: Path, *args: str) -> subprocess.Popen:
    """A process that stays 60 s with args on its command line and cwd as its directory."""
    return subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)", *args], cwd=cwd)


def unlock(directory: Path) -> str:
    run = subprocess.run([sys.executable, UNLOCK, str(directory)], capture_output=True, text=True, timeout=30)
    assert run.returncode == 0, run.stderr
    return run.stderr


def stale_lock(directory: Path) -> Path:
    locks = directory / ".snakemake" / "locks"
    locks.mkdir(parents=True)
    (locks / "0.input.lock").write_text("results/a.h5\n")
    return locks


def test_lock_kept_while_a_snakemake_process_works_there(tmp_path):
    here, elsewhere = tmp_path / "here", tmp_path / "elsewhere"
    elsewhere.mkdir()
    locks = stale_lock(here)
    # in the directory, or naming it with --directory from elsewhere: the lock is kept
    for proc in (sleeper(here, "snakemake", "-j2"), sleeper(elsewhere, "snakemake", "--directory", str(here))):
        try:
            message = unlock(here)
            assert "kept the Snakemake lock" in message and f"pid {proc.pid}" in message, message
            assert (locks / "0.input.lock").is_file()
        finally:
            proc.kill()
            proc.wait()


def test_stale_lock_removed_when_no_snakemake_works_there(tmp_path):
    here, elsewhere = tmp_path / "here", tmp_path / "elsewhere"
    elsewhere.mkdir()
    locks = stale_lock(here)
    others = [sleeper(here, "python-job"), sleeper(elsewhere, "snakemake", "-j2")]  # not Snakemake / not here
    try:
        assert "removed the lock an interrupted build left" in unlock(here)
        assert not locks.exists()
        assert unlock(here) == ""  # no lock: nothing to say
    finally:
        for proc in others:
            proc.kill()
            proc.wait()
