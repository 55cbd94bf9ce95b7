"""The workflow takes its model from a model file named in the config: a dry run of fig02 on
config/tiny.yaml plans the bifurcation sweeps with the file's parameters, and Snakemake's params
trigger reruns every job whose model changed.

How, without running a simulation: the outputs of fig02's jobs and their benchmark files (which
Snakemake counts among a job's outputs) are created empty and marked done with model BC (--touch
records each job's params), so a dry run with the model file shows the jobs it would rerun and why. On the command line the file is given as --config 'model={file: ...}'
(Snakemake 9 refuses a dotted key such as model.file=... in --config).
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from test_config import REFUSED_MODELS, alias_bomb  # tests/ is on sys.path (pytest's prepend import mode)

from impactosc.model.model_file import write_model_file
from impactosc.model.parameters import ModelParams

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
CONFIGS = ["--configfile", str(REPO / "config" / "config.yaml"), str(REPO / "config" / "tiny.yaml")]


def _snakemake(work, *args):
    run = subprocess.run([*SNAKEMAKE, "-d", str(work), *args], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return run.stdout + run.stderr


def test_model_file_reruns_the_sweeps_with_its_parameters(tmp_path):
    rig = write_model_file(tmp_path / "rig.yaml", ModelParams(k=1500.0), name="test rig")
    summary = _snakemake(tmp_path, "fig02", "--summary", *CONFIGS)
    for line in summary.splitlines()[1:]:
        if line.startswith("results/"):
            out = tmp_path / line.split("\t")[0]
            out.parent.mkdir(parents=True, exist_ok=True)
            out.touch()
    plan = _snakemake(tmp_path, "fig02", "-n", "--forceall", *CONFIGS)
    for path in re.findall(r"^    benchmark: (\S+)$", plan, re.MULTILINE):
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).touch()
    _snakemake(tmp_path, "fig02", "--touch", "--forceall", *CONFIGS)  # done with model BC
    assert "Nothing to be done" in _snakemake(tmp_path, "fig02", "-n", *CONFIGS)

    dry = _snakemake(tmp_path, "fig02", "-n", *CONFIGS, "--config", f"model={{file: {rig}}}")
    jobs = {}  # rule -> reasons of its jobs
    for rule, reason in re.findall(r"^rule (\w+):\n(?:    .*\n)*?    reason: (.*)$", dry, re.MULTILINE):
        jobs.setdefault(rule, []).append(reason)
    for rule in ("bifurcation_coarse", "bifurcation_chunk", "fig02"):
        assert rule in jobs, (rule, sorted(jobs))
    for reason in jobs["bifurcation_coarse"]:  # both sweeps, with the file's k
        assert "Params have changed" in reason and "now: {'m': 8.735, 'm0e': 0.01805, 'k': 1500.0" in reason
    assert len(jobs["bifurcation_coarse"]) == 2 and len(jobs["bifurcation_chunk"]) == 4


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        *[(yaml.safe_dump({"model": model}), expected) for model, expected in REFUSED_MODELS],
        ("\n".join(["bomb:", *alias_bomb(7), "model: {k: *l6}", ""]), "its aliases (*name) add 11,434,267 values"),
    ],
    ids=["flores-e", "kelvin-voigt-n1", "aliases"],
)
def test_a_dry_run_refuses_a_config_every_job_would_refuse(tmp_path, text, expected):
    bad = tmp_path / "bad.yaml"
    bad.write_text(text)
    run = subprocess.run(
        [*SNAKEMAKE, "-d", str(tmp_path), "fig02", "-n", *CONFIGS, str(bad)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    out = run.stdout + run.stderr
    assert run.returncode != 0 and "invalid configuration:\n  " in out and expected in out, out[-3000:]
    assert len(out) < 5000 and not (tmp_path / "results").exists()
