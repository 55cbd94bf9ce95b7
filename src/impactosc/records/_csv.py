"""CSV parsing of a measured record: the metadata block, the header and the samples.

Why a module: a record of an hour at kHz rates is millions of lines, so the samples are read
in blocks of lines (bounded memory, :mod:`impactosc.records.streams`), each parsed by one
``np.loadtxt`` call; where numpy refuses a block (a malformed line), a line-by-line parser
reads it again to name the line and the problem.  The format is described in
:mod:`impactosc.records.formats`.
"""

from __future__ import annotations

import csv

import numpy as np

__all__ = ["CsvSource"]

#: Characters of a block of text read at once (1 MB: ~40 000 lines of a record).
BLOCK_CHARS = 1 << 20
#: Longest line of a CSV record (64 K characters): a sample's line has tens, a header a few
#: hundred; csv's own field limit (128 K) is never reached.
MAX_LINE_CHARS = 1 << 16
# the line boundaries of str.splitlines
_BREAKS = "\n\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029"


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


def _line_blocks(f, source):
    """The lines of the open text file ``f`` (as ``str.splitlines`` splits them), a list per
    block of about ``BLOCK_CHARS`` characters.  A line longer than ``MAX_LINE_CHARS`` is
    refused (naming it, not quoting it): the unfinished line carried into the next block stays
    short, so a file without line breaks costs one block, not a scan per block."""
    pending, lineno = "", 0
    while True:
        text = f.read(BLOCK_CHARS)
        if not text:
            if pending:
                yield [pending]
            return
        text = pending + text
        lines = text.splitlines()
        pending = "" if text[-1] in _BREAKS else lines.pop()
        if len(pending) > MAX_LINE_CHARS or (lines and max(map(len, lines)) > MAX_LINE_CHARS):
            k = next((k for k, line in enumerate(lines) if len(line) > MAX_LINE_CHARS), len(lines))
            raise ValueError(
                f"{source}: line {lineno + k + 1} is longer than {MAX_LINE_CHARS} characters; "
                "a record's CSV lines are short (a header, then one sample per line)"
            )
        lineno += len(lines)
        if lines:
            yield lines


def _loadtxt_columns(data, first_lineno, n_columns, cols):
    """Fast path: parse the data lines with one ``np.loadtxt`` call (about 5x faster on 1e6 rows).

    Returns (list of the columns ``cols``, line numbers of the rows), or None when numpy refuses the block
    (non-numeric or missing fields, ragged rows, whitespace-only lines, quoted fields ...) or
    its rows do not match the header; the caller then reparses line by line, which names the
    line and the problem.
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
    numbers = np.arange(first_lineno, first_lineno + len(data))
    if a.shape[0] != len(data):
        numbers = numbers[np.fromiter(map(bool, data), bool, len(data))]
        if len(numbers) != a.shape[0]:
            return None
    return [a[:, j].copy() for j in cols], numbers


def _parse_lines(lines, first_lineno, header, cols, source):
    """Columns ``cols`` of data lines and the line number of each row (empty lines skipped)."""
    fast = _loadtxt_columns(lines, first_lineno, len(header), cols)
    if fast is not None:
        return fast
    # Line-by-line fallback: slower, but names the line and the problem of a malformed row.
    values, numbers = [[] for _ in cols], []
    for k, row in enumerate(csv.reader(lines), start=first_lineno):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != len(header):
            raise ValueError(f"{source}: line {k}: {len(row)} fields, the header has {len(header)}")
        try:
            for v, j in zip(values, cols):
                v.append(float(row[j]))
        except ValueError:
            raise ValueError(f"{source}: line {k}: non-numeric value in {row}") from None
        numbers.append(k)
    return [np.asarray(v, dtype=float) for v in values], np.asarray(numbers, dtype=np.int64)


class CsvSource:
    """A CSV record's metadata and header, read on opening, and its samples in blocks of lines.

    The columns ``time_column`` and ``x_column`` (and ``phase_column``, by default a column
    named ``phase`` if there is one); the metadata block is the metadata.  Read sequentially:
    the number of samples is known only at the end.
    """

    random_access = False
    validated = False
    n = None

    def __init__(self, path, time_column, x_column, units, omega, phase_column=None, phase_units=None):
        self.path = path
        self.source = source = str(path)
        head, lineno, header_line = [], 0, None
        with open(path) as f:
            for lines in _line_blocks(f, self.source):
                for line in lines:
                    lineno += 1
                    if line.startswith("#") or not line.strip():
                        head.append((lineno, line))
                        continue
                    header_line = line
                    break
                if header_line is not None:
                    break
        self.meta = _parse_meta(head, source)
        if header_line is None:
            raise ValueError(f"{source}: no header line after the metadata block")
        self.header_lineno = lineno
        self.header = header = [h.strip() for h in next(csv.reader([header_line]))]
        if phase_column is None and "phase" in header:  # a column named phase is the phase
            phase_column = "phase"
        wanted = [time_column, x_column] + ([phase_column] if phase_column is not None else [])
        for col in wanted:
            if col not in header:
                raise ValueError(f"{source}: line {lineno}: header {header} has no column {col!r}")
        self.cols = [header.index(c) for c in wanted]
        self.has_phase = phase_column is not None
        self.header_options = dict(units=units, omega=omega, phase_units=phase_units, counts_per_rev=None)

    def blocks(self, start, stop, size=None, phase_only=False):
        """(t, x, phase or None, line numbers) of the samples [0, stop) (all: stop None), a
        block of lines at a time; a sequential source starts at sample 0."""
        if start != 0:
            raise ValueError("a CSV record is read from its first sample")
        got = 0
        with open(self.path) as f:
            lineno, skip = 0, self.header_lineno
            for lines in _line_blocks(f, self.source):
                if skip:
                    k = min(skip, len(lines))
                    skip, lineno, lines = skip - k, lineno + k, lines[k:]
                    if not lines:
                        continue
                arrays, numbers = _parse_lines(lines, lineno + 1, self.header, self.cols, self.source)
                lineno += len(lines)
                if stop is not None and got + numbers.size >= stop:
                    k = stop - got
                    arrays, numbers = [a[:k] for a in arrays], numbers[:k]
                if numbers.size:
                    got += numbers.size
                    yield arrays[0], arrays[1], arrays[2] if self.has_phase else None, numbers
                if stop is not None and got >= stop:
                    return

    def close(self):
        pass
