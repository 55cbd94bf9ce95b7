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
sampling (an interval above ``max_gap_factor`` times the median interval of the first
``REFERENCE_SAMPLES``), a record shorter than
one forcing period, undeclared or implausible units; a phase that does not advance or jumps
back.  The checks are :class:`SampleCheck`'s, which takes the samples chunk by chunk (a
record read whole is one chunk) so that a long record can be read in parts
(:mod:`impactosc.records.streams`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = [
    "Record",
    "check_motion",
    "record_from_samples",
    "record_header",
    "RecordHeader",
    "SampleCheck",
    "sample_reference",
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
#: The median sample interval and phase step the checks compare with are those of this many
#: first samples (1.3 s at 50 kHz).
REFERENCE_SAMPLES = 2**16 + 1


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
    Returns (t, x) as float arrays.  The checks are :class:`SampleCheck`'s, on one chunk.
    """
    header = RecordHeader({}, omega, source)
    t = np.asarray(t, dtype=float)
    check = SampleCheck(header, sample_reference(t), max_gap_factor=max_gap_factor)
    t, x, _ = check.chunk(t, x, name=(lambda i: where[i]) if where is not None else None, last=True)
    check.finish()
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


def _unwrap(q, carry=None):
    """``np.unwrap(q)`` continued from the previous chunk: ``carry`` is (its last value, the
    correction added to it).  Returns (unwrapped, carry for the next chunk); chunk by chunk it
    equals the whole phase's unwrap bit for bit (``cumsum`` adds in order, so a sum started
    at the carried correction continues the whole one)."""
    if q.size == 0:
        return q.copy(), carry
    p = q if carry is None else np.concatenate(([carry[0]], q))
    dd = np.diff(p)
    # numpy's unwrap (period 2 pi, discontinuity pi), operation for operation
    period = 2 * np.pi
    high = period / 2
    low = -high
    ddmod = np.mod(dd - low, period) + low
    np.copyto(ddmod, high, where=(ddmod == low) & (dd > 0))
    correct = ddmod - dd
    np.copyto(correct, 0, where=abs(dd) < high)
    if carry is None:
        added = correct.cumsum()
        up = np.array(q, dtype=float)
        up[1:] = q[1:] + added
    else:
        added = np.concatenate(([carry[1]], correct)).cumsum()[1:]
        up = q + added
    return up, (float(q[-1]), float(added[-1]) if added.size else 0.0)


def sample_reference(t, phase=None, *, factor=1.0, offset=0.0):
    """The median sample interval (s) and median phase step (rad; None without a phase) of the
    record's first ``REFERENCE_SAMPLES`` samples (non-finite ones left out): what the gap and
    phase checks of :class:`SampleCheck` compare with.  Why the first ones and not all: a
    record read in chunks knows them before its first chunk, so it is checked as when read
    whole; for a uniformly sampled record the two medians agree."""
    t = np.asarray(t[:REFERENCE_SAMPLES], dtype=float)
    t = t[np.isfinite(t)]
    dt = float(np.median(np.diff(t))) if t.size > 1 else math.nan
    if phase is None:
        return dt, None
    q = np.asarray(phase[:REFERENCE_SAMPLES], dtype=float)
    q = q[np.isfinite(q)]
    up = _unwrap((q + offset) * factor)[0]
    return dt, (float(np.median(np.diff(up))) if up.size > 1 else math.nan)


@dataclass(frozen=True)
class RecordHeader:
    """What a record's samples become: the Record's metadata and omega, and the factors from
    the file's units to metres and radians (``phase_factor`` None: no phase channel)."""

    meta: dict
    omega: float | None
    source: str
    x_factor: float = 1.0
    phase_factor: float | None = None
    phase_offset: float = 0.0


def record_header(meta, *, units, omega, source, phase=False, phase_units=None, counts_per_rev=None) -> RecordHeader:
    """Units, omega and metadata of a record from its file's metadata and the caller's options
    (which must agree with the file's, or, for omega, take precedence)."""
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
    if not phase:
        return RecordHeader(meta, omega, source, UNITS[units])
    if phase_units is not None and declared_phase is not None and phase_units != declared_phase:
        raise ValueError(f"{source}: phase units given as {phase_units!r} but the record declares {declared_phase!r}")
    phase_units = phase_units or declared_phase
    if phase_units is None:
        raise ValueError(
            f"{source}: phase units not declared; add '# phase_units: rad' (or deg, rev, "
            "counts:N) to the metadata block (or pass phase_units)"
        )
    factor = phase_factor(phase_units, source, counts_per_rev)
    meta["phase_read_as"] = str(phase_units)
    # an encoder counter's count c means an angle in [c, c + 1) counts: read as its centre
    # (removes a bias of half a count, 0.8 mrad at 4096 counts per revolution, ~20 us at 40 rad/s)
    return RecordHeader(meta, omega, source, UNITS[units], factor, 0.5 if _is_counts(phase_units) else 0.0)


def check_motion(source, x_min: float, x_max: float, task: str) -> None:
    """A record whose displacement never changes (x from `x_min` to `x_max`, equal: a sensor
    unplugged, a channel of zeros) has no motion: refused naming that, with `task` (what there
    is nothing to do: "identify", "extract"), rather than by a later step finding no impact,
    turning point or window in it."""
    if x_min == x_max:
        raise ValueError(f"record {source}: x does not move (constant at {x_min:g} m): nothing to {task}")


def check_length(n: int, source) -> None:
    """A whole record of ``n`` samples: at least ``MIN_SAMPLES`` (fewer leave no interval to
    judge the sampling by, nor a motion to extract)."""
    if n < MIN_SAMPLES:
        raise ValueError(f"{source}: only {n} samples; a record needs at least {MIN_SAMPLES}")


class SampleCheck:
    """Unit conversion and validation of a record's samples, given in order, chunk by chunk.

    Why one class for both: a record read whole is one chunk, so a record read in chunks gets
    the same values and the same messages, also for a defect at a chunk border (the last time
    stamp and phase of a chunk are carried to the next).  The gaps and the phase step are
    judged against :func:`sample_reference` (``reference``).  ``whole``: the chunks cover the
    whole record, which adds the checks of the record as such (at least ``MIN_SAMPLES``, one
    forcing period long, a plausible displacement range); part of a record gets the checks of
    its samples.  Where a message counts over the record (NaN values, the range), the chunk
    that meets the defect scans the ``rest`` of the chunks ((t, x) in file units) for it.  With
    several defects a chunked read names the first it meets, a whole read the first by kind.

    The phase is unwrapped (which needs less than half a revolution per sample): a wrapped
    phase (0..2 pi, or counts reset by the index pulse) becomes continuous, an unwrapped one is
    left unchanged.  It must advance, at most pi/2 per sample, and never jump back.
    """

    def __init__(self, header: RecordHeader, reference, *, n=None, whole=True, max_gap_factor=1.5):
        self.header = header
        self.ref_dt, self.ref_step = reference
        self.n, self.whole, self.max_gap_factor = n, whole, max_gap_factor
        self.count = 0
        self.t_first = self.t_last = self.phase_last = None
        self.x_min, self.x_max = math.inf, -math.inf
        self._carry = None
        self._length_checked = self._step_checked = False

    def _fail(self, message):
        raise ValueError(f"{self.header.source}: {message}")

    def _check_length(self, n):
        check_length(n, self.header.source)
        self._length_checked = True

    def _phase(self, raw, n, name):
        q = np.asarray(raw, dtype=float)
        if q.shape != (n,):
            self._fail(f"phase has {q.size} samples, the displacement {n}")
        bad = np.flatnonzero(~np.isfinite(q))
        if bad.size:
            self._fail(f"{name(bad[0])}: phase is {q[bad[0]]} (NaN or inf)")
        h = self.header
        previous = self.phase_last
        up, self._carry = _unwrap((q + h.phase_offset) * h.phase_factor, self._carry)
        if up.size:
            self.phase_last = up[-1]
        return up, previous

    def skip(self, t=None, phase=None, name=None):
        """Carry the samples before a part read over them (its first time stamp and phase are
        judged against them) without returning or checking them."""
        if t is not None and len(t):
            self.t_last = float(t[-1])
        if phase is not None and self.header.phase_factor is not None:
            self._phase(phase, len(phase), name or (lambda i: f"sample {i}"))

    def chunk(self, t, x, phase=None, name=None, *, rest=(), last=False):
        """The next samples converted and checked: (t in s, x in m, phase in rad or None).

        ``name(i)``: how sample i of the chunk is named (default ``"sample k"``, k counted from
        the first chunk); ``last``: no chunk follows.
        """
        h = self.header
        t = np.asarray(t, dtype=float)
        x = np.asarray(x, dtype=float) * h.x_factor
        if name is None:
            first = self.count

            def name(i):
                return f"sample {first + i}"

        if t.ndim != 1 or t.shape != x.shape:
            self._fail(f"t and x must be 1-D of equal length, got {t.shape} and {x.shape}")
        if self.whole and not self._length_checked and (self.n is not None or last):
            self._check_length(self.n if self.n is not None else self.count + t.size)
        rest = iter(rest)
        for arr, what, col in ((t, "time", 0), (x, "displacement", 1)):
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                total = bad.size + sum(int(np.count_nonzero(~np.isfinite(np.asarray(b[col], float)))) for b in rest)
                self._fail(f"{name(bad[0])}: {what} is {arr[bad[0]]} (NaN or inf); {total} such value(s) in the record")
        # interval k is between sample k - 1 and k (sample 0: the previous chunk's last)
        first = 1 if self.t_last is None else 0
        d = np.diff(t) if self.t_last is None else np.diff(t, prepend=self.t_last)
        bad = np.flatnonzero(d <= 0)
        if bad.size:
            i = bad[0] + first
            kind = "repeated" if d[bad[0]] == 0 else "unsorted (earlier than the previous one)"
            self._fail(f"{name(i)}: time stamp {float(t[i])!r} s is {kind}; time must be strictly increasing")
        med = self.ref_dt
        bad = np.flatnonzero(d > self.max_gap_factor * med)
        if bad.size:
            i = bad[0] + first
            self._fail(
                f"{name(i)}: gap of {d[bad[0]]:.6g} s before t = {float(t[i])!r} s "
                f"(median sample interval {med:.6g} s); a gap hides impacts, so split "
                "the record there"
            )
        if t.size:
            self.t_first = t[0] if self.t_first is None else self.t_first
            self.t_last = t[-1]
        if h.omega is not None and med > 0 and 2 * math.pi / float(h.omega) < 2 * med:
            self._fail(
                f"omega = {float(h.omega):.6g} rad/s: its forcing period {2 * math.pi / float(h.omega):.6g} s is "
                f"shorter than two sample intervals ({med:.6g} s): the record cannot resolve it (omega is in rad/s)"
            )
        if self.whole and last and h.omega is not None and self.t_first is not None:
            period = 2 * math.pi / float(h.omega)
            if self.t_last - self.t_first < period:
                self._fail(
                    f"the record spans {self.t_last - self.t_first:.6g} s, shorter than one "
                    f"forcing period 2 pi/omega = {period:.6g} s"
                )
        if self.whole and x.size:
            self.x_min, self.x_max = min(self.x_min, float(x.min())), max(self.x_max, float(x.max()))
            if self.x_max - self.x_min > MAX_PLAUSIBLE_RANGE_M:
                for b in rest:
                    xr = np.asarray(b[1], dtype=float) * h.x_factor
                    if xr.size:
                        self.x_min, self.x_max = min(self.x_min, float(xr.min())), max(self.x_max, float(xr.max()))
                self._fail(
                    f"displacement range {self.x_max - self.x_min:.6g} m is implausible for the rig "
                    "(a few mm of travel); are the values in mm but declared as m?"
                )
        up = None
        if h.phase_factor is not None:
            up, previous = self._phase(phase, t.size, name)
            if not self._step_checked:
                step = self.ref_step
                if not step > 0:
                    self._fail(
                        f"the phase does not advance (median step {step:.3g} rad per sample); "
                        "an encoder counting backwards needs its sign flipped"
                    )
                if step > math.pi / 2:
                    self._fail(
                        f"the phase advances {step:.3g} rad per sample; it must be sampled at least "
                        "4 times per revolution to be unwrapped"
                    )
                self._step_checked = True
            first = 1 if previous is None else 0
            d = np.diff(up) if previous is None else np.diff(up, prepend=previous)
            back = np.flatnonzero(d < -math.pi / 2)
            if back.size:
                self._fail(
                    f"{name(back[0] + first)}: the phase jumps back by {-d[back[0]]:.3g} rad; "
                    "is this channel an angle (check phase_units)?"
                )
        self.count += t.size
        return t, x, up

    def finish(self):
        """After the last chunk: a record without samples fails here."""
        if self.whole and not self._length_checked:
            self._check_length(self.count)


def record_from_samples(
    t, x, meta, *, units, omega, source, where, path, phase=None, phase_units=None, counts_per_rev=None
):
    """Apply units, coerce metadata types and validate (a record read whole: one chunk of
    :class:`SampleCheck`; the readers of :mod:`impactosc.records.streams` use the same)."""
    header = record_header(
        meta,
        units=units,
        omega=omega,
        source=source,
        phase=phase is not None,
        phase_units=phase_units,
        counts_per_rev=counts_per_rev,
    )
    t = np.asarray(t, dtype=float)
    check = SampleCheck(header, sample_reference(t, phase, factor=header.phase_factor, offset=header.phase_offset))
    name = (lambda i: where[i]) if where is not None else None
    t, x, phase = check.chunk(t, x, phase, name, last=True)
    check.finish()
    return Record(t, x, header.omega, header.meta, str(path), phase)
