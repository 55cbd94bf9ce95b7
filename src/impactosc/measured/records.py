"""Measured displacement records: reading, validating and writing (CSV, HDF5; TDMS read).

Why: the paper's experimental panels come from a rig whose data are not public.  A user's
own record (or the clearly labelled surrogate of :mod:`impactosc.measured.surrogate`) enters the
workflow here, is checked, and then goes through exactly the event extraction
(:mod:`impactosc.measured.extract`) and statistics used for the model.

One record per file: uniformly sampled time (s) and displacement (m, mm or um, declared),
optionally with the forcing phase measured by an encoder on the unbalance's shaft.

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

A record may carry the forcing phase (CSV column ``phase``, HDF5 ``record/phase``, or a TDMS
channel): the angle of the unbalance, in ``phase_units`` (``rad``, ``deg``, ``rev``, or
``counts:N`` for an encoder with N counts per revolution), wrapped (e.g. 0..2 pi, or counts
reset by the index pulse each revolution) or unwrapped -- the reader unwraps it, which needs
less than half a revolution per sample.  Phase 0 (and 2 pi i) must be the forcing's phase 0
(``sin(phase) = 0`` rising, the model's ``t = 2 pi i / omega``): zero the encoder there.
``Record.phase`` is then in radians, unwrapped and advancing.  Why: the rig's motor speed is
not exactly the nominal w and drifts; Poincare points taken at the measured phase stay on the
section, those at ``2 pi i / omega`` slide off it (:mod:`impactosc.measured.extract`).

TDMS (National Instruments; read with npTDMS): name the ``group`` and the displacement
``channel`` (either may be left out when there is only one), optionally a ``phase_channel``
and a ``time_channel``.  Time comes from the named time channel (s or ms, or a timestamp
channel, taken relative to its first sample), else from the channel's waveform properties
``wf_start_offset + k * wf_increment``; neither -> error.  Displacement units come from the
channel's ``unit_string`` property (m, mm, um) or the ``units`` option (both: they must
agree); phase units from the phase channel's ``unit_string`` (rad, deg, rev, counts/ticks
with a ``counts_per_rev`` property) or ``phase_units``.  Scalar properties of the file, the
group and the channel (``omega``, ``x_impact`` in the channel's units, ``label`` ...; not the
``wf_*``/``NI_*`` ones) become metadata.  A Hall-sensor channel still in volts is refused:
apply the sensor's calibration (a DAQmx custom scale) first.

A bifurcation experiment is a *record set*: one record per w, either an HDF5 file with
groups ``records/<name>/{t,x}`` each carrying an ``omega`` attribute, or a CSV manifest
with columns ``omega,file`` (paths relative to the manifest).

Bad records are refused with a ValueError naming the line (CSV) or sample (HDF5):
non-numeric or missing values, NaN/inf, unsorted or repeated time stamps, gaps in the
sampling (an interval above ``max_gap_factor`` times the median), a record shorter than
one forcing period, undeclared or implausible units; a phase that does not advance or jumps
back.  TDMS problems (no such group or channel, no time base, unknown unit) get one line
naming the file, the channel and the fix.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from ..files import PROVENANCE_ATTRS, atomic_write, stamp_h5, write_provenance_sidecar

__all__ = [
    "Record",
    "read_record",
    "write_record",
    "read_record_set",
    "write_record_set",
    "is_record_set",
    "read_records",
    "validate_samples",
    "phase_factor",
    "UNITS",
    "PHASE_UNITS",
]

#: Displacement units a record may declare, with their factor to metres.
UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6}
#: Spellings of the same units (LabVIEW writes the micro sign).
_UNIT_ALIASES = {"\u00b5m": "um", "\u03bcm": "um"}
#: Phase units with their factor to radians; ``counts:N`` (N counts per revolution) besides.
PHASE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0, "rev": 2.0 * math.pi}
_PHASE_ALIASES = {"radians": "rad", "degrees": "deg", "\u00b0": "deg", "revolutions": "rev", "turns": "rev"}
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
    phase : ndarray or None
        Measured forcing phase (rad) at each sample, unwrapped and advancing, 2 pi i at the
        forcing's phase 0 of period i; None when the record has no encoder channel.
    """

    t: np.ndarray
    x: np.ndarray
    omega: float | None = None
    meta: dict = field(default_factory=dict)
    path: str = "<memory>"
    phase: np.ndarray | None = None

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


