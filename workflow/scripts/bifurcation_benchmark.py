"""Throughput of the bifurcation sweeps: w values per second per core, and the wall time.

Reads input.sweeps (merged sweep files with per-job timing); writes output.json (per sweep the CPU seconds
and w values per second per core; over all sweeps the wall time of the sweep jobs).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("bifurcation_benchmark")
configure_logging(snakemake)

import json
import logging
from pathlib import Path

from impactosc.dynamics.sweep import load_sweep


def main(paths, names, out):
    report = {"sweeps": {}}
    first, last = [], []
    for name, path in zip(names, paths):
        res, attrs = load_sweep(path)
        wall = float(sum(attrs["job_core_seconds"]))
        cpu = float(sum(attrs["job_cpu_seconds"]))
        n_jobs_w = int(sum(attrs["job_n_omega"]))
        report["sweeps"][name] = {
            "n_omega": len(res),
            "n_omega_computed": n_jobs_w,
            "jobs": len(attrs["job_part"]),
            "cpu_seconds": cpu,
            "job_wall_seconds": wall,
            "omega_per_second_per_core": len(res) / cpu,
            "forcing_periods_per_second_per_core": n_jobs_w * (res.settings.n_transient + res.settings.n_record) / cpu,
            "steps_per_second": res.steps_per_second,
            "abandoned": int((res.status != 0).sum()),
            "span_seconds": float(max(attrs["job_finished"]) - min(attrs["job_started"])),
        }
        first.append(min(attrs["job_started"]))
        last.append(max(attrs["job_finished"]))
    report["all_sweeps_span_seconds"] = float(max(last) - min(first))
    report["note"] = (
        "cpu_seconds: CPU time of the per-w runs of every job (coarse pass and chunk warm-ups "
        "included; unlike job_wall_seconds it does not grow when other processes share the core); "
        "omega_per_second_per_core = delivered w / cpu_seconds; forcing periods counted as "
        "n_transient + n_record per computed w; all_sweeps_span_seconds = first job start to last "
        "job end (wall time of the sweep jobs under the -j used)"
    )
    Path(out).write_text(json.dumps(report, indent=1))
    logging.info(json.dumps(report))


main(snakemake.input.sweeps, snakemake.params.names, snakemake.output.json)
