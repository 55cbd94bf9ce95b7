"""The three tiers of the workflow, from Snakemake's own dry runs of the paper's config: the paper
(rule all) schedules no job of beyond or the benchmarks, the paper's table waits for no job that
times, and every job belongs to one tier only.

How: a dry run lists every job it would run with its benchmark file; each tier's build-time job
(rule build_times) takes the benchmark files of exactly the jobs its rules files put in that tier.
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [
    sys.executable,
    "-m",
    "snakemake",
    "-s",
    str(REPO / "Snakefile"),
    "--configfile",
    str(REPO / "config" / "config.yaml"),
]
TIERS = {"paper": "all", "beyond": "beyond", "benchmarks": "benchmarks"}


def dry_run(tmp_path, *targets) -> list[dict]:
    """The jobs of a dry run of ``targets`` in an empty working directory: rule, input, benchmark."""
    run = subprocess.run(
        [*SNAKEMAKE, "-d", str(tmp_path), "-n", *targets],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    jobs = []
    for block in re.split(r"^rule ", run.stdout, flags=re.MULTILINE)[1:]:
        fields = dict(re.findall(r"^    (\w+): (.*)$", block, flags=re.MULTILINE))
        jobs.append(
            {
                "rule": block.split(":", 1)[0],
                "input": fields.get("input", "").split(", "),
                "output": fields.get("output", ""),
                "benchmark": fields.get("benchmark"),
            }
        )
    return jobs


def tier_of(jobs: list[dict]) -> dict:
    """Each tier's benchmark files, read from the inputs of its build-time job."""
    tiers = {}
    for job in jobs:
        if job["rule"] == "build_times":
            tier = re.search(r"build_times_(\w+)\.csv", job["output"])[1]
            tiers[tier] = set(job["input"])
    return tiers


@pytest.fixture(scope="module")
def everything(tmp_path_factory):
    return dry_run(tmp_path_factory.mktemp("everything"), "everything")


def test_every_job_is_in_one_tier(everything):
    tiers = tier_of(everything)
    assert set(tiers) == set(TIERS)
    for a in TIERS:
        for b in TIERS:
            if a < b:
                assert not tiers[a] & tiers[b], f"jobs in both {a} and {b}: {sorted(tiers[a] & tiers[b])[:5]}"
    scheduled = {job["benchmark"] for job in everything if job["benchmark"]}
    assert scheduled == set().union(*tiers.values())


def test_the_paper_schedules_nothing_beyond_it(everything, tmp_path):
    paper = dry_run(tmp_path, "all")
    tiers = tier_of(everything)
    scheduled = {job["benchmark"] for job in paper if job["benchmark"]}
    assert scheduled == tiers["paper"]
    assert {job["rule"] for job in paper} >= {"paper_vs_replication", "fig02", "fig09", "fig03"}


def test_the_paper_table_waits_for_no_timing(everything, tmp_path):
    table = dry_run(tmp_path, "paper_vs_replication")
    timing = tier_of(everything)["benchmarks"]
    scheduled = {job["benchmark"] for job in table if job["benchmark"]}
    assert scheduled and not scheduled & timing, sorted(scheduled & timing)
