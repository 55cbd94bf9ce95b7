"""The workflow on the oldest and the newest Snakemake release of pyproject's range
(make check-snakemake): for each, in a throw-away virtual environment holding that Snakemake and
the package with the extras the jobs import (explore: the explorer's latency; peers: the
benchmarks' compiled peers, which `make` installs too), dry runs of the
targets all, beyond and benchmarks on the paper's config and a build of every target
(everything) on config/tiny.yaml, as tests/test_workflow_tiny.py builds it.

The oldest release is the lower bound of pyproject's `snakemake>=X` (installed as ==X); the
newest is what the resolver picks for the range. Everything else is resolved afresh from the
package index (not requirements.lock), as `pip install .` would. Needs the index (PyPI) and uv.

Usage: python .ci/check_snakemake.py UV [--snakemake VERSION ...] [--keep]
    --snakemake VERSION   check these releases instead (e.g. to find the oldest that works)
"""

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
DRY_TARGETS = ["all", "beyond", "benchmarks"]
PAPER = ["--configfile", str(REPO / "config" / "config.yaml")]
TINY = [*PAPER, str(REPO / "config" / "tiny.yaml")]


def snakemake_range() -> str:
    """pyproject's requirement on Snakemake, e.g. '>=8.0'."""
    deps = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["dependencies"]
    found = [d for d in deps if re.match(r"snakemake\s*[<>=!~]", d)]
    if len(found) != 1:
        sys.exit(f"pyproject.toml: expected one requirement on snakemake, found {found}")
    return found[0].removeprefix("snakemake").strip()


def oldest(spec: str) -> str:
    match = re.search(r">=\s*([0-9][0-9.]*)", spec)
    if not match:
        sys.exit(f"pyproject.toml: snakemake{spec} has no lower bound (>=X)")
    return match[1]


def run(cmd, log, **kwargs):
    """Run ``cmd``, its output appended to ``log``; True when it succeeds."""
    with open(log, "a") as out:
        out.write(f"\n$ {' '.join(map(str, cmd))}\n")
        out.flush()
        return subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, **kwargs).returncode == 0


def check(uv: str, requirement: str, root: Path) -> dict:
    """Install ``requirement`` (snakemake==X or snakemake<range>) with the package into a fresh venv
    under ``root``, then dry-run the tiers and build the tiny config. The steps' results."""
    venv, log = root / "venv", root / "check.log"
    python, snakemake = venv / "bin" / "python", venv / "bin" / "snakemake"
    result = {"requirement": requirement, "version": None, "log": str(log), "steps": {}}
    start = time.monotonic()
    install = [uv, "pip", "install", "--quiet", "--compile-bytecode", "--python", python]
    ok = run([uv, "venv", "--quiet", "--no-python-downloads", "--python", sys.executable, venv], log) and run(
        [*install, f"{REPO}[explore,peers]", requirement], log
    )
    result["steps"]["install"] = ok
    if not ok:
        return result
    version = subprocess.run([snakemake, "--version"], capture_output=True, text=True)
    result["version"] = version.stdout.strip()
    base = [snakemake, "-s", REPO / "Snakefile"]
    for target in DRY_TARGETS:
        work = root / f"dry_{target}"
        result["steps"][f"dry run {target}"] = run([*base, target, "-d", work, *PAPER, "-n", "--quiet", "rules"], log)
    work = root / "tiny"
    built = run([*base, "everything", "-d", work, *TINY, "-j2", "--quiet", "rules"], log)
    table = work / "results" / "paper" / "tables" / "paper_vs_replication.md"
    built = built and table.is_file() and table.read_text().count("\n|") > 20
    # a finished build is up to date: a second dry run has nothing to do
    if built:
        again = subprocess.run([*base, "-d", work, *TINY, "-n", "everything"], capture_output=True, text=True)
        built = again.returncode == 0 and "Nothing to be done" in again.stdout + again.stderr
    result["steps"]["tiny build everything"] = built
    result["minutes"] = (time.monotonic() - start) / 60
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("uv", help="the uv executable (make: .tools/uv/bin/uv)")
    parser.add_argument("--snakemake", nargs="+", metavar="VERSION", help="check these releases instead")
    parser.add_argument("--keep", action="store_true", help="keep the environments and builds (path printed)")
    args = parser.parse_args()
    spec = snakemake_range()
    requirements = (
        [f"snakemake=={v}" for v in args.snakemake]
        if args.snakemake
        else [f"snakemake=={oldest(spec)}", f"snakemake{spec}"]
    )
    print(f"pyproject: snakemake{spec}; checking {', '.join(requirements)}", flush=True)
    results = []
    top = Path(tempfile.mkdtemp(prefix="check-snakemake-"))
    try:
        for i, requirement in enumerate(requirements):
            root = top / str(i)
            root.mkdir()
            result = check(args.uv, requirement, root)
            results.append(result)
            failed = [step for step, ok in result["steps"].items() if not ok]
            print(
                f"{requirement}: Snakemake {result['version'] or '(not installed)'}: "
                + ("passes" if not failed else f"FAILS at {', '.join(failed)}")
                + (f" ({result['minutes']:.1f} min)" if "minutes" in result else ""),
                flush=True,
            )
            if failed:
                print(f"  the last lines of {result['log']}:")
                print("    " + "\n    ".join(Path(result["log"]).read_text().splitlines()[-25:]), flush=True)
    finally:
        if args.keep or any(not all(r["steps"].values()) for r in results):
            print(f"kept: {top}")
        else:
            shutil.rmtree(top, ignore_errors=True)
    if any(not all(r["steps"].values()) for r in results):
        sys.exit(1)
    print(f"check-snakemake: the workflow works on {' and '.join(r['version'] for r in results)}")


if __name__ == "__main__":
    main()
