"""The laws study (target laws_study, config/laws.yaml): model BC, Hertz and Flores (its e matched
to model BC's dissipation) through Fig 2's and Fig 3b's sweeps, drawn over each other.

What it guards: the target resolves to what the study needs and nothing of the paper's (one
matched-e job, one sweep per law and direction, one reading per law, the figures), under
results/laws/; and on config/tiny.yaml it builds: the table's Flores dissipates what model BC
does, each law's model file reaches its own sweeps only, both figures are drawn. The dry run is
in the default run; the tiny build (about 40 s of a worker) runs with the slow tests.
"""

import re
import subprocess
import sys
from pathlib import Path

import h5py
import pytest

from impactosc.io.files import read_csv
from impactosc.model.model_file import read_model_file

REPO = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
CONFIG, TINY, LAWS = (str(REPO / "config" / name) for name in ("config.yaml", "tiny.yaml", "laws.yaml"))


def _snakemake(work, *args):
    run = subprocess.run(
        [*SNAKEMAKE, "laws_study", "-d", str(work), "-j2", "--quiet", "rules", *args],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert run.returncode == 0, f"workflow failed:\n{run.stdout[-4000:]}\n{run.stderr[-4000:]}"
    return run.stdout + run.stderr


def test_the_laws_study_resolves_to_its_own_jobs(tmp_path):
    out = _snakemake(tmp_path, "-n", "--configfile", CONFIG, LAWS)
    jobs = dict(re.findall(r"^(\w+)\s+(\d+)$", out.split("Job stats:")[1], re.M))
    # three laws, two sweeps each, one job per sweep (config/laws.yaml: chunks 1, no coarse pass)
    assert jobs == {
        "numba_cache": "1",
        "laws_models": "1",
        "laws_chunk": "6",
        "laws_merge": "6",
        "laws_tables": "3",
        "laws_figures": "1",
        "laws_study": "1",
        "total": "19",
    }, out[-3000:]


@pytest.mark.slow
def test_the_laws_study_builds_on_tiny_settings(tmp_path):
    _snakemake(tmp_path, "--configfile", CONFIG, TINY, LAWS)
    study = tmp_path / "results" / "laws"
    assert sorted(p.name for p in (tmp_path / "results").iterdir()) == ["laws"]
    rows = {r["law"]: r for r in read_csv(study / "tables" / "laws" / "matched_e.csv")}
    assert list(rows) == ["bc", "hertz", "flores"]
    # the matched e delivers model BC's e_eff (1e-8: the root finder's tolerance, test_contact_laws)
    assert abs(float(rows["flores"]["e_eff"]) - float(rows["bc"]["e_eff"])) < 1e-8
    assert abs(float(rows["hertz"]["e_eff"]) - 1.0) < 1e-9 and rows["hertz"]["e"] == ""
    e = float(rows["flores"]["e"])
    assert read_model_file(study / "models" / "laws" / "flores.yaml").params.e == pytest.approx(e, rel=1e-9)
    for law in rows:
        for sweep in ("increasing", "decreasing"):
            with h5py.File(study / "runs" / "laws" / law / f"{sweep}.h5") as f:
                assert f.attrs["param_law"] == law
                if law == "flores":
                    assert f.attrs["param_e"] == pytest.approx(e, rel=1e-9)
    for name in ("fig02", "fig03b"):
        for ext in ("png", "pdf"):
            path = study / "figures" / "laws" / f"{name}_laws.{ext}"
            assert path.is_file() and path.stat().st_size > 1000, path
