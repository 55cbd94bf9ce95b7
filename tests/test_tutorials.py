"""The tutorials of the documentation run as written: every ``sh`` and ``python`` block of each
page in docs/tutorials/, in order, in a fresh copy of the repository (the workflow writes its
results/ there). A block that fails fails the test with its output; the python blocks of a page
share one namespace, as a reader runs them."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
TUTORIALS = sorted((REPO / "docs" / "tutorials").glob("*.md"))
BLOCK = re.compile(r"^```(sh|python)\n(.*?)^```", re.M | re.S)
SKIP = shutil.ignore_patterns(".git", ".venv", "results", "site", ".snakemake", "__pycache__", ".pytest_cache")


def blocks(page: Path) -> list[tuple[str, str]]:
    """(language, code) of every sh and python block of a page, in order."""
    return BLOCK.findall(page.read_text(encoding="utf-8"))


def test_every_tutorial_has_code():
    assert len(TUTORIALS) >= 3
    for page in TUTORIALS:
        assert blocks(page), f"{page.name} has no sh or python block"


#: The two longest tutorials (about 30 s each) run with the slow tests; the others by default.
LONG = {"rig-record", "change-parameter"}


@pytest.mark.parametrize(
    "page",
    [pytest.param(p, marks=pytest.mark.slow) if p.stem in LONG else p for p in TUTORIALS],
    ids=[p.stem for p in TUTORIALS],
)
def test_tutorial_runs_as_written(page, tmp_path):
    work = tmp_path / "repo"
    shutil.copytree(REPO, work, ignore=SKIP)
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}", MPLBACKEND="Agg")
    namespace: dict = {}
    cwd = os.getcwd()
    os.chdir(work)
    try:
        for i, (lang, code) in enumerate(blocks(page)):
            if lang == "sh":
                r = subprocess.run(["bash", "-euo", "pipefail", "-c", code], env=env, capture_output=True, text=True)
                assert r.returncode == 0, (
                    f"{page.name} block {i + 1} failed:\n{code}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
                )
            else:
                exec(compile(code, f"{page.name} block {i + 1}", "exec"), namespace)
    finally:
        os.chdir(cwd)
