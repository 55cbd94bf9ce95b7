"""Extraction of measured records against sample rate and record length: throughput and peak
resident memory, for HDF5 and TDMS files, and whether the extracted impacts are right.

Why: a rig records for hours at tens of kHz (an hour at 50 kHz is 180 M samples), and such a
record must extract in the memory of a laptop, at a pace that keeps up with the rig.
``impactosc extract`` reads the record in chunks (:mod:`impactosc.records.streams`); this
measures it, one case per format x sample rate x duration.

How each case is measured:

* The record is a long surrogate (:func:`impactosc.records.long_surrogate.write_long_surrogate`,
  the model at ``omega`` with white sensor noise), written once to a scratch folder and deleted
  after its case. HDF5 records are written uncompressed (format ``h5``; a DAQ writes its file
  so, and the measure is then the extraction's, not zlib's); ``h5_gzip`` is the surrogate's
  gzip + shuffle file, for the cost of decompressing. TDMS records hold one channel and the
  waveform time base (8 bytes a sample; HDF5 stores the times too, 16 bytes a sample).
* With ``cold_cache`` the record is dropped from the page cache before each run (fsync, then
  ``posix_fadvise(DONTNEED)``), so it is read from the disk as a rig's file would be, not from
  the memory it was just written from.
* The extraction runs in a fresh process: ``python -m impactosc.cli.main extract RECORD
  --output OUT`` (the ``impactosc extract`` command; x_impact from the record's metadata).
  Wall time: from starting that process to its exit (interpreter start, imports and writing the
  run file included: what a user waits for). Peak RSS: ``ru_maxrss`` of that one process (the
  kernel's high-water mark of its resident set), read by a small wrapper interpreter whose only
  child it is (:func:`measure` says why not from this process).
* For records of at most ``in_memory_max_samples`` samples the in-memory path runs too, the same
  way: ``read_record`` + ``extract_events(record)`` in a fresh process, for the memory contrast.
* The extracted impacts are matched one to one to the surrogate's exact ones
  (:func:`impactosc_study.noise_study.match_impacts`): found, true, matched, missed, extra, and
  the rms timing error of the matched ones.

:func:`startup_floor` measures the same interpreter importing the extraction path and exiting:
the part of a short case's time and memory that does not depend on the record.
"""

from __future__ import annotations

import contextlib
import math
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from impactosc.io.files import read_run
from impactosc.model.parameters import ModelParams
from impactosc.records.long_surrogate import write_long_surrogate
from impactosc.records.streams import open_record_stream
from impactosc.records.surrogate import SurrogateOptions
from impactosc_study.noise_study import match_impacts

__all__ = [
    "FORMATS",
    "COLUMNS",
    "Measured",
    "measure",
    "drop_cached",
    "startup_floor",
    "impact_check",
    "run_case",
    "extraction_scaling",
    "goal_lines",
    "scaling_markdown",
    "scaling_figure",
]

#: format -> (file suffix, HDF5 compression of write_long_surrogate)
FORMATS = {"h5": (".h5", None), "h5_gzip": (".h5", "gzip"), "tdms": (".tdms", None)}
#: path -> what runs in the measured process
PATHS = {
    "streamed": "impactosc extract (chunks of 2^20 samples)",
    "in_memory": "read_record + extract_events(record)",
}
COLUMNS = [
    "format",
    "path",
    "rate_hz",
    "duration_s",
    "samples",
    "file_mb",
    "write_s",
    "wall_s",
    "samples_per_s",
    "peak_rss_mb",
    "impacts_found",
    "impacts_true",
    "matched",
    "missed",
    "extra",
    "timing_rms_s",
    "cold_cache",
]
MB = 1e6
# ru_maxrss is in kB on Linux, in bytes on macOS
_MAXRSS_BYTES = 1 if sys.platform == "darwin" else 1024
# The in-memory path as the measured process runs it: the record read whole, then extracted.
IN_MEMORY = """import sys
from impactosc.io.files import write_run
from impactosc.records.extract import extract_events
from impactosc.records.formats import read_record
events, attrs = extract_events(read_record(sys.argv[1]))
write_run(sys.argv[2], events, attrs, sources=[sys.argv[1]])
"""
# The measuring wrapper (see measure): argv[1] the log file, argv[2:] the measured command.
WRAPPER = """import json, resource, subprocess, sys, time
with open(sys.argv[1], "wb") as log:
    start = time.perf_counter()
    code = subprocess.call(sys.argv[2:], stdout=log, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - start
rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
print(json.dumps({"returncode": code, "wall_s": wall, "maxrss": rss}))
"""
# What the streamed command imports before it reads a sample (the startup floor).
IMPORTS = "import impactosc.cli.main, impactosc.io.files, impactosc.records.extract, impactosc.records.streams"