def phase_factor(units, source="record", counts_per_rev=None) -> float:
    """Factor from a phase unit to radians: ``rad``, ``deg``, ``rev`` or ``counts:N`` (also
    ``ticks:N``; plain ``counts`` with ``counts_per_rev``).  Why counts: an encoder read by a
    counter input gives ticks, N per revolution (4 x the lines of a quadrature encoder)."""
    u = str(units).strip()
    key = _PHASE_ALIASES.get(u.lower(), u.lower())
    if key in PHASE_UNITS:
        return PHASE_UNITS[key]
    kind, _, n = key.partition(":")
    if kind in ("counts", "ticks"):
        n = n.strip() or counts_per_rev
        if n in (None, ""):
            raise ValueError(
                f"{source}: phase in encoder {kind} but the counts per revolution are unknown; "
                "give phase_units as 'counts:N' (N counts per revolution) or a counts_per_rev property"
            )
        try:
            n = float(n)
        except ValueError:
            raise ValueError(f"{source}: counts per revolution {n!r} is not a number") from None
        if not (math.isfinite(n) and n > 0):
            raise ValueError(f"{source}: counts per revolution must be > 0, got {n:g}")
        return 2.0 * math.pi / n
    raise ValueError(f"{source}: unknown phase unit {units!r}; use rad, deg, rev or counts:N (N counts per revolution)")


def _is_counts(units) -> bool:
    return str(units).strip().lower().partition(":")[0] in ("counts", "ticks")


def _phase_radians(raw, n, factor, source, where, offset=0.0):
    """Measured phase in radians, unwrapped and checked (finite, advancing, no jump back).

    ``offset`` is added to the raw values first: half a count for an encoder counter, whose
    count c means the angle is in [c, c + 1) counts (the centre removes a bias of half a
    count, 0.8 mrad at 4096 counts per revolution, ~20 us at 40 rad/s).
    np.unwrap makes a wrapped phase (0..2 pi, or counts reset each revolution) continuous and
    leaves an unwrapped one unchanged, provided the phase moves less than pi per sample.
    """
    name = (lambda i: where[i]) if where is not None else (lambda i: f"sample {i}")
    phase = np.asarray(raw, dtype=float)
    if phase.shape != (n,):
        raise ValueError(f"{source}: phase has {phase.size} samples, the displacement {n}")
    bad = np.flatnonzero(~np.isfinite(phase))
    if bad.size:
        raise ValueError(f"{source}: {name(bad[0])}: phase is {phase[bad[0]]} (NaN or inf)")
    phase = np.unwrap((phase + offset) * factor)
    d = np.diff(phase)
    step = float(np.median(d))
    if not step > 0:
        raise ValueError(
            f"{source}: the phase does not advance (median step {step:.3g} rad per sample); "
            "an encoder counting backwards needs its sign flipped"
        )
    if step > math.pi / 2:
        raise ValueError(
            f"{source}: the phase advances {step:.3g} rad per sample; it must be sampled at least "
            "4 times per revolution to be unwrapped"
        )
    back = np.flatnonzero(d < -math.pi / 2)
    if back.size:
        raise ValueError(
            f"{source}: {name(back[0] + 1)}: the phase jumps back by {-d[back[0]]:.3g} rad; "
            "is this channel an angle (check phase_units)?"
        )
    return phase


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


def _finish(t, x, meta, *, units, omega, source, where, path, phase=None, phase_units=None, counts_per_rev=None):
    """Apply units, coerce metadata types and validate (shared by CSV, HDF5 and TDMS)."""
    meta = dict(meta)
    declared = meta.pop("units", None)
    declared = _UNIT_ALIASES.get(declared, declared)
    units = _UNIT_ALIASES.get(units, units)
    declared_phase = meta.pop("phase_units", None)
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
    if phase is not None:
        if phase_units is not None and declared_phase is not None and phase_units != declared_phase:
            raise ValueError(
                f"{source}: phase units given as {phase_units!r} but the record declares {declared_phase!r}"
            )
        phase_units = phase_units or declared_phase
        if phase_units is None:
            raise ValueError(
                f"{source}: phase units not declared; add '# phase_units: rad' (or deg, rev, "
                "counts:N) to the metadata block (or pass phase_units)"
            )
        factor = phase_factor(phase_units, source, counts_per_rev)
        offset = 0.5 if _is_counts(phase_units) else 0.0
        phase = _phase_radians(phase, t.size, factor, source, where, offset)
        meta["phase_read_as"] = str(phase_units)
    return Record(t, x, omega, meta, str(path), phase)


class _LineNames:
    """``where[i]`` = "line k" of sample i, without building a string per sample."""

    def __init__(self, numbers):
        self.numbers = numbers

    def __getitem__(self, i):
        return f"line {self.numbers[i]}"


