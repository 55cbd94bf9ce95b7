"""Every file the package writes or reads: atomically written text, JSON, CSV and HDF5 run files.

Why one module: each format is written in exactly one way, so a number looks the same in
every table and an interrupted job never leaves a file that looks complete (everything is
written under a temporary name in the target directory and renamed into place).

HDF5 run files are the contract between the simulation and every downstream rule.
Layout (stable; measured records written by other tools follow it too):
    impacts/t, impacts/v, penetrations/t, penetrations/h, near_misses/t, near_misses/gap,
    poincare/t, poincare/x, poincare/v, trajectory/t|x|v (only when a window was asked for)
    root attributes: model parameters (param_*), omega, transient, duration, x0, v0, solver,
    rtol, atol, step/RHS counters, wall_time, version, git_commit.
JSON: statistics with NaN/inf written as null. CSV: tables with "\n" line ends; the
number format is an explicit option of :func:`write_csv`.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import os
import subprocess
import tempfile
from contextlib import contextmanager
from pathlib import Path

import h5py
import numpy as np

from . import __version__


def git_commit() -> str:
    """Commit of the source tree the package runs from ('unknown' outside a git checkout)."""
    here = Path(__file__).resolve().parent
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if out.returncode != 0:
        return "unknown"
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=here,
                           capture_output=True, text=True, timeout=5).stdout.strip()
    return out.stdout.strip() + ("-dirty" if dirty else "")


def check_writable(path) -> Path:
    """Fail early (before any computing) when `path` cannot be created."""
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if path.is_dir():
        raise ValueError(f"output path {path} is a directory")
    if not parent.is_dir():
        raise ValueError(f"output directory {parent} does not exist")
    if not os.access(parent, os.W_OK):
        raise ValueError(f"output directory {parent} is not writable")
    return path


@contextmanager
def atomic_write(path):
    """Yield a temporary file name next to `path`; it replaces `path` only if the block
    completes, so an interrupted writer never leaves a file that looks finished."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def write_text(path, text: str) -> Path:
    """Write `text` atomically, line ends as given."""
    path = Path(path)
    with atomic_write(path) as tmp, open(tmp, "w", newline="") as f:
        f.write(text)
    return path


# ------------------------------------------------------------------------------ JSON

def _jsonable(obj):
    """Plain JSON types: arrays and tuples become lists, numpy scalars Python ones, dataclasses
    dicts, and NaN/inf null (JSON has none; numpy reads null back as NaN with dtype=float)."""
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    if isinstance(obj, (np.bool_,)):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return _jsonable(dataclasses.asdict(obj))
    return obj


def write_json(path, data, *, final_newline: bool = False) -> Path:
    """Write `data` (numpy arrays and scalars allowed; NaN/inf become null) atomically as
    JSON indented by 1; `final_newline` ends the file with a newline."""
    text = json.dumps(_jsonable(data), indent=1, allow_nan=False)
    return write_text(path, text + "\n" if final_newline else text)


def read_json(path) -> dict:
    """Read a JSON file (e.g. one written by :func:`write_json`)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"statistics file {path} does not exist")
    return json.loads(path.read_text())


# ------------------------------------------------------------------------------- CSV

def _cell(v, floats: str, yes_no: bool, join_lists: bool):
    if v is None:
        return ""
    if yes_no and isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return format(float(v), floats)
    if join_lists and isinstance(v, (list, tuple, np.ndarray)):
        return " ".join(str(_cell(x, floats, yes_no, join_lists)) for x in v)
    return v


def write_csv(path, rows: list[dict], columns=None, *, floats: str = ".6g", yes_no: bool = False,
              join_lists: bool = False) -> Path:
    """Write dict rows atomically as CSV ("\n" line ends).

    Parameters
    ----------
    rows : list of dict
        A missing cell is written empty; a key outside `columns` raises ValueError.
    columns : sequence of str, optional
        The header; default the keys of all rows in first-seen order (then `rows` must not
        be empty).
    floats : str
        Format spec of float cells (".6g": tables for reading; ".10g": measurements that
        are read back and compared; "": the shortest form that reads back exactly, as
        Python prints the float).
    yes_no : bool
        Write booleans as yes/no (else True/False).
    join_lists : bool
        Write lists, tuples and arrays as their cells joined by spaces.
    """
    if columns is None:
        if not rows:
            raise ValueError(f"no rows to write to {path}")
        columns = list(dict.fromkeys(k for r in rows for k in r))
    columns = list(columns)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=columns, lineterminator="\n")
    w.writeheader()
    for r in rows:
        if set(r) - set(columns):
            raise ValueError(f"row has columns {sorted(set(r) - set(columns))} not in {columns}")
        w.writerow({c: _cell(r.get(c), floats, yes_no, join_lists) for c in columns})
    return write_text(path, buf.getvalue())


def _number(s: str):
    if s == "":
        return math.nan
    try:
        return float(s)
    except ValueError:
        return s


def read_csv(path, numbers: bool = False) -> list[dict]:
    """Rows of a CSV file as dicts of strings; with `numbers`, numeric cells become floats
    and empty ones NaN."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"table {path} does not exist")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [{k: _number(v) for k, v in r.items()} for r in rows] if numbers else rows


def write_table(path, rows: list[dict]) -> Path:
    """A measurement table (benchmarks) that :func:`read_table` reads back: floats with 10
    significant digits, booleans yes/no, lists joined by spaces, columns the union of the rows'."""
    return write_csv(path, rows, floats=".10g", yes_no=True, join_lists=True)


def read_table(path) -> list[dict]:
    """Rows of a table written by :func:`write_table`; numeric cells become floats."""
    return read_csv(path, numbers=True)


# -------------------------------------------------------------------------- run files

def write_run(path, events: dict, attrs: dict, trajectory: dict | None = None) -> Path:
    """Write events (group -> column -> array), optional trajectory and attributes atomically."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        for group, columns in events.items():
            g = f.create_group(group)
            for name, values in columns.items():
                g.create_dataset(name, data=np.asarray(values, dtype=float))
        if trajectory is not None:
            g = f.create_group("trajectory")
            for name in ("t", "x", "v"):
                g.create_dataset(name, data=np.asarray(trajectory[name], dtype=float), compression="gzip")
        for key, value in attrs.items():
            f.attrs[key] = value
        f.attrs.setdefault("version", __version__)
        f.attrs.setdefault("git_commit", git_commit())
    return path


def read_run(path) -> tuple[dict, dict, dict | None]:
    """(events, attrs, trajectory) of a run file; raises FileNotFoundError naming the path."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"run file {path} does not exist")
    events, trajectory = {}, None
    with h5py.File(path, "r") as f:
        for group in f:
            cols = {name: f[group][name][()] for name in f[group]}
            if group == "trajectory":
                trajectory = cols
            else:
                events[group] = cols
        attrs = {k: (v.item() if hasattr(v, "item") else v) for k, v in f.attrs.items()}
    return events, attrs, trajectory
