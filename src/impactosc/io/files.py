"""How the package writes and reads files: atomically written text, JSON, CSV tables, HDF5 run
files, and the provenance and units every file carries.

Why one module: each format is written in exactly one way, so a number looks the same in
every table and an interrupted job never leaves a file that looks complete (everything is
written under a temporary name in the target directory and renamed into place). A result with
a file of its own is written beside its type, through these helpers: sweeps
(:mod:`impactosc.dynamics.sweep`), 2-D maps (:mod:`impactosc.dynamics.maps`), basins
(:mod:`impactosc.dynamics.basins`), records (:mod:`impactosc.records.formats`) and model files
(:mod:`impactosc.model.model_file`).

HDF5 run files are the contract between the simulation and every downstream rule.
Layout (stable; measured records written by other tools follow it too):
    impacts/t, impacts/v, penetrations/t, penetrations/h, near_misses/t, near_misses/gap,
    poincare/t, poincare/x, poincare/v, trajectory/t|x|v (only when a window was asked for)
    root attributes: model parameters (param_*), omega, transient, duration, x0, v0, solver,
    rtol, atol, step/RHS counters, wall_time.
Format version 1 (attribute ``format_version = "1"``) adds to every HDF5 file written here
(run, sweep, map and record files) a ``units`` attribute on each dataset (from
:data:`DATASET_UNITS`; "1" = dimensionless or a count) and the root attributes of
:func:`provenance`: version, git_commit, python_version, numpy_version, scipy_version,
numba_version, h5py_version and, when the writer names its inputs, sources (array of str).
Files without them (written before) read the same.
JSON: statistics with NaN/inf written as null and a top-level ``provenance`` entry (the
same keys), which :func:`read_json` leaves out unless asked. CSV: tables with "\n" line
ends; the number format is an explicit option of :func:`write_csv`; provenance goes to a
sidecar ``<name>.csv.provenance.json`` (with the table's sha256) so the table itself stays a
plain CSV for every reader.
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import hashlib
import importlib.metadata
import io
import json
import math
import os
import platform
import signal
import subprocess
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path

import h5py
import numpy as np

from impactosc import __version__


def git_commit() -> str:
    """Commit of the source tree the package runs from ('unknown' outside a git checkout)."""
    here = Path(__file__).resolve().parent
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if out.returncode != 0:
        return "unknown"
    dirty = subprocess.run(
        ["git", "status", "--porcelain", "--untracked-files=no"], cwd=here, capture_output=True, text=True, timeout=5
    ).stdout.strip()
    return out.stdout.strip() + ("-dirty" if dirty else "")


#: Layout version of the HDF5 files written here; raise it when a reader would need to know.
FORMAT_VERSION = "1"

#: Unit of every dataset the package writes, by the last part of its name; "1" means
#: dimensionless or a count. A writer refuses a dataset missing here (add it, with its unit).
DATASET_UNITS = {
    # run and event files; measured records (record/t, record/x)
    "t": "s",
    "x": "m",
    "v": "m/s",
    "h": "m",
    "gap": "m",
    "sigma_t": "s",
    "crb_t": "s",  # Cramer-Rao bound of a measured impact time
    "fit_start": "s",  # first sample of a measured impact time's fit
    "fit_samples": "1",
    "fit_degree": "1",
    # noise in the dynamics a run file writes out (group noise; impactosc.model.noise_realisation.RULE)
    "motor_speed": "rad/s",
    "cart_force": "N",
    # sweep files (impactosc.dynamics.sweep)
    "omega": "rad/s",
    "poincare_x": "m",
    "poincare_v": "m/s",
    "impact_t": "s",
    "impact_v": "m/s",
    "impact_offsets": "1",
    "min_gap": "m",
    "x_start": "m",
    "v_start": "m/s",
    "x_end": "m",
    "v_end": "m/s",
    "contact_v0_end": "m/s",
    "n_steps": "1",
    "wall_time": "s",
    "cpu_time": "s",
    "status": "1",
    # map files (impactosc.dynamics.maps; "values" takes the unit of the map's parameter)
    "period": "1",
    "impacts": "1",
    "rate": "1",
    "n_isi_levels": "1",  # period in forcing periods
    # Poincare points of a measured record set
    "record_omega": "rad/s",
    "n_points": "1",
    # measured forcing phase (encoder) of a record; segments of a measured slow sweep
    "phase": "rad",
    "point_omega": "rad/s",
    "segment_start": "s",
    "segment_stop": "s",
    "omega_spread": "rad/s",
}

_LIBRARIES = ("numpy", "scipy", "numba", "h5py")

#: Attributes the writers add to an HDF5 root (readers of user metadata skip them).
PROVENANCE_ATTRS = (
    "format_version",
    "version",
    "git_commit",
    "python_version",
    *(f"{lib}_version" for lib in _LIBRARIES),
    "sources",
)


@functools.cache
def _library_versions() -> dict:
    out = {"python_version": platform.python_version()}
    for lib in _LIBRARIES:
        try:
            out[f"{lib}_version"] = importlib.metadata.version(lib)
        except importlib.metadata.PackageNotFoundError:
            out[f"{lib}_version"] = "not installed"
    return out


def _source_list(sources) -> list[str]:
    """Paths as str from a path or any nesting of lists of paths (e.g. snakemake.input)."""
    if isinstance(sources, (str, os.PathLike)):
        return [os.fspath(sources)]
    return [s for item in sources for s in _source_list(item)]


def provenance(sources=None) -> dict:
    """What produced a file: package version, git commit, Python and library versions, and
    the input files when the caller names them. One dict, so every format says the same."""
    out = {"version": __version__, "git_commit": git_commit(), **_library_versions()}
    if sources is not None:
        out["sources"] = _source_list(sources)
    return out


def dataset_unit(name: str, units: dict | None = None) -> str:
    """Unit of dataset `name` (a path; its last part is looked up in `units`, then
    :data:`DATASET_UNITS`). Unknown names raise, so no dataset is written without a unit."""
    base = name.rsplit("/", 1)[-1]
    for table in (units or {}, DATASET_UNITS):
        if base in table:
            return table[base]
    raise ValueError(f"dataset {name!r} has no unit: add {base!r} to impactosc.io.files.DATASET_UNITS")


def stamp_h5(f, *, sources=None, units: dict | None = None) -> None:
    """Give every dataset of the open HDF5 file `f` its unit and the root the format version
    and :func:`provenance`; every HDF5 writer calls it once the datasets exist."""

    def label(name, obj):
        if isinstance(obj, h5py.Dataset):
            obj.attrs["units"] = dataset_unit(name, units)

    f.visititems(label)
    f.attrs["format_version"] = FORMAT_VERSION
    for key, value in provenance(sources).items():
        f.attrs[key] = np.array(value, dtype=h5py.string_dtype()) if key == "sources" else value


def _attr(key, value):
    """An HDF5 attribute as a Python value: size-1 arrays as scalars, others as lists,
    sources always a list of str."""
    if key == "sources":
        return [s.decode() if isinstance(s, bytes) else str(s) for s in np.atleast_1d(value)]
    if isinstance(value, np.ndarray) and value.size != 1:
        return value.tolist()
    return value.item() if hasattr(value, "item") else value


def _umask() -> int:
    """The process umask, from /proc where Linux shows it (no window in which it is changed),
    else by setting it and restoring it at once."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    old = os.umask(0o077)
    os.umask(old)
    return old


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