def _loadtxt_columns(data, first_lineno, n_columns, cols):
    """Fast path: parse the data lines with one ``np.loadtxt`` call (about 5x faster on 1e6 rows).

    Returns (list of the columns ``cols``, where), or None when numpy refuses the block (non-numeric or missing
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
    return [a[:, j].copy() for j in cols], _LineNames(numbers)


def _read_csv(path, time_column, x_column, units, omega, phase_column=None, phase_units=None):
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
    if phase_column is None and "phase" in header:  # a column named phase is the phase
        phase_column = "phase"
    wanted = [time_column, x_column] + ([phase_column] if phase_column is not None else [])
    for col in wanted:
        if col not in header:
            raise ValueError(f"{source}: line {header_lineno}: header {header} has no column {col!r}")
    cols = [header.index(c) for c in wanted]
    finish = dict(units=units, omega=omega, source=source, path=path, phase_units=phase_units)
    fast = _loadtxt_columns(lines[i + 1 :], header_lineno + 1, len(header), cols)
    if fast is not None:
        arrays, where = fast
        phase = arrays[2] if len(arrays) > 2 else None
        return _finish(arrays[0], arrays[1], meta, where=where, phase=phase, **finish)
    # Line-by-line fallback: slower, but names the line and the problem of a malformed row.
    values, where = [[] for _ in cols], []
    for k, row in enumerate(csv.reader(lines[i + 1 :]), start=header_lineno + 1):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != len(header):
            raise ValueError(f"{source}: line {k}: {len(row)} fields, the header has {len(header)}")
        try:
            for v, j in zip(values, cols):
                v.append(float(row[j]))
        except ValueError:
            raise ValueError(f"{source}: line {k}: non-numeric value in {row}") from None
        where.append(f"line {k}")
    phase = values[2] if len(values) > 2 else None
    return _finish(values[0], values[1], meta, where=where, phase=phase, **finish)


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
        phase = f["record/phase"][()] if "phase" in f["record"] else None
        meta = _attrs_meta(f.attrs)
    if phase is not None:
        meta.setdefault("phase_units", "rad")
    return _finish(t, x, meta, units=units, omega=omega, source=source, where=None, path=path, phase=phase)


#: TDMS properties that describe the acquisition, not the record (left out of Record.meta).
_TDMS_RESERVED = ("unit_string", "counts_per_rev", "counts_per_revolution")


def _tdms_meta(*objects):
    """Scalar properties of the file, group and channel (later ones win), minus waveform and
    NI bookkeeping; timestamps and other objects are left out (they are not record metadata)."""
    meta = {}
    for obj in objects:
        for k, v in obj.properties.items():
            if k.startswith(("wf_", "NI_")) or k in _TDMS_RESERVED:
                continue
            if isinstance(v, (np.generic,)):
                v = v.item()
            if isinstance(v, (str, int, float)) and not isinstance(v, bool):
                meta[k] = v
    return meta


def _tdms_pick(source, what, name, available, option):
    """The named group/channel, or the only one; else an error listing what there is."""
    if name is None:
        if len(available) == 1:
            return available[0]
        raise ValueError(f"{source}: {len(available)} {what}s {available}; name one ({option})")
    if name not in available:
        raise ValueError(f"{source}: no {what} {name!r} in the TDMS file; {what}s: {available}")
    return name


def _tdms_unit(channel):
    u = channel.properties.get("unit_string", "")
    return str(u).strip() or None


def _tdms_time(source, group, channel, time_channel, n):
    """Sample times (s): the named time channel, else the waveform properties, else an error."""
    where = f"{source}: channel '{group.name}/{channel.name}'"
    if time_channel is not None:
        names = [c.name for c in group.channels()]
        if time_channel not in names:
            raise ValueError(f"{source}: group '{group.name}' has no time channel {time_channel!r}; channels: {names}")
        tc = group[time_channel]
        raw = tc[:]
        if raw.size != n:
            raise ValueError(f"{source}: time channel {time_channel!r} has {raw.size} samples, the displacement {n}")
        if raw.dtype.names and {"seconds", "second_fractions"} <= set(raw.dtype.names):
            # TDMS timestamps (read raw: 2^-64 s resolution, not numpy's 1 us): seconds from the first
            return (raw["seconds"] - raw["seconds"][0]).astype(float) + raw["second_fractions"] / 2.0**64
        unit = _tdms_unit(tc) or "s"
        scale = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "\u00b5s": 1e-6}.get(unit)
        if scale is None:
            raise ValueError(f"{source}: time channel {time_channel!r} has unit {unit!r}; use s, ms or us")
        return np.asarray(raw, dtype=float) * scale
    props = channel.properties
    if "wf_increment" not in props:
        raise ValueError(
            f"{where} has no time base: no wf_increment property and no time channel given "
            "(name one with time_channel / --time-channel)"
        )
    dt = float(props["wf_increment"])
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"{where}: wf_increment must be a sample interval > 0 s, got {dt!r}")
    return float(props.get("wf_start_offset", 0.0)) + dt * np.arange(n)


def _read_tdms(path, *, group, channel, phase_channel, time_channel, units, phase_units, omega):
    from nptdms import TdmsFile

    source = str(path)
    try:
        f = TdmsFile.open(path, raw_timestamps=True)
    except Exception as exc:  # npTDMS raises assorted errors on a damaged or foreign file
        raise ValueError(f"{source}: not a readable TDMS file ({type(exc).__name__}: {exc})") from None
    with f:
        groups = [g.name for g in f.groups()]
        if not groups:  # npTDMS reads a file without TDMS segments as an empty one
            raise ValueError(f"{source}: no groups in the file; not a TDMS file, or an empty one")
        gname = _tdms_pick(source, "group", group, groups, "group / --group")
        g = f[gname]
        names = [c.name for c in g.channels()]
        if channel is None:
            others = [c for c in names if c not in (phase_channel, time_channel)]
            channel = others[0] if len(others) == 1 else None
        cname = _tdms_pick(source, "channel", channel, names, "channel / --channel")
        ch = g[cname]
        x = np.asarray(ch[:], dtype=float)
        meta = _tdms_meta(f, g, ch)
        declared = _tdms_unit(ch)
        if declared is not None:
            declared = _UNIT_ALIASES.get(declared, declared)
            if declared not in UNITS:
                raise ValueError(
                    f"{source}: channel '{gname}/{cname}' has unit {declared!r}, not a displacement unit; "
                    f"use one of {sorted(UNITS)} (calibrate a sensor voltage first)"
                )
            meta["units"] = declared
        elif units is None and "units" not in meta:
            raise ValueError(
                f"{source}: channel '{gname}/{cname}' declares no unit (unit_string); "
                f"pass units / --units (one of {sorted(UNITS)})"
            )
        t = _tdms_time(source, g, ch, time_channel, x.size)
        phase, counts = None, None
        if phase_channel is not None:
            if phase_channel not in names:
                raise ValueError(f"{source}: group '{gname}' has no phase channel {phase_channel!r}; channels: {names}")
            pc = g[phase_channel]
            phase = np.asarray(pc[:], dtype=float)
            if pc.properties.get("wf_increment", None) not in (None, ch.properties.get("wf_increment")):
                raise ValueError(
                    f"{source}: phase channel {phase_channel!r} is sampled every "
                    f"{pc.properties['wf_increment']!r} s, the displacement every "
                    f"{ch.properties.get('wf_increment')!r} s; both must come from one acquisition"
                )
            punit = _tdms_unit(pc)
            if punit is None and phase_units is None:
                raise ValueError(
                    f"{source}: phase channel '{gname}/{phase_channel}' declares no unit (unit_string); "
                    "pass phase_units / --phase-units (rad, deg, rev or counts:N)"
                )
            if punit is not None:
                meta["phase_units"] = punit
            counts = pc.properties.get("counts_per_rev", pc.properties.get("counts_per_revolution"))
            meta["phase_channel"] = phase_channel
    meta["tdms_group"], meta["tdms_channel"] = gname, cname
    return _finish(
        t,
        x,
        meta,
        units=units,
        omega=omega,
        source=f"{source}:{gname}/{cname}",
        where=None,
        path=path,
        phase=phase,
        phase_units=phase_units,
        counts_per_rev=counts,
    )


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
    ``time_channel`` (see the module docstring).  HDF5: ``record/phase`` when present.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"record file {path} does not exist")
    suffix = path.suffix.lower()
    if suffix == ".tdms":
        return _read_tdms(
            path,
            group=group,
            channel=channel,
            phase_channel=phase_channel,
            time_channel=time_channel,
            units=units,
            phase_units=phase_units,
            omega=omega,
        )
    given = [k for k, v in (("group", group), ("channel", channel), ("time_channel", time_channel)) if v is not None]
    if given:
        raise ValueError(f"{path}: {', '.join(given)} name(s) TDMS groups and channels; this is a {suffix} record")
    if suffix == ".csv":
        return _read_csv(path, time_column, x_column, units, omega, phase_channel, phase_units)
    if suffix in (".h5", ".hdf5"):
        if phase_channel is not None:
            raise ValueError(f"{path}: an HDF5 record's phase is record/phase; phase_channel is for CSV and TDMS")
        return _read_h5(path, units, omega)
    raise ValueError(f"{path}: unknown record format {path.suffix!r}; use .csv, .h5 or .tdms")


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


def read_records(paths, **options) -> list[Record]:
    """Records of several files, each a record (read with ``options``, as read_record) or a record set."""
    out = []
    for path in paths:
        out += read_record_set(path) if is_record_set(path) else [read_record(path, **options)]
    return out
