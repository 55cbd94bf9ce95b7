"""The build-time table: Snakemake's benchmark files read and summed per group (that every job of a
tier is counted in its tier's table is tests/test_tiers.py's)."""

import math
from pathlib import Path

import pytest

from impactosc_study.build_times import build_times_markdown, group_table, largest_jobs, read_benchmark

HEADER = "s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"


def benchmark(root: Path, group: str, job: str, *rows: tuple[str, str]) -> Path:
    """A benchmark file as Snakemake writes it: one row (wall s, cpu_time) per run of the job."""
    path = root / group / f"{job}.tsv"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER + "".join(f"{s}\t0:00:00\t100.5\t200\t1\t1\t0\t0\t50\t{cpu}\n" for s, cpu in rows))
    return path


def test_read_benchmark_sums_repeats_and_reads_na_as_unsampled(tmp_path):
    job = read_benchmark(benchmark(tmp_path, "scenes", "simulate_scene_chaos", ("2.5", "2.0"), ("1.5", "NA")))
    assert job == {"group": "scenes", "job": "simulate_scene_chaos", "wall_s": 4.0, "cpu_s": 2.0, "max_rss_mb": 100.5}
    assert math.isnan(read_benchmark(benchmark(tmp_path, "periodic", "fig01", ("0.4", "NA")))["cpu_s"])
    (tmp_path / "empty.tsv").write_text("")
    with pytest.raises(ValueError, match="not a Snakemake benchmark file"):
        read_benchmark(tmp_path / "empty.tsv")


def test_groups_longest_first_with_total_and_largest_jobs(tmp_path):
    jobs = [
        read_benchmark(benchmark(tmp_path, "bifurcation", "bifurcation_chunk_increasing_0", ("30", "29"))),
        read_benchmark(benchmark(tmp_path, "bifurcation", "bifurcation_chunk_increasing_1", ("20", "19"))),
        read_benchmark(benchmark(tmp_path, "periodic", "fig01", ("10", "NA"))),
    ]
    groups = group_table(jobs)
    assert [g["group"] for g in groups] == ["bifurcation", "periodic", "total"]
    assert groups[0] == {
        "group": "bifurcation",
        "jobs": 2,
        "wall_s": 50.0,
        "cpu_s": 48.0,
        "share_pct": 83.3,
        "longest_job": "bifurcation_chunk_increasing_0",
        "longest_wall_s": 30.0,
    }
    assert math.isnan(groups[1]["cpu_s"])  # no job of the group was sampled
    assert groups[-1]["jobs"] == 3 and groups[-1]["wall_s"] == 60.0 and groups[-1]["cpu_s"] == 48.0
    assert [j["job"] for j in largest_jobs(jobs, 2)] == [
        "bifurcation_chunk_increasing_0",
        "bifurcation_chunk_increasing_1",
    ]
    page = build_times_markdown(groups, largest_jobs(jobs, 2))
    assert "3 jobs, 60.0 s of wall time" in page
    assert "| periodic | 1 | 10.0 | - | 16.7 | fig01 | 10.0 |" in page
    assert "| **total** | 3 | 60.0 | 48.0 | 100.0 |" in page
