"""HDF5 run files: the contract between the simulation and every downstream rule.

Layout (stable; measured records written by other tools follow it too):
    impacts/t, impacts/v, penetrations/t, penetrations/h, near_misses/t, near_misses/gap,
    poincare/t, poincare/x, poincare/v, trajectory/t|x|v (only when a window was asked for)
    root attributes: model parameters (param_*), omega, transient, duration, x0, v0, solver,
    rtol, atol, step/RHS counters, wall_time, version, git_commit.
Files are written under a temporary name in the target directory and renamed into place,
so an interrupted job never leaves a file that looks complete.
"""

from __future__ import annotations

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
