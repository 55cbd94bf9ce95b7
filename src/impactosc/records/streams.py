"""Records read in chunks: a rig record of any length (an hour at 50 kHz is 180 M samples) read
with bounded memory.

Why: :func:`impactosc.records.formats.read_record` holds the whole record in memory.  A
:class:`RecordStream` reads a record (CSV, HDF5, TDMS, or a :class:`Record` in memory) chunk by
chunk, with the same values and the same checks and messages as a whole read, because
``read_record`` is this reader with one chunk (:class:`impactosc.records.record.SampleCheck`).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np

from impactosc.records.record import (
    MIN_SAMPLES,
    REFERENCE_SAMPLES,
    Record,
    RecordHeader,
    SampleCheck,
    check_length,
    record_header,
    sample_reference,
)

__all__ = ["RecordChunk", "RecordStream", "open_record_stream"]

#: Samples per read of a file that can be sliced (HDF5, TDMS), at least: smaller chunks are cut from it.
READ_BLOCK = 1 << 16


class RecordChunk(NamedTuple):
    """Samples ``start`` .. ``start + len(t) - 1`` of a record: t (s), x (m), phase (rad) or None."""

    start: int
    t: np.ndarray
    x: np.ndarray
    phase: np.ndarray | None


def _cut(block, k):
    """(the first k samples of a raw block, the rest)."""
    return tuple(None if a is None else a[:k] for a in block), tuple(None if a is None else a[k:] for a in block)


def _join(blocks):
    if len(blocks) == 1:
        return blocks[0]
    return tuple(None if blocks[0][j] is None else np.concatenate([b[j] for b in blocks]) for j in range(4))


class _Rechunk:
    """Raw blocks (t, x, phase, lines) of any length regrouped into chunks of ``size`` samples
    (the last may be shorter), each with whether it is the last (from ``total``, the number of
    samples, when known, else by reading ahead); ``rest()``: what follows."""

    def __init__(self, blocks, size, total=None):
        self.blocks, self.size, self.left = iter(blocks), size, total
        self.buf, self.nbuf, self.done = [], 0, False

    def _fill(self, want):
        while self.nbuf < want and not self.done:
            block = next(self.blocks, None)
            if block is None:
                self.done = True
            elif len(block[0]):
                self.buf.append(block)
                self.nbuf += len(block[0])

    def __iter__(self):
        while True:
            self._fill(self.size)
            if not self.nbuf:
                return
            parts, k = [], min(self.size, self.nbuf)
            while k:
                block = self.buf.pop(0)
                if len(block[0]) > k:
                    block, rest = _cut(block, k)
                    self.buf.insert(0, rest)
                parts.append(block)
                k -= len(block[0])
                self.nbuf -= len(block[0])
            chunk = _join(parts)
            if self.left is None:
                self._fill(1)  # is there more?
                last = not self.nbuf
            else:
                self.left -= len(chunk[0])
                last = self.left <= 0
            yield chunk, last

    def rest(self):
        yield from self.buf
        yield from self.blocks


def _namer(start, lines):
    """How sample i of a chunk is named in messages: its CSV line, else its index in the record."""
    if lines is None:
        return lambda i: f"sample {start + i}"
    return lambda i: f"line {lines[i]}"


class _MemorySource:
    """A Record already in memory (validated, in m and rad)."""

    random_access = True
    validated = True

    def __init__(self, record: Record):
        self.record = record
        self.path = self.source = record.path
        self.meta, self.omega = dict(record.meta), record.omega
        self.n, self.has_phase = record.t.size, record.phase is not None

    def blocks(self, start, stop, size, phase_only=False):
        r = self.record
        for a in range(start, stop, size):
            b = min(a + size, stop)
            yield r.t[a:b], r.x[a:b], (r.phase[a:b] if r.phase is not None else None), None

    def close(self):
        pass


class RecordStream:
    """One record, read chunk by chunk (a context manager: closes the file).

    Attributes: ``meta``, ``omega``, ``path``, ``label`` as :class:`Record`'s; ``n_samples``
    (None for a CSV file, which would have to be read to the end to know it); ``t0`` the first
    time stamp; ``dt`` the median sample interval of the first ``REFERENCE_SAMPLES`` samples;
    ``has_phase``.  Open a file with :func:`open_record_stream`, a Record with
    :meth:`from_record`.
    """

    def __init__(self, source):
        self._src = src = source
        try:
            if src.validated:
                self._header = RecordHeader(dict(src.meta), src.omega, src.source)
            else:
                self._header = record_header(src.meta, source=src.source, phase=src.has_phase, **src.header_options)
            h = self._header
            head = self._raw_head()
            if len(head[0]) < MIN_SAMPLES:  # fewer than asked for: the whole record, too short to be one
                check_length(len(head[0]), src.source)
            self._reference = sample_reference(head[0], head[2], factor=h.phase_factor or 1.0, offset=h.phase_offset)
        except BaseException:
            src.close()
            raise
        self.path = str(src.path)
        self.meta, self.omega = h.meta, h.omega
        self.n_samples, self.has_phase = src.n, src.has_phase
        self.dt = self._reference[0]
        self.t0 = float(head[0][0]) if len(head[0]) else None

    @classmethod
    def from_record(cls, record: Record) -> RecordStream:
        """A Record in memory as a stream (its chunks are views of its arrays)."""
        return cls(_MemorySource(record))

    @property
    def label(self) -> str:
        return str(self.meta.get("label", Path(self.path).stem))

    def _raw_head(self):
        n = REFERENCE_SAMPLES if self._src.n is None else min(self._src.n, REFERENCE_SAMPLES)
        blocks = list(self._src.blocks(0, n, max(n, 1))) if n else []
        if not blocks:
            return np.empty(0), None, None, None
        return _join(blocks)

    def _range(self, start, stop):
        start = int(start)
        if start < 0 or (stop is not None and int(stop) < start):
            raise ValueError(f"{self.path}: sample range [{start}, {stop}) must have 0 <= start <= stop")
        n = self.n_samples
        if n is not None:
            stop = n if stop is None else min(int(stop), n)
            start = min(start, stop)
        elif stop is not None:
            stop = int(stop)
        return start, stop

    def _blocks(self, check, start, stop, size):
        """Raw blocks of the samples [start, stop); those before ``start`` are carried over
        (the time stamp and phase of the one before, the phase unwrapped from the first)."""
        src = self._src
        if src.random_access:
            stop = src.n if stop is None else stop
            if start > 0:
                check.skip(t=next(src.blocks(start - 1, start, 1))[0])
                if src.has_phase:
                    for a, (_, _, q, _) in zip(range(0, start, 1 << 20), src.blocks(0, start, 1 << 20, True)):
                        check.skip(phase=q, name=_namer(a, None))
            yield from src.blocks(start, stop, min(max(size, READ_BLOCK), max(stop - start, 1)))
            return
        pos = 0
        for block in src.blocks(0, stop, size):
            n = len(block[0])
            if pos < start:
                k = min(start - pos, n)
                skipped, block = _cut(block, k)
                check.skip(skipped[0], skipped[2], _namer(pos, skipped[3]))
                pos += k
                if k == n:
                    continue
            pos += len(block[0])
            yield block

    def chunks(self, size, start=0, stop=None):
        """Yield :class:`RecordChunk` of ``size`` samples (the last may be shorter) of the
        samples [start, stop) (stop None: to the end), converted and checked as
        :func:`impactosc.records.formats.read_record` does: the same values, the same
        ValueError for a bad sample, naming it, also at a chunk border.  Checks of the record
        as such (length, one forcing period, displacement range) when the chunks cover it
        whole; the phase of a part is unwrapped from the record's first sample."""
        size = int(size)
        if size < 1:
            raise ValueError(f"chunk size must be >= 1 sample, got {size}")
        start, stop = self._range(start, stop)
        if self._src.validated:
            for block in self._src.blocks(start, stop, size):
                yield RecordChunk(start, *block[:3])
                start += len(block[0])
            return
        whole = start == 0 and (stop is None or stop == self.n_samples)
        check = SampleCheck(self._header, self._reference, n=self.n_samples, whole=whole)
        total = None if stop is None else stop - start
        chunker = _Rechunk(self._blocks(check, start, stop, size), size, total)
        pos = start
        for (t, x, phase, lines), last in chunker:
            rest = ((b[0], b[1]) for b in chunker.rest())
            t, x, phase = check.chunk(t, x, phase, _namer(pos, lines), rest=rest, last=last)
            yield RecordChunk(pos, t, x, phase)
            pos += t.size
        check.finish()

    def read(self, start=0, stop=None) -> RecordChunk:
        """The samples [start, stop) as one chunk (all of them by default)."""
        start, stop = self._range(start, stop)
        size = stop - start if stop is not None else sys.maxsize
        parts = list(self.chunks(max(size, 1), start, stop))
        if parts:
            return parts[0]
        empty = np.empty(0)
        return RecordChunk(start, empty, empty.copy(), empty.copy() if self.has_phase else None)

    def to_record(self) -> Record:
        """The whole record (what :func:`impactosc.records.formats.read_record` returns)."""
        if self._src.validated:
            return self._src.record
        c = self.read()
        return Record(c.t, c.x, self.omega, dict(self.meta), self.path, c.phase)

    def close(self):
        self._src.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        n = "?" if self.n_samples is None else self.n_samples
        return f"RecordStream({self.path!r}, {n} samples, omega={self.omega})"


