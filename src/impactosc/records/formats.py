"""Measured-record files: one record read from CSV, HDF5 or TDMS and written to CSV or HDF5, and
record sets (one record per w).

Why a module: the formats a user's record may come in meet here, and each is read by one
reader (:mod:`impactosc.records.streams`, whole or in chunks) whose samples go through
:class:`impactosc.records.record.SampleCheck`, so that every format gives the same
validated :class:`impactosc.records.record.Record` (x in metres).

CSV format (``examples/record_example.csv``)::

    # units: mm            <- metadata block: '# key: value' lines before the header
    # omega: 40.86         <- forcing frequency, rad/s (optional; enables Poincare points)
    # label: rig run 3     <- optional name
    t,x                    <- header naming the columns (others are ignored)
    100.0000,-2.1093
    ...

Keys: ``units`` (``m`` or ``mm``, required unless given by the caller), ``omega``
(rad/s), ``x_impact`` (obstacle position in the declared units), ``label``, ``source``;
other keys are kept as metadata.  HDF5 format: datasets ``record/t`` and ``record/x`` and
the same keys as root attributes (``x`` stored in metres, ``units = "m"``); files written
here also carry the provenance attributes of :func:`impactosc.io.files.stamp_h5`, which are
not record metadata and are left out of ``Record.meta``.  A CSV written here gets the
provenance sidecar of :func:`impactosc.io.files.write_provenance_sidecar`.

A record may carry the forcing phase (CSV column ``phase``, HDF5 ``record/phase``, or a TDMS
channel) in ``phase_units`` (``rad``, ``deg``, ``rev`` or ``counts:N``; what it must measure:
:mod:`impactosc.records.record`).  TDMS (National Instruments): groups, channels and their
properties as :mod:`impactosc.records._tdms` reads them.

A bifurcation experiment is a *record set*: one record per w, either an HDF5 file with
groups ``records/<name>/{t,x}`` each carrying an ``omega`` attribute, or a CSV manifest
with columns ``omega,file`` (paths relative to the manifest).
"""

from __future__ import annotations

import csv
from pathlib import Path

import h5py
import numpy as np

from impactosc.io.files import atomic_write, stamp_h5, write_provenance_sidecar
from impactosc.records._h5 import attrs_meta
from impactosc.records.record import UNITS, Record, record_from_samples
from impactosc.records.streams import open_record_stream

__all__ = [
    "read_record",
    "write_record",
    "read_record_set",
    "write_record_set",
    "is_record_set",
    "read_records",
]


def read_record(
    path,
    *,
    time_column="t",
    x_column="x",
    units=None,
    omega=None,
    group=None,
    channel=None,
    phase_channel=None,
    time_channel=None,
    phase_units=None,
) -> Record:
    """Read and validate one record (``.csv``, ``.h5``/``.hdf5`` or ``.tdms``); x in metres.

    ``units`` and ``omega`` override nothing: when given and also declared in the file they
    must agree (units, phase_units) or take precedence (omega).  CSV: ``time_column`` and
    ``x_column`` name the columns, ``phase_channel`` a phase column (default: a column named
    ``phase``, if any).  TDMS: ``group``, ``channel`` (displacement), ``phase_channel``,
    ``time_channel`` (see :mod:`impactosc.records._tdms`).  HDF5: ``record/phase`` when present.
    The reader of :func:`impactosc.records.streams.open_record_stream`, with one chunk.
    """
    with open_record_stream(
        path,
        time_column=time_column,
        x_column=x_column,
        units=units,
        omega=omega,
        group=group,
        channel=channel,
        phase_channel=phase_channel,
        time_channel=time_channel,
        phase_units=phase_units,
    ) as stream:
        return stream.to_record()


