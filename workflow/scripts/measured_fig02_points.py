"""Poincare points of a bifurcation experiment (one record per w) for the Fig 2 left panel.

Reads snakemake.input.records (record set: HDF5 or CSV manifest, impactosc.measured.records);
writes snakemake.output.points, HDF5 with flat datasets omega (rad/s) and x (m), stamped
with units and provenance (impactosc.files.stamp_h5).
"""

from _logging import configure_logging

configure_logging(snakemake)

import logging

import h5py

from impactosc.files import atomic_write, check_writable, stamp_h5
from impactosc.measured.extract import record_set_poincare
from impactosc.measured.records import read_record_set

recs = read_record_set(snakemake.input.records)
pts = record_set_poincare(recs)
out = check_writable(snakemake.output.points)
with atomic_write(out) as tmp, h5py.File(tmp, "w") as f:
    for k, v in pts.items():
        f.create_dataset(k, data=v)
    f.attrs["label"] = recs[0].label
    stamp_h5(f, sources=snakemake.input.records)
logging.info(f"{len(recs)} records, {pts['x'].size} Poincare points")
