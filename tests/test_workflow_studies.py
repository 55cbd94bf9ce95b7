"""Results per study: a second study (config study, with a model file of its own) builds Fig 2 and
Fig 3b under results/<study>/ beside the paper's, on config/tiny.yaml in a temporary directory,
and compare_studies draws the two studies over each other.

What it guards: every path of the workflow is under results/<study>/ (the second study's build
neither rewrites nor touches a file of results/paper/: same bytes, same mtimes), the study's
model reaches its own sweeps only, and the comparison reads the other study's files, stopping
with a message naming the missing ones when that study is not built.

The builds of the two studies (about 60 s of a worker) run with the slow tests: the default run
builds the workflow end to end once, in tests/test_workflow_tiny.py. The refusal of an unsafe
study name is a dry run, in the default run.
"""

import hashlib
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from impactosc.io.files import read_json
from impactosc.model.model_file import write_model_file
from impactosc.model.parameters import ModelParams

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
CONFIGS = ["--configfile", str(REPO / "config" / "config.yaml"), str(REPO / "config" / "tiny.yaml")]
# the paper's Fig 2 and the decreasing sweep behind its Fig 3b (all that compare_studies reads of it)
PAPER_TARGETS = ["fig02", "results/paper/runs/bifurcation/decreasing.h5"]


def _snakemake(work, targets, *args, check=True):
    run = subprocess.run(
        [*SNAKEMAKE, *targets, "-d", str(work), *CONFIGS, "-j2", "--quiet", "rules", *args],
        capture_output=True,
        text=True,
        timeout=900,
    )
    if check:
        assert run.returncode == 0, f"workflow failed:\n{run.stdout[-4000:]}\n{run.stderr[-4000:]}"
    return run


def _state(folder):
    """{relative path: (sha256, mtime_ns)} of every file under folder."""
    return {
        str(p.relative_to(folder)): (hashlib.sha256(p.read_bytes()).hexdigest(), p.stat().st_mtime_ns)
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="module")
def two_studies(tmp_path_factory):
    """The paper's study, then Fig 2 and the predictions of study myrig (c = 6.9 N s/m from a model
    file with a covariance, as identification writes one: close enough to model BC that the tiny
    branch still brackets its grazing, which Fig 2's reading needs); the paper's files as they
    were before myrig was built."""
    work = tmp_path_factory.mktemp("studies")
    _snakemake(work, PAPER_TARGETS)
    paper = _state(work / "results" / "paper")
    p = ModelParams(c=6.9)
    se = np.array([0.005 * p.k / p.m, 0.01 * p.c / p.m, 1e-6])
    covariance = (["k/m", "c/m", "xI"], ["1/s^2", "1/s", "m"], np.diag(se**2))
    rig = write_model_file(work / "rig.yaml", p, covariance=covariance, name="test rig")
    _snakemake(work, ["fig02", "predictions"], "--config", "study=myrig", f"model_file={rig}")
    return work, paper


@pytest.mark.slow
def test_second_study_leaves_the_paper_study_untouched(two_studies):
    work, before = two_studies
    assert len(before) > 20 and "figures/fig02.png" in before and ".numba_cache_ready" in before
    assert _state(work / "results" / "paper") == before
    assert sorted(p.name for p in (work / "results").iterdir()) == ["myrig", "paper"]
    figure = work / "results" / "myrig" / "figures" / "fig02.png"
    assert figure.is_file() and figure.stat().st_size > 1000
    assert (work / "results" / "myrig" / "logs" / "bifurcation" / "fig02.log").is_file()
    # the config's {study} path: Fig 2's surrogate panel of myrig's own model
    assert (work / "results" / "myrig" / "runs" / "measured" / "fig02_experimental.h5").is_file()
    # each study's sweeps were run with its own model
    for study, c in (("paper", 6.6511), ("myrig", 6.9)):
        with h5py.File(work / "results" / study / "runs" / "bifurcation" / "increasing.h5") as f:
            assert f.attrs["param_c"] == c


@pytest.mark.slow
def test_a_model_with_a_covariance_gets_its_error_bars(two_studies):
    """myrig's model states a covariance: Fig 2 took its segments' predictions (located points
    with standard errors, bands), and the predictions' table lists them; the paper's model BC,
    stated exactly, has none."""
    work, _before = two_studies
    found = read_json(work / "results" / "myrig" / "runs" / "predictions" / "period1.json")
    doublings = [q for q in found["points"] if q["kind"] == "period_doubling"]
    assert doublings and all(q["se"] > 0 for q in doublings), found["points"]
    se_x = [v for orbit in found["band"]["se_poincare_x"] for v in orbit if v is not None]
    assert se_x and all(v >= 0 for v in se_x) and max(se_x) > 0
    table = (work / "results" / "myrig" / "tables" / "predictions" / "predicted_points.md").read_text()
    assert "| period1 | period doubling | 37.2" in table
    assert not (work / "results" / "paper" / "runs" / "predictions").exists()
    # the paper's study asked for predictions: the rule says what it needs
    run = _snakemake(work, ["predictions"], "-n", check=False)
    assert run.returncode != 0 and "predictions need a model file with a covariance" in run.stdout + run.stderr


@pytest.mark.slow
def test_compare_studies_overlays_the_built_study(two_studies):
    work, before = two_studies
    rig = work / "rig.yaml"
    compare = ["--config", "study=myrig", f"model_file={rig}", "compare={study: paper}"]
    _snakemake(work, ["compare_studies"], *compare)  # builds myrig's decreasing sweep, reads the paper's
    for name in ("fig02", "fig03b"):
        for ext in ("png", "pdf"):
            path = work / "results" / "myrig" / "figures" / "compare" / f"{name}_vs_paper.{ext}"
            assert path.is_file() and path.stat().st_size > 1000, path
    assert _state(work / "results" / "paper") == before

    # a study that was never built: the rule stops and names the files it lacks
    run = _snakemake(work, ["compare_studies"], "-n", "--config", "study=myrig", "compare={study: nobody}", check=False)
    out = run.stdout + run.stderr
    assert run.returncode != 0
    assert "study 'nobody' (config compare.study) is not built" in out, out[-3000:]
    assert "results/nobody/runs/bifurcation/increasing.h5" in out
    # no study named: the rule says which key to set
    run = _snakemake(work, ["compare_studies"], "-n", "--config", "study=myrig", check=False)
    assert run.returncode != 0 and "config compare.study names no study" in run.stdout + run.stderr


def test_unsafe_study_name_is_refused(tmp_path):
    run = _snakemake(tmp_path, ["fig02"], "-n", "--config", "study=../elsewhere", check=False)
    assert run.returncode != 0
    assert "study: '../elsewhere' is not a safe directory name" in run.stdout + run.stderr
    assert not (tmp_path / "results").exists()
