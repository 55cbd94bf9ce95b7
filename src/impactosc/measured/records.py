"""Measured displacement records: reading, validating and writing (CSV and HDF5).

Why: the paper's experimental panels come from a rig whose data are not public.  A user's
own record (or the clearly labelled surrogate of :mod:`impactosc.measured.surrogate`) enters the
workflow here, is checked, and then goes through exactly the event extraction
(:mod:`impactosc.measured.extract`) and statistics used for the model.

One record per file: uniformly sampled time (s) and displacement (m or mm, declared).

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
here also carry the provenance attributes of :func:`impactosc.files.stamp_h5`, which are
not record metadata and are left out of ``Record.meta``.  A CSV written here gets the
provenance sidecar of :func:`impactosc.files.write_provenance_sidecar`.

A bifurcation experiment is a *record set*: one record per w, either an HDF5 file with
groups ``records/<name>/{t,x}`` each carrying an ``omega`` attribute, or a CSV manifest
with columns ``omega,file`` (paths relative to the manifest).

Bad records are refused with a ValueError naming the line (CSV) or sample (HDF5):
non-numeric or missing values, NaN/inf, unsorted or repeated time stamps, gaps in the
sampling (an interval above ``max_gap_factor`` times the median), a record shorter than
one forcing period, undeclared or implausible units.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from ..files import PROVENANCE_ATTRS, atomic_write, stamp_h5, write_provenance_sidecar

__all__ = ["Record", "read_record", "write_record", "read_record_set", "write_record_set", "validate_samples", "UNITS"]

#: Displacement units a record may declare, with their factor to metres.
UNITS = {"m": 1.0, "mm": 1e-3}
#: A displacement range above this (in metres) cannot come from the rig (travel of a few mm).
MAX_PLAUSIBLE_RANGE_M = 0.1
MIN_SAMPLES = 20


@dataclass(frozen=True)
class Record:
    """A validated, uniformly sampled displacement record.

    Attributes
    ----------
    t : ndarray
        Sample times (s), strictly increasing, uniform within the gap tolerance.
    x : ndarray
        Displacement (m).
    omega : float or None
        Forcing frequency (rad/s).
    meta : dict
        Remaining metadata (label, source, x_impact in m, surrogate settings ...).
    path : str
        Where the record came from (for messages).
    """

    t: np.ndarray
    x: np.ndarray
    omega: float | None = None
    meta: dict = field(default_factory=dict)
    path: str = "<memory>"

    @property
    def dt(self) -> float:
        """Median sample interval (s)."""
        return float(np.median(np.diff(self.t)))

    @property
    def label(self) -> str:
        return str(self.meta.get("label", Path(self.path).stem))


def validate_samples(t, x, *, omega=None, where=None, source="record", max_gap_factor=1.5):
    """Check a record's samples; raise ValueError naming the first bad line/sample.

    ``where[i]`` is how sample i is named in messages (e.g. "line 17"); default "sample i".
    Returns (t, x) as float arrays.
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    name = (lambda i: where[i]) if where is not None else (lambda i: f"sample {i}")
    if t.ndim != 1 or t.shape != x.shape:
        raise ValueError(f"{source}: t and x must be 1-D of equal length, got {t.shape} and {x.shape}")
    if t.size < MIN_SAMPLES:
        raise ValueError(f"{source}: only {t.size} samples; a record needs at least {MIN_SAMPLES}")
    for arr, what in ((t, "time"), (x, "displacement")):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise ValueError(
                f"{source}: {name(bad[0])}: {what} is {arr[bad[0]]} (NaN or inf); "
                f"{bad.size} such value(s) in the record"
            )
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0)
    if bad.size:
        i = bad[0] + 1
        kind = "repeated" if d[bad[0]] == 0 else "unsorted (earlier than the previous one)"
        raise ValueError(
            f"{source}: {name(i)}: time stamp {float(t[i])!r} s is {kind}; time must be strictly increasing"
        )
    med = float(np.median(d))
    bad = np.flatnonzero(d > max_gap_factor * med)
    if bad.size:
        i = bad[0] + 1
        raise ValueError(
            f"{source}: {name(i)}: gap of {d[bad[0]]:.6g} s before t = {float(t[i])!r} s "
            f"(median sample interval {med:.6g} s); a gap hides impacts, so split "
            "the record there"
        )
    if omega is not None:
        period = 2 * math.pi / float(omega)
        if t[-1] - t[0] < period:
            raise ValueError(
                f"{source}: the record spans {t[-1] - t[0]:.6g} s, shorter than one "
                f"forcing period 2 pi/omega = {period:.6g} s"
            )
    span = float(np.ptp(x))
    if span > MAX_PLAUSIBLE_RANGE_M:
        raise ValueError(
            f"{source}: displacement range {span:.6g} m is implausible for the rig "
            "(a few mm of travel); are the values in mm but declared as m?"
        )
    return t, x


