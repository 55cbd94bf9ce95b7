"""Where the time of a workflow build goes: job time per group of rules, from Snakemake's
benchmark files.

Why: the share of each group changes with every change to the workflow, so the build writes
its own table (rule build_times) instead of hand-measured prose going stale. Each job's
benchmark file is ``results/<study>/benchmarks/<group>/<rule>[_<wildcards>].tsv`` (one row per run of
the job): ``s``, the job's wall time, and ``cpu_time``, the user + system time of the job's
processes at Snakemake's last sample of them (once a second for the first 30 s, then every
30 s: a lower bound, short by up to that interval; ``NA`` when the job ended before a sample).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

__all__ = ["group_table", "largest_jobs", "build_times_markdown", "read_benchmark"]


def _number(text: str) -> float:
    """A cell of a benchmark file as a float; NA (no sample taken) as NaN."""
    return math.nan if text.strip() in ("", "NA", "-") else float(text)


def read_benchmark(path) -> dict:
    """One job: group (the benchmark file's folder), job (its name: rule and wildcards), wall_s
    and cpu_s summed over the file's rows (a job repeated with repeat() has one row per run),
    max_rss_mb (the largest). cpu_s is NaN when no row has a sample."""
    path = Path(path)
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f, delimiter="\t"))
    if not rows or "s" not in rows[0]:
        raise ValueError(f"{path}: not a Snakemake benchmark file (a header with column s, then a row per run)")
    cpu = [_number(r.get("cpu_time", "NA")) for r in rows]
    rss = [_number(r.get("max_rss", "NA")) for r in rows]
    return {
        "group": path.parent.name,
        "job": path.stem,
        "wall_s": sum(_number(r["s"]) for r in rows),
        "cpu_s": math.nan if all(math.isnan(c) for c in cpu) else sum(c for c in cpu if not math.isnan(c)),
        "max_rss_mb": max((r for r in rss if not math.isnan(r)), default=math.nan),
    }


def group_table(jobs: list[dict]) -> list[dict]:
    """One row per group, the longest first, then a ``total`` row: the number of jobs, their
    wall and CPU time (s; CPU over the jobs with a sample), the share of the total wall time (%)
    and the group's longest job."""
    total = sum(j["wall_s"] for j in jobs)
    rows = []
    for group in sorted({j["group"] for j in jobs}):
        members = [j for j in jobs if j["group"] == group]
        rows.append(_summary(group, members, total))
    rows.sort(key=lambda r: -r["wall_s"])
    return [*rows, _summary("total", jobs, total)] if jobs else []


def _summary(name: str, jobs: list[dict], total: float) -> dict:
    """The table's row of a set of jobs (a group, or all of them)."""
    cpu = [j["cpu_s"] for j in jobs if not math.isnan(j["cpu_s"])]
    wall = sum(j["wall_s"] for j in jobs)
    longest = max(jobs, key=lambda j: j["wall_s"])
    return {
        "group": name,
        "jobs": len(jobs),
        "wall_s": round(wall, 2),
        "cpu_s": round(sum(cpu), 2) if cpu else math.nan,
        "share_pct": round(100 * wall / total, 1) if total > 0 else math.nan,
        "longest_job": longest["job"],
        "longest_wall_s": round(longest["wall_s"], 2),
    }


def largest_jobs(jobs: list[dict], n: int) -> list[dict]:
    """The n jobs with the longest wall time, longest first."""
    return sorted(jobs, key=lambda j: -j["wall_s"])[:n]


def _cell(v) -> str:
    """A number of the Markdown tables: one decimal, or a dash where nothing was sampled."""
    if isinstance(v, float):
        return "-" if math.isnan(v) else f"{v:.1f}"
    return str(v)


def build_times_markdown(groups: list[dict], largest: list[dict], target: str = "all", command: str = "make") -> str:
    """The Markdown page of one tier (its ``target`` rule, built by ``command``): the table per
    group with the total, then the largest jobs."""
    total = groups[-1] if groups else {"jobs": 0, "wall_s": 0.0, "cpu_s": math.nan}
    lines = [
        "# Build time",
        "",
        f"Job time of the build of rule `{target}` (`{command}`): {total['jobs']} jobs, "
        f"{_cell(total['wall_s'])} s of wall time summed over the jobs ({_cell(total['cpu_s'])} s of CPU time).",
        "Read from each job's Snakemake benchmark file (`results/<study>/benchmarks/<group>/<job>.tsv`) by the",
        "rule `build_times`. Jobs run side by side, so the build's own duration is shorter than the sum",
        "(at least the sum divided by the number of cores). CPU time is Snakemake's last sample of the job's",
        "processes (once a second, every 30 s after the first 30 s): a lower bound; - where none was taken.",
        "",
        "| group | jobs | wall s | CPU s | share of wall % | longest job | its wall s |",
        "|---|---:|---:|---:|---:|---|---:|",
    ]
    for r in groups:
        name = f"**{r['group']}**" if r["group"] == "total" else r["group"]
        lines.append(
            f"| {name} | {r['jobs']} | {_cell(r['wall_s'])} | {_cell(r['cpu_s'])} | {_cell(r['share_pct'])} "
            f"| {r['longest_job']} | {_cell(r['longest_wall_s'])} |"
        )
    lines += ["", f"## The {len(largest)} longest jobs", "", "| job | group | wall s | CPU s | max RSS MB |"]
    lines.append("|---|---|---:|---:|---:|")
    lines += [
        f"| {j['job']} | {j['group']} | {_cell(j['wall_s'])} | {_cell(j['cpu_s'])} | {_cell(j['max_rss_mb'])} |"
        for j in largest
    ]
    return "\n".join(lines) + "\n"
