"""Measured Poincare points for the Fig 2 left panel: per-w records, or one slow-sweep record.

Reads input.kernels (compiled kernels), input.records (a record set, or with params.segments one slow-sweep
record read as params.reader says, cut into segments of quasi-constant w); writes output.points (HDF5: omega,
x, with provenance).
"""

from _logging import configure_logging, mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("measured_fig02_points")
configure_logging(snakemake)

import logging

import h5py

from impactosc.io.files import atomic_write, check_writable, stamp_h5
from impactosc.records.formats import read_record, read_record_set
from impactosc.records.poincare import record_set_poincare
from impactosc.records.slow_sweep import sweep_segments, write_sweep_points

p = snakemake.params
if p.segments:
    s = p.segments
    rec = read_record(snakemake.input.records, **p.reader)
    pts, info = sweep_segments(rec, s["bin_width"], s["settle"], min_points=s["min_points"])
    write_sweep_points(snakemake.output.points, pts, info, label=rec.label, sources=snakemake.input.records)
    logging.info(
        f"{rec.path}: sweep record cut into {info['n_segments']} segments of w "
        f"{pts['record_omega'].min():.4g}..{pts['record_omega'].max():.4g} rad/s, {pts['x'].size} Poincare points "
        f"({info['n_points_settling']} discarded while settling, {info['n_segments_dropped']} short segments dropped)"
    )
else:
    recs = read_record_set(snakemake.input.records)
    pts = record_set_poincare(recs)
    out = check_writable(snakemake.output.points)
    with atomic_write(out) as tmp, h5py.File(tmp, "w") as f:
        for k, v in pts.items():
            f.create_dataset(k, data=v)
        f.attrs["label"] = recs[0].label
        stamp_h5(f, sources=snakemake.input.records)
    logging.info(f"{len(recs)} records, {pts['x'].size} Poincare points")