def _parse_meta(lines, source):
    meta = {}
    for lineno, line in lines:
        body = line.lstrip("#").strip()
        if not body:
            continue
        if ":" not in body:
            raise ValueError(f"{source}: line {lineno}: metadata line must read '# key: value', got {line!r}")
        key, value = (s.strip() for s in body.split(":", 1))
        meta[key] = value
    return meta


def _finish(t, x, meta, *, units, omega, source, where, path):
    """Apply units, coerce metadata types and validate (shared by CSV and HDF5)."""
    meta = dict(meta)
    declared = meta.pop("units", None)
    if units is not None and declared is not None and units != declared:
        raise ValueError(f"{source}: units given as {units!r} but the record declares {declared!r}")
    units = units or declared
    if units is None:
        raise ValueError(
            f"{source}: displacement units not declared; add '# units: m' or "
            "'# units: mm' to the metadata block (or pass units)"
        )
    if units not in UNITS:
        raise ValueError(f"{source}: unknown units {units!r}; use one of {sorted(UNITS)}")
    x = np.asarray(x, dtype=float) * UNITS[units]
    if omega is None and meta.get("omega") not in (None, "", "none"):
        omega = meta["omega"]
    meta.pop("omega", None)
    if omega is not None:
        try:
            omega = float(omega)
        except ValueError:
            raise ValueError(f"{source}: omega {omega!r} is not a number (rad/s)") from None
        if not math.isfinite(omega) or omega <= 0:
            raise ValueError(f"{source}: omega must be a positive frequency in rad/s, got {omega}")
    if "x_impact" in meta:
        try:
            meta["x_impact"] = float(meta["x_impact"]) * UNITS[units]
        except ValueError:
            raise ValueError(f"{source}: x_impact {meta['x_impact']!r} is not a number") from None
    t, x = validate_samples(t, x, omega=omega, where=where, source=source)
    return Record(t, x, omega, meta, str(path))


class _LineNames:
    """``where[i]`` = "line k" of sample i, without building a string per sample."""

    def __init__(self, numbers):
        self.numbers = numbers

    def __getitem__(self, i):
        return f"line {self.numbers[i]}"


def _loadtxt_columns(data, first_lineno, n_columns, jt, jx):
    """Fast path: parse the data lines with one ``np.loadtxt`` call (about 5x faster on 1e6 rows).

    Returns (t, x, where), or None when numpy refuses the block (non-numeric or missing
    fields, ragged rows, whitespace-only lines, quoted fields ...) or its rows do not match
    the header; the caller then reparses line by line, which names the line and the problem.
    """
    if not any(data):  # nothing but empty lines: loadtxt would only warn
        return None
    try:
        a = np.loadtxt(data, delimiter=",", comments=None, ndmin=2, dtype=float)
    except ValueError:
        return None
    if a.shape[1] != n_columns:
        return None
    # loadtxt skips empty lines; number the rows it kept as the line parser would
    numbers = range(first_lineno, first_lineno + len(data))
    if a.shape[0] != len(data):
        numbers = [k for k, line in zip(numbers, data) if line]
        if len(numbers) != a.shape[0]:
            return None
    return a[:, jt].copy(), a[:, jx].copy(), _LineNames(numbers)