class Terminated(SystemExit):
    """SIGTERM arrived (a timeout, scancel, Snakemake stopping a job): raised where the process
    is, so that finally blocks run; uncaught, the process exits with status 143 (128 + 15)."""

    def __init__(self):
        super().__init__(128 + signal.SIGTERM)


def _terminate(signum, frame):
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # a second SIGTERM must not cut the cleanup short
    raise Terminated()


def raise_on_sigterm():
    """Make SIGTERM raise :class:`Terminated` in the main thread, as SIGINT raises
    KeyboardInterrupt: without it the process dies at once and :func:`atomic_write` leaves its
    hidden temporary file. Returns the handler it replaces (None outside the main thread, where
    Python cannot set one)."""
    if threading.current_thread() is not threading.main_thread():
        return None
    return signal.signal(signal.SIGTERM, _terminate)


@contextmanager
def atomic_write(path):
    """Yield a temporary file name next to `path`; it replaces `path` only if the block
    completes, so an interrupted writer never leaves a file that looks finished (nor, on an
    exception, Ctrl-C or, with :func:`raise_on_sigterm`, SIGTERM, its temporary file). The file
    gets the mode a plain open() would (0666 less the umask), not mkstemp's private 0600."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.close(fd)
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())
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


def write_json(path, data: dict, *, final_newline: bool = False, sources=None) -> Path:
    """Write the dict `data` (numpy arrays and scalars allowed; NaN/inf become null) atomically
    as JSON indented by 1, with a last top-level entry ``provenance`` (:func:`provenance` of
    `sources`, the input files); `final_newline` ends the file with a newline."""
    data = _jsonable(data)
    if not isinstance(data, dict):
        raise TypeError(f"{path}: write_json writes a dict (it adds a provenance entry), got {type(data).__name__}")
    if "provenance" in data:
        raise ValueError(f"{path}: 'provenance' is the writer's own entry; rename that key")
    text = json.dumps({**data, "provenance": provenance(sources)}, indent=1, allow_nan=False)
    return write_text(path, text + "\n" if final_newline else text)


def read_json(path, *, keep_provenance: bool = False) -> dict:
    """Read a JSON file (e.g. one written by :func:`write_json`); its ``provenance`` entry is
    left out unless `keep_provenance`, so readers see the data as before it existed."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"statistics file {path} does not exist")
    data = json.loads(path.read_text())
    if not keep_provenance and isinstance(data, dict):
        data.pop("provenance", None)
    return data


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