@dataclass(frozen=True)
class Measured:
    """One process run: wall time from its start to its exit (s) and its peak resident set (bytes)."""

    wall_s: float
    peak_rss: int


def measure(argv, log_path) -> Measured:
    """Run ``argv`` in a fresh process (its output to ``log_path``) and measure it: wall time
    and the peak RSS of that process. Raises RuntimeError with the end of its output when it
    fails.

    The process is started by a small wrapper interpreter (:data:`WRAPPER`) that times it and
    reads its ``ru_maxrss`` (RUSAGE_CHILDREN: it is the wrapper's only child). Why a wrapper:
    Linux keeps the high-water mark of the memory a process had before ``exec`` in its
    ru_maxrss, and a child started by this process (fork or vfork, then exec) would report at
    least this process's own peak, hundreds of MB once the surrogate was simulated. The
    wrapper's own few MB are below any extraction's."""
    import json

    argv = [str(a) for a in argv]
    run = subprocess.run(
        [sys.executable, "-c", WRAPPER, str(log_path), *argv], capture_output=True, text=True, check=False
    )
    if run.returncode != 0:
        raise RuntimeError(f"the measuring wrapper failed ({run.returncode}): {run.stderr[-2000:]}")
    out = json.loads(run.stdout.strip().splitlines()[-1])
    if out["returncode"] != 0:
        tail = Path(log_path).read_text(errors="replace")[-2000:]
        raise RuntimeError(f"{' '.join(argv[:4])} ... exited with {out['returncode']}:\n{tail}")
    return Measured(out["wall_s"], int(out["maxrss"]) * _MAXRSS_BYTES)


def drop_cached(path) -> bool:
    """Drop a file's pages from the page cache (written to disk first), so that the next read
    comes from the disk; False where the system cannot (no posix_fadvise)."""
    if not hasattr(os, "posix_fadvise"):
        return False
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)  # dirty pages are not dropped
        os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
    finally:
        os.close(fd)
    return True


def startup_floor(scratch) -> Measured:
    """The interpreter importing the extraction path and exiting, measured as a case is."""
    return measure([sys.executable, "-c", IMPORTS], Path(scratch) / "startup.log")


def impact_check(found_t, true_t) -> dict:
    """Extracted impact times against the exact ones: counts and the rms timing error."""
    found_t, true_t = np.sort(np.asarray(found_t, float)), np.sort(np.asarray(true_t, float))
    i_found, i_true = match_impacts(true_t, found_t)
    dt = found_t[i_found] - true_t[i_true]
    return {
        "impacts_found": int(found_t.size),
        "impacts_true": int(true_t.size),
        "matched": int(i_found.size),
        "missed": int(true_t.size - i_true.size),
        "extra": int(found_t.size - i_found.size),
        "timing_rms_s": float(np.sqrt(np.mean(dt**2))) if dt.size else math.nan,
    }


def _argv(path, record, out):
    if path == "streamed":
        return [sys.executable, "-m", "impactosc.cli.main", "extract", record, "--output", out]
    return [sys.executable, "-c", IN_MEMORY, record, out]


