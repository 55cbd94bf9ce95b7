"""Measured displacement records: what a record holds, and when it is valid.

Why: the paper's experimental panels come from a rig whose data are not public.  A user's
own record (or the clearly labelled surrogate of :mod:`impactosc.records.surrogate`) enters the
workflow as a :class:`Record`, is checked here, and then goes through exactly the event extraction
(:mod:`impactosc.records.extract`) and statistics used for the model.  The files a record is
read from and written to (CSV, HDF5 and record sets; TDMS read) are
:mod:`impactosc.records.formats`; every reader ends in :func:`record_from_samples`, so
each format is checked alike.

One record: uniformly sampled time (s) and displacement (declared in m, mm or um; held in m),
optionally with the forcing phase measured by an encoder on the unbalance's shaft.

The forcing phase is the angle of the unbalance, in ``phase_units`` (``rad``, ``deg``, ``rev``,
or ``counts:N`` for an encoder with N counts per revolution), wrapped (e.g. 0..2 pi, or counts
reset by the index pulse each revolution) or unwrapped -- the reader unwraps it, which needs
less than half a revolution per sample.  Phase 0 (and 2 pi i) must be the forcing's phase 0
(``sin(phase) = 0`` rising, the model's ``t = 2 pi i / omega``): zero the encoder there.
``Record.phase`` is then in radians, unwrapped and advancing.  Why: the rig's motor speed is
not exactly the nominal w and drifts; Poincare points taken at the measured phase stay on the
section, those at ``2 pi i / omega`` slide off it (:mod:`impactosc.records.poincare`).

Bad records are refused with a ValueError naming the line (CSV) or sample (HDF5):
non-numeric or missing values, NaN/inf, unsorted or repeated time stamps, gaps in the
sampling (an interval above ``max_gap_factor`` times the median), a record shorter than
one forcing period, undeclared or implausible units; a phase that does not advance or jumps
back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "Record",
    "record_from_samples",
    "validate_samples",
    "phase_factor",
    "UNITS",
    "UNIT_ALIASES",
    "PHASE_UNITS",
]

#: Displacement units a record may declare, with their factor to metres.
UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6}
#: Spellings of the same units (LabVIEW writes the micro sign).
UNIT_ALIASES = {"\u00b5m": "um", "\u03bcm": "um"}
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


def record_from_samples(
    t, x, meta, *, units, omega, source, where, path, phase=None, phase_units=None, counts_per_rev=None
):
    """Apply units, coerce metadata types and validate (shared by CSV, HDF5 and TDMS)."""
    meta = dict(meta)
    declared = meta.pop("units", None)
    declared = UNIT_ALIASES.get(declared, declared)
    units = UNIT_ALIASES.get(units, units)
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