def _read_csv(path, time_column, x_column, units, omega):
    source = str(path)
    with open(path, newline="") as f:
        lines = f.read().splitlines()
    head, i = [], 0
    while i < len(lines) and (lines[i].startswith("#") or not lines[i].strip()):
        head.append((i + 1, lines[i]))
        i += 1
    meta = _parse_meta(head, source)
    if i == len(lines):
        raise ValueError(f"{source}: no header line after the metadata block")
    header_lineno = i + 1
    header = [h.strip() for h in next(csv.reader([lines[i]]))]
    for col in (time_column, x_column):
        if col not in header:
            raise ValueError(f"{source}: line {header_lineno}: header {header} has no column {col!r}")
    jt, jx = header.index(time_column), header.index(x_column)
    fast = _loadtxt_columns(lines[i + 1 :], header_lineno + 1, len(header), jt, jx)
    if fast is not None:
        t, x, where = fast
        return _finish(t, x, meta, units=units, omega=omega, source=source, where=where, path=path)
    # Line-by-line fallback: slower, but names the line and the problem of a malformed row.
    t, x, where = [], [], []
    for k, row in enumerate(csv.reader(lines[i + 1 :]), start=header_lineno + 1):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != len(header):
            raise ValueError(f"{source}: line {k}: {len(row)} fields, the header has {len(header)}")
        try:
            t.append(float(row[jt]))
            x.append(float(row[jx]))
        except ValueError:
            raise ValueError(f"{source}: line {k}: non-numeric value in {row}") from None
        where.append(f"line {k}")
    return _finish(t, x, meta, units=units, omega=omega, source=source, where=where, path=path)


def _attrs_meta(attrs):
    return {
        k: (v.decode() if isinstance(v, bytes) else (v.item() if hasattr(v, "item") else v))
        for k, v in attrs.items()
        if k not in PROVENANCE_ATTRS
    }


def _read_h5(path, units, omega):
    source = str(path)
    with h5py.File(path, "r") as f:
        if "record" not in f or "t" not in f["record"] or "x" not in f["record"]:
            raise ValueError(f"{source}: no record/t and record/x datasets; not a record file")
        t, x = f["record/t"][()], f["record/x"][()]
        meta = _attrs_meta(f.attrs)
    return _finish(t, x, meta, units=units, omega=omega, source=source, where=None, path=path)


def read_record(path, *, time_column="t", x_column="x", units=None, omega=None) -> Record:
    """Read and validate one record (``.csv`` or ``.h5``/``.hdf5``); x returned in metres.

    ``units`` and ``omega`` override nothing: when given and also declared in the file they
    must agree (units) or take precedence (omega).
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"record file {path} does not exist")
    if path.suffix.lower() == ".csv":
        return _read_csv(path, time_column, x_column, units, omega)
    if path.suffix.lower() in (".h5", ".hdf5"):
        return _read_h5(path, units, omega)
    raise ValueError(f"{path}: unknown record format {path.suffix!r}; use .csv or .h5")


def write_record(path, t, x, *, omega=None, meta=None, units="m", sources=None) -> Path:
    """Write a record (x in metres) as CSV (in ``units``) or HDF5 (in m), atomically, with
    provenance (`sources`: input files)."""
    path = Path(path)
    meta = dict(meta or {})
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if units not in UNITS:
        raise ValueError(f"unknown units {units!r}; use one of {sorted(UNITS)}")
    if path.suffix.lower() == ".csv":

        def write(tmp):
            scale = 1.0 / UNITS[units]
            with open(tmp, "w") as f:
                f.write(f"# units: {units}\n")
                if omega is not None:
                    f.write(f"# omega: {float(omega)!r}\n")
                for k, v in meta.items():
                    if k == "x_impact":
                        v = f"{float(v) * scale:.9g}"
                    f.write(f"# {k}: {v}\n")
                f.write("t,x\n")
                np.savetxt(f, np.column_stack([t, x * scale]), fmt="%.9g", delimiter=",")
    elif path.suffix.lower() in (".h5", ".hdf5"):

        def write(tmp):
            with h5py.File(tmp, "w") as f:
                g = f.create_group("record")
                g.create_dataset("t", data=t, compression="gzip")
                g.create_dataset("x", data=x, compression="gzip")
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
                meta = _attrs_meta(g.attrs)
                out.append(
                    _finish(
                        g["t"][()],
                        g["x"][()],
                        meta,
                        units=None,
                        omega=None,
                        source=f"{path}:records/{name}",
                        where=None,
                        path=f"{path}:{name}",
                    )
                )
                if out[-1].omega is None:
                    raise ValueError(f"{path}:records/{name}: no omega attribute")
    if not out:
        raise ValueError(f"{path}: the record set is empty")
    return out