def run_case(
    fmt,
    rate,
    duration,
    scratch,
    *,
    omega=40.86,
    transient=100.0,
    noise=5e-6,
    seed=0,
    params: ModelParams | None = None,
    in_memory_max_samples=40_000_000,
    cold_cache=True,
    log=None,
) -> list[dict]:
    """Write one record, extract it (streamed; in memory too when it is small enough), check
    the impacts, delete the record; one row (:data:`COLUMNS`) per path."""
    if fmt not in FORMATS:
        raise ValueError(f"format {fmt!r} is not one of {sorted(FORMATS)}")
    suffix, compression = FORMATS[fmt]
    scratch = Path(scratch)
    record = scratch / f"record_{fmt}_{rate:g}Hz_{duration:g}s{suffix}"
    out = scratch / f"events_{fmt}_{rate:g}Hz_{duration:g}s.h5"
    rows = []
    try:
        start = time.perf_counter()
        _, truth = write_long_surrogate(
            record,
            omega,
            duration,
            SurrogateOptions(rate=float(rate), noise=float(noise), seed=int(seed)),
            transient=transient,
            params=params,
            h5_compression=compression,
        )
        write_s = time.perf_counter() - start
        with open_record_stream(record) as stream:
            samples = int(stream.n_samples)
        paths = ["streamed"] + (["in_memory"] if samples <= in_memory_max_samples else [])
        for path in paths:
            cold = drop_cached(record) if cold_cache else False
            m = measure(_argv(path, record, out), out.with_suffix(".log"))
            events, _, _ = read_run(out)
            row = {
                "format": fmt,
                "path": path,
                "rate_hz": float(rate),
                "duration_s": float(duration),
                "samples": samples,
                "file_mb": record.stat().st_size / MB,
                "write_s": write_s,
                "wall_s": m.wall_s,
                "samples_per_s": samples / m.wall_s,
                "peak_rss_mb": m.peak_rss / MB,
                **impact_check(events["impacts"]["t"], truth["impacts"]["t"]),
                "cold_cache": cold,
            }
            rows.append(row)
            if log is not None:
                log(
                    f"{fmt} {path} {rate:g} Hz x {duration:g} s ({samples} samples): {m.wall_s:.2f} s, "
                    f"{row['samples_per_s'] / 1e6:.3g} M samples/s, peak RSS {row['peak_rss_mb']:.0f} MB; "
                    f"impacts {row['matched']}/{row['impacts_true']} matched, {row['missed']} missed, "
                    f"{row['extra']} extra"
                )
    finally:
        for f in (record, out, out.with_suffix(".log")):
            with contextlib.suppress(FileNotFoundError):
                f.unlink()
    return rows


def extraction_scaling(formats, rates, durations, scratch, *, log=None, **case) -> list[dict]:
    """Every case, shortest records first (a failure shows early): the rows of :func:`run_case`.
    ``case``: its keyword options (omega, transient, noise, seed, params, in_memory_max_samples,
    cold_cache)."""
    Path(scratch).mkdir(parents=True, exist_ok=True)
    cases = sorted(((r * d, f, r, d) for f in formats for r in rates for d in durations), key=lambda c: c[0])
    rows = []
    for _, fmt, rate, duration in cases:
        rows += run_case(fmt, float(rate), float(duration), scratch, log=log, **case)
    order = {f: i for i, f in enumerate(formats)}
    rows.sort(key=lambda r: (order[r["format"]], r["path"] != "streamed", r["rate_hz"], r["duration_s"]))
    return rows


def goal_lines(rows, goal) -> list[str]:
    """For each format, whether its longest streamed record meets the goal (peak RSS under
    ``goal["peak_rss_mb"]``, at least ``goal["samples_per_s"]``)."""
    lines = []
    for fmt in dict.fromkeys(r["format"] for r in rows):
        streamed = [r for r in rows if r["format"] == fmt and r["path"] == "streamed"]
        if not streamed:
            continue
        r = max(streamed, key=lambda r: r["samples"])
        ok_rss = r["peak_rss_mb"] < goal["peak_rss_mb"]
        ok_speed = r["samples_per_s"] >= goal["samples_per_s"]
        verdict = "meets the goal" if ok_rss and ok_speed else "MISSES the goal"
        lines.append(
            f"- **{fmt}**, {r['rate_hz']:g} Hz x {r['duration_s']:g} s ({r['samples'] / 1e6:.4g} M samples): "
            f"peak RSS {r['peak_rss_mb']:.0f} MB, {r['samples_per_s'] / 1e6:.3g} M samples/s, "
            f"{r['matched']} of {r['impacts_true']} impacts matched ({r['missed']} missed, {r['extra']} extra, "
            f"rms timing error {r['timing_rms_s']:.2g} s): {verdict}"
        )
    return lines


def _table(rows) -> list[str]:
    head = (
        "| format | path | rate (Hz) | duration (s) | samples | file (MB) | wall (s) | M samples/s | peak RSS (MB) "
        "| impacts found / true | missed | extra | rms timing error (s) |"
    )
    lines = [head, "|" + "---|" * head.count(" | ") + "---|"]
    lines += [
        f"| {r['format']} | {r['path'].replace('_', ' ')} | {r['rate_hz']:g} | {r['duration_s']:g} "
        f"| {r['samples']:,} | {r['file_mb']:.4g} | {r['wall_s']:.2f} | {r['samples_per_s'] / 1e6:.3g} "
        f"| {r['peak_rss_mb']:.0f} | {r['impacts_found']} / {r['impacts_true']} | {r['missed']} | {r['extra']} "
        f"| {r['timing_rms_s']:.2g} |"
        for r in rows
    ]
    return lines