def provenance_path(path) -> Path:
    """The sidecar holding the provenance of a CSV file: ``<name>.csv.provenance.json``."""
    path = Path(path)
    return path.with_name(path.name + ".provenance.json")


def write_provenance_sidecar(path, sources=None) -> Path:
    """Write :func:`provenance` of the finished file `path` (with its name and sha256, so a
    sidecar left from another version of the file shows) to :func:`provenance_path`."""
    path = Path(path)
    info = {"file": path.name, "sha256": hashlib.sha256(path.read_bytes()).hexdigest(), **provenance(sources)}
    return write_text(provenance_path(path), json.dumps(info, indent=1) + "\n")


def read_provenance(path) -> dict:
    """Provenance of a file written here: HDF5 root attributes, the JSON entry or the CSV
    sidecar (checked against the file's sha256); {} for files written before it existed."""
    path = Path(path)
    if path.suffix.lower() in (".h5", ".hdf5"):
        with h5py.File(path, "r") as f:
            return {k: _attr(k, f.attrs[k]) for k in PROVENANCE_ATTRS if k in f.attrs}
    if path.suffix.lower() == ".json":
        return read_json(path, keep_provenance=True).get("provenance", {})
    side = provenance_path(path)
    if not side.is_file():
        return {}
    info = json.loads(side.read_text())
    if info.get("sha256") != hashlib.sha256(path.read_bytes()).hexdigest():
        raise ValueError(f"{side} describes another version of {path} (sha256 differs)")
    return info


def write_csv(
    path,
    rows: list[dict],
    columns=None,
    *,
    floats: str = ".6g",
    yes_no: bool = False,
    join_lists: bool = False,
    sources=None,
) -> Path:
    """Write dict rows atomically as CSV ("\n" line ends), then the provenance sidecar
    (:func:`write_provenance_sidecar`; `sources`: the input files).

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
    write_text(path, buf.getvalue())
    write_provenance_sidecar(path, sources)
    return Path(path)


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


def write_table(path, rows: list[dict], columns=None, *, sources=None) -> Path:
    """A measurement table (benchmarks) that :func:`read_table` reads back: floats with 10
    significant digits, booleans yes/no, lists joined by spaces, columns the union of the rows'
    (or `columns`, which an empty table needs)."""
    return write_csv(path, rows, columns, floats=".10g", yes_no=True, join_lists=True, sources=sources)


def read_table(path) -> list[dict]:
    """Rows of a table written by :func:`write_table`; numeric cells become floats."""
    return read_csv(path, numbers=True)


# -------------------------------------------------------------------------- run files


def write_run(
    path, events: dict, attrs: dict, trajectory: dict | None = None, *, sources=None, compress: bool = True
) -> Path:
    """Write events (group -> column -> array), optional trajectory and attributes atomically,
    stamped by :func:`stamp_h5` (`sources`: input files, e.g. the record events came from).
    The trajectory is gzipped unless `compress` is False: for a temporary file read back at
    once, where compressing and decompressing cost more time than the disk space they save."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        for group, columns in events.items():
            g = f.create_group(group)
            for name, values in columns.items():
                g.create_dataset(name, data=np.asarray(values, dtype=float))
        if trajectory is not None:
            g = f.create_group("trajectory")
            for name in ("t", "x", "v"):
                data = np.asarray(trajectory[name], dtype=float)
                g.create_dataset(name, data=data, compression="gzip" if compress else None)
        for key, value in attrs.items():
            f.attrs[key] = value
        stamp_h5(f, sources=sources)
    return path


def read_run(path) -> tuple[dict, dict, dict | None]:
    """(events, attrs, trajectory) of a run file, with or without the format-1 attributes;
    raises FileNotFoundError naming the path."""
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
        attrs = {k: _attr(k, v) for k, v in f.attrs.items()}
    return events, attrs, trajectory