def write_record(path, t, x, *, omega=None, meta=None, units="m", sources=None, phase=None) -> Path:
    """Write a record (x in metres, optional phase in rad) as CSV (x in ``units``) or HDF5
    (in m), atomically, with provenance (`sources`: input files)."""
    path = Path(path)
    meta = {k: v for k, v in (meta or {}).items() if k != "phase_units"}
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if units not in UNITS:
        raise ValueError(f"unknown units {units!r}; use one of {sorted(UNITS)}")
    if phase is not None:
        phase = np.asarray(phase, dtype=float)
        if phase.shape != t.shape:
            raise ValueError(f"phase has shape {phase.shape}, t {t.shape}")
    if path.suffix.lower() == ".csv":

        def write(tmp):
            scale = 1.0 / UNITS[units]
            with open(tmp, "w") as f:
                f.write(f"# units: {units}\n")
                if phase is not None:
                    f.write("# phase_units: rad\n")
                if omega is not None:
                    f.write(f"# omega: {float(omega)!r}\n")
                for k, v in meta.items():
                    if k == "x_impact":
                        v = f"{float(v) * scale:.9g}"
                    f.write(f"# {k}: {v}\n")
                # the phase keeps 12 digits: 1e-8 rad of ~1e5 rad (an hour at 40 rad/s)
                if phase is None:
                    f.write("t,x\n")
                    np.savetxt(f, np.column_stack([t, x * scale]), fmt="%.9g", delimiter=",")
                else:
                    f.write("t,x,phase\n")
                    np.savetxt(f, np.column_stack([t, x * scale, phase]), fmt=("%.9g", "%.9g", "%.12g"), delimiter=",")
    elif path.suffix.lower() in (".h5", ".hdf5"):

        def write(tmp):
            with h5py.File(tmp, "w") as f:
                g = f.create_group("record")
                g.create_dataset("t", data=t, compression="gzip")
                g.create_dataset("x", data=x, compression="gzip")
                if phase is not None:
                    g.create_dataset("phase", data=phase, compression="gzip")
                    f.attrs["phase_units"] = "rad"
                f.attrs["units"] = "m"
                if omega is not None:
                    f.attrs["omega"] = float(omega)
                for k, v in meta.items():
                    f.attrs[k] = v
                stamp_h5(f, sources=sources)
    else:
        raise ValueError(f"{path}: unknown record format {path.suffix!r}; use .csv or .h5")
    with atomic_write(path) as tmp:
        write(tmp)
    if path.suffix.lower() == ".csv":
        write_provenance_sidecar(path, sources)
    return path


def write_record_set(path, records, *, sources=None) -> Path:
    """Write records (each with an omega) into one HDF5 record set, atomically, with provenance."""
    path = Path(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        g = f.create_group("records")
        for i, rec in enumerate(records):
            if rec.omega is None:
                raise ValueError(f"record {i} ({rec.path}) has no omega; a record set needs one per record")
            r = g.create_group(f"{i:04d}")
            r.create_dataset("t", data=rec.t, compression="gzip")
            r.create_dataset("x", data=rec.x, compression="gzip")
            if rec.phase is not None:
                r.create_dataset("phase", data=rec.phase, compression="gzip")
                r.attrs["phase_units"] = "rad"
            r.attrs["omega"] = rec.omega
            r.attrs["units"] = "m"
            for k, v in rec.meta.items():
                r.attrs[k] = v
        stamp_h5(f, sources=sources)
    return path


def read_record_set(path) -> list[Record]:
    """Records of a bifurcation experiment (HDF5 record set or CSV manifest omega,file)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"record set {path} does not exist")
    out = []
    if path.suffix.lower() == ".csv":
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        if not rows or not {"omega", "file"} <= set(rows[0]):
            raise ValueError(f"{path}: a manifest needs a header 'omega,file' and one row per record")
        for k, row in enumerate(rows, start=2):
            try:
                w = float(row["omega"])
            except ValueError:
                raise ValueError(f"{path}: line {k}: omega {row['omega']!r} is not a number") from None
            out.append(read_record(path.parent / row["file"], omega=w))
    else:
        with h5py.File(path, "r") as f:
            if "records" not in f:
                raise ValueError(f"{path}: no 'records' group; not a record set")
            for name in sorted(f["records"]):
                g = f["records"][name]
                meta = attrs_meta(g.attrs)
                out.append(
                    record_from_samples(
                        g["t"][()],
                        g["x"][()],
                        meta,
                        units=None,
                        omega=None,
                        source=f"{path}:records/{name}",
                        where=None,
                        path=f"{path}:{name}",
                        phase=g["phase"][()] if "phase" in g else None,
                    )
                )
                if out[-1].omega is None:
                    raise ValueError(f"{path}:records/{name}: no omega attribute")
    if not out:
        raise ValueError(f"{path}: the record set is empty")
    return out


def is_record_set(path) -> bool:
    """A record set (HDF5 with a 'records' group, or a CSV manifest 'omega,file') rather than one record."""
    path = Path(path)
    if not path.is_file():
        return False
    if path.suffix.lower() in (".h5", ".hdf5"):
        with h5py.File(path, "r") as f:
            return "records" in f
    if path.suffix.lower() == ".csv":
        with open(path, newline="") as f:
            first = f.readline().strip().replace(" ", "")
        return first == "omega,file"
    return False


def read_records(paths, *, duration=None, **options) -> list[Record]:
    """Records of several files, each a record (read with ``options``, as read_record) or a record set.

    ``duration`` (s): of each record file only its first ``duration`` seconds, read in chunks (a
    long record's samples beyond them are never read into memory); None: whole records.
    """
    if duration is not None and not (np.isfinite(duration) and duration > 0):
        raise ValueError(f"duration must be > 0 s, got {duration}")
    out = []
    for path in paths:
        if is_record_set(path):
            out += read_record_set(path)
        elif duration is None:
            out.append(read_record(path, **options))
        else:
            with open_record_stream(path, **options) as stream:
                c = stream.read(0, int(round(duration / stream.dt)) + 1)
                out.append(Record(c.t, c.x, stream.omega, dict(stream.meta), stream.path, c.phase))
    return out
