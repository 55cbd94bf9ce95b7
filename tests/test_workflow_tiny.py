"""The workflow end to end: every rule of `snakemake everything` (the three tiers: the paper, beyond
it, the benchmarks) on config/tiny.yaml (short scenes, a few sweep points, a 2 x 2 map and a short
curve over it, a short surrogate, tiny benchmarks) in a temporary directory.

What it guards: the DAG is complete (every rule runs, no input is missing, every script
writes what its rule declares), and a finished build is up to date (a second dry run has
nothing to do). The numbers of the tiny build are not checked here: the regression tests
check the real scenes.
"""

import subprocess
import sys
from pathlib import Path

import h5py
import pytest

from impactosc.io.files import read_csv

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
CONFIGS = ["--configfile", str(REPO / "config" / "config.yaml"), str(REPO / "config" / "tiny.yaml")]
TARGETS = ["everything"]
TIERS = ("paper", "beyond", "benchmarks")

PAPER_FIGURES = [f"fig{nn:02d}" for nn in range(1, 12)] + ["fig03a", "fig03b"]
SUPPLEMENTARY = [
    "periodic/grazing",
    "bifurcation/bifurcation_overlay",
    "bifurcation/map2d",
    "two_parameter/map2d_curves",
    "basins/basins",
    "attractors/attractors",
    "orbits/fig02_orbits",
    "orbits/fig03b_orbits",
    "lyapunov/lyapunov_chaos",
    "lyapunov/fig02_lyapunov",
    "lyapunov/fig03b_lyapunov",
    "measured/measured_noise_study",
    "work_precision/work_precision",
]


@pytest.fixture(scope="module")
def tiny_build(tmp_path_factory):
    work = tmp_path_factory.mktemp("tiny")
    run = subprocess.run(
        [*SNAKEMAKE, *TARGETS, "-d", str(work), *CONFIGS, "-j2", "--quiet", "rules"],
        capture_output=True,
        text=True,
        timeout=1200,
    )
    assert run.returncode == 0, f"tiny workflow failed:\n{run.stdout[-4000:]}\n{run.stderr[-4000:]}"
    return work


def test_every_figure_is_drawn(tiny_build):
    figures = tiny_build / "results" / "paper" / "figures"
    for name in PAPER_FIGURES + SUPPLEMENTARY:
        for ext in ("png", "pdf"):
            path = figures / f"{name}.{ext}"
            assert path.is_file() and path.stat().st_size > 1000, f"{path} missing or empty"


def test_paper_table_and_benchmarks_are_written(tiny_build):
    tables = tiny_build / "results" / "paper" / "tables"
    md = (tables / "paper_vs_replication.md").read_text()
    assert md.count("\n|") > 20  # one row per number of the paper
    assert (tables / "benchmark" / "benchmark_core.md").read_text().startswith("# Core speed")
    assert (tables / "work_precision" / "hard_cases.csv").stat().st_size > 0
    assert (tables / "benchmark" / "benchmarks_report.md").read_text().startswith("# Benchmarks")


def test_build_time_tables_count_every_job(tiny_build):
    tables = tiny_build / "results" / "paper" / "tables"
    counted = 0
    for tier in TIERS:
        groups = read_csv(tables / f"build_times_{tier}.csv", numbers=True)
        total = groups[-1]
        assert total["group"] == "total" and total["wall_s"] == pytest.approx(sum(g["wall_s"] for g in groups[:-1]))
        assert "| **total** |" in (tables / f"build_times_{tier}.md").read_text()
        counted += total["jobs"]
    # every job of the three tiers wrote a benchmark file and is counted in exactly one tier
    benchmarks = list((tiny_build / "results" / "paper" / "benchmarks").rglob("*.tsv"))
    assert counted == len(benchmarks) > 80


def test_run_files_carry_provenance(tiny_build):
    with h5py.File(tiny_build / "results" / "paper" / "runs" / "scenes" / "chaos.h5") as f:
        assert f.attrs["format_version"] and f.attrs["numba_version"] and f.attrs["git_commit"]
        for name in ("impacts/t", "impacts/v", "poincare/x"):
            assert f[name].attrs["units"] in ("s", "m", "m/s")


def test_finished_build_is_up_to_date(tiny_build):
    dry = subprocess.run(
        [*SNAKEMAKE, "-d", str(tiny_build), *CONFIGS, "-n", *TARGETS], capture_output=True, text=True, timeout=300
    )
    assert dry.returncode == 0, dry.stderr[-3000:]
    assert "Nothing to be done" in dry.stdout + dry.stderr, (dry.stdout + dry.stderr)[-3000:]


def test_report_has_front_page_and_paper_table(tiny_build):
    report = tiny_build / "report.html"
    run = subprocess.run(
        [*SNAKEMAKE, "-d", str(tiny_build), *CONFIGS, "--report", str(report)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    page = report.read_text()
    assert "How the results are made" in page  # the front page, workflow/report/workflow.rst
    assert "paper_vs_replication.html" in page  # the table as a report item