def scaling_markdown(rows, settings: dict, floor: Measured | None = None) -> str:
    """The table with its setup, the goal for the longest record and the startup floor."""
    cold = all(r["cold_cache"] for r in rows)
    lines = [
        "# Extracting long records: throughput and peak memory",
        "",
        f"Surrogate records at w = {settings['omega']:g} rad/s, noise {settings['noise']:g} m, seed "
        f"{settings['seed']}; formats: h5 = HDF5 uncompressed, h5_gzip = HDF5 gzip + shuffle, tdms = TDMS "
        "(one channel, waveform time base). Each extraction runs in a fresh process: streamed = "
        f"`{PATHS['streamed']}`, in memory = `{PATHS['in_memory']}` (records up to "
        f"{settings['in_memory_max_samples']:,} samples). Wall time from the process's start to its exit, "
        "imports included; peak RSS = ru_maxrss of that process (read by a wrapper whose only child it is); "
        "throughput = samples / wall time. "
        + (
            "The record was dropped from the page cache before each run (read from the disk)."
            if cold
            else "The record may have been read from the page cache (it was just written)."
        ),
        "",
        f"Goal for the longest record: peak RSS under {settings['goal']['peak_rss_mb']:g} MB and at least "
        f"{settings['goal']['samples_per_s'] / 1e6:g} M samples/s.",
        "",
        *goal_lines(rows, settings["goal"]),
        "",
    ]
    if floor is not None:
        lines += [
            f"Startup floor (the interpreter importing the extraction path, then exiting): {floor.wall_s:.2f} s, "
            f"peak RSS {floor.peak_rss / MB:.0f} MB.",
            "",
        ]
    lines += _table(rows)
    return "\n".join(lines) + "\n"


FORMAT_STYLES = {
    "h5": dict(marker="o", ls="-"),
    "h5_gzip": dict(marker="s", ls="-."),
    "tdms": dict(marker="^", ls="--"),
}


def scaling_figure(rows, png, pdf, goal=None) -> None:
    """Throughput and peak RSS against samples, log-log: one line per format and rate
    (streamed), the in-memory runs as open markers of the same colour; the goal dotted."""
    import matplotlib.pyplot as plt
    import matplotlib.ticker as mticker

    from impactosc_study.figures.style import DOUBLE, apply_style, save_figure

    apply_style()
    fig, axes = plt.subplots(1, 2, figsize=(DOUBLE, 0.42 * DOUBLE))
    rates = sorted({r["rate_hz"] for r in rows})
    colours = {rate: f"C{i}" for i, rate in enumerate(rates)}
    for ax, key, scale, label in (
        (axes[0], "samples_per_s", 1e6, "throughput (M samples/s)"),
        (axes[1], "peak_rss_mb", 1.0, "peak RSS (MB)"),
    ):
        for fmt in dict.fromkeys(r["format"] for r in rows):
            for rate in rates:
                for path in PATHS:
                    sel = sorted(
                        (r for r in rows if r["format"] == fmt and r["rate_hz"] == rate and r["path"] == path),
                        key=lambda r: r["samples"],
                    )
                    if not sel:
                        continue
                    style = dict(FORMAT_STYLES.get(fmt, {}), color=colours[rate], ms=3.5)
                    kw = {"label": f"{fmt}, {rate / 1000:g} kHz"} if path == "streamed" else {}
                    if path == "in_memory":
                        style.update(mfc="none", lw=0.6, alpha=0.7)
                    ax.plot([r["samples"] for r in sel], [r[key] / scale for r in sel], **style, **kw)
        if goal is not None:
            level = goal["samples_per_s"] / 1e6 if key == "samples_per_s" else goal["peak_rss_mb"]
            ax.axhline(level, color="0.3", lw=0.7, ls=":", label="goal" if key == "samples_per_s" else None)
        ax.set(xscale="log", yscale="log", xlabel="samples in the record", ylabel=label)
        if key == "peak_rss_mb":  # less than two decades: label 1-2-3-5 steps, not only the powers of ten
            lo, hi = ax.get_ylim()
            ax.set_yticks([v for e in range(1, 6) for v in (10**e, 2 * 10**e, 3 * 10**e, 5 * 10**e) if lo <= v <= hi])
            ax.set_ylim(lo, hi)
        ax.yaxis.set_major_formatter(mticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(mticker.NullFormatter())
        ax.grid(True, which="major", lw=0.3, alpha=0.5)
    axes[0].legend(ncol=2, fontsize=6, loc="lower right")
    axes[1].text(0.97, 0.03, "filled: streamed\nopen: in memory", transform=axes[1].transAxes, ha="right", fontsize=6)
    save_figure(fig, png, pdf)
