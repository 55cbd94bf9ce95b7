"""CSV tables of the benchmark rules: rows of mixed columns, written atomically.

Why: measurement rows differ in their columns (a failed SciPy run has a message, not an
error), so the header is the union of all rows in first-seen order; floats keep 10
significant digits (timings and errors are compared across rows), lists are joined by
spaces, and reading turns numbers back into floats.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
from ..files import atomic_write


def _cell(v):
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return format(float(v), ".10g")
    if isinstance(v, (list, tuple, np.ndarray)):
        return " ".join(str(_cell(x)) for x in v)
    return "" if v is None else v


def write_table(path, rows: list[dict]) -> Path:
    """Write dict rows to CSV (union of columns, first-seen order), atomically."""
    if not rows:
        raise ValueError(f"no rows to write to {path}")
    columns = list(dict.fromkeys(k for r in rows for k in r))
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({c: _cell(r.get(c)) for c in columns})
    path = Path(path)
    with atomic_write(path) as tmp, open(tmp, "w", newline="") as f:
        f.write(buf.getvalue())
    return path


def _parse(s: str):
    if s == "":
        return math.nan
    try:
        return float(s)
    except ValueError:
        return s


def read_table(path) -> list[dict]:
    """Rows of a CSV written by :func:`write_table`; numeric cells become floats."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"table {path} does not exist")
    with open(path, newline="") as f:
        return [{k: _parse(v) for k, v in row.items()} for row in csv.DictReader(f)]