def open_record_stream(
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
) -> RecordStream:
    """Open one record (``.csv``, ``.h5``/``.hdf5`` or ``.tdms``) for reading in chunks; the
    options are :func:`impactosc.records.formats.read_record`'s.  Reads the metadata and the
    first ``REFERENCE_SAMPLES`` samples; use it as a context manager (it holds the file open)."""
    from impactosc.records._csv import CsvSource
    from impactosc.records._h5 import H5Source
    from impactosc.records._tdms import TdmsSource

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"record file {path} does not exist")
    suffix = path.suffix.lower()
    if suffix == ".tdms":
        src = TdmsSource(
            path,
            group=group,
            channel=channel,
            phase_channel=phase_channel,
            time_channel=time_channel,
            units=units,
            phase_units=phase_units,
            omega=omega,
        )
        return RecordStream(src)
    given = [k for k, v in (("group", group), ("channel", channel), ("time_channel", time_channel)) if v is not None]
    if given:
        raise ValueError(f"{path}: {', '.join(given)} name(s) TDMS groups and channels; this is a {suffix} record")
    if suffix == ".csv":
        return RecordStream(CsvSource(path, time_column, x_column, units, omega, phase_channel, phase_units))
    if suffix in (".h5", ".hdf5"):
        if phase_channel is not None:
            raise ValueError(f"{path}: an HDF5 record's phase is record/phase; phase_channel is for CSV and TDMS")
        return RecordStream(H5Source(path, units=units, omega=omega))
    raise ValueError(f"{path}: unknown record format {path.suffix!r}; use .csv, .h5 or .tdms")
