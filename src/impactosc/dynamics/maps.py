"""2-D maps: the reading of a sweep in w repeated for each value of a second parameter.

Why: a map is computed in row chunks (one continuation in w per parameter value,
:func:`impactosc.dynamics.sweep.parameter_rows`), each chunk classified
(:func:`impactosc.dynamics.diagram.classify_sweep`) and saved as a small HDF5 file by
its own job, then merged. This module holds the map, its file and the merge.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import h5py
import numpy as np

from impactosc.io.files import atomic_write, check_writable, stamp_h5

if TYPE_CHECKING:  # annotations only
    from impactosc.dynamics.diagram import BranchTable

__all__ = ["MapResult", "save_map", "load_map", "merge_maps"]


@dataclass
class MapResult:
    """Reading of a 2-D map: rows are parameter values, columns w (increasing along a row).

    period, impacts, rate, n_isi_levels: (n_values, n_w) as in BranchTable.
    """

    parameter: str
    values: np.ndarray
    omega: np.ndarray
    period: np.ndarray
    impacts: np.ndarray
    rate: np.ndarray
    n_isi_levels: np.ndarray
    wall_time: float = 0.0

    @classmethod
    def from_tables(cls, parameter: str, values, tables: list[BranchTable], wall_time: float = 0.0) -> MapResult:
        if not tables:
            raise ValueError("a map needs at least one row")
        return cls(
            parameter,
            np.asarray(values, dtype=float),
            tables[0].omega.copy(),
            *(np.vstack([getattr(t, k) for t in tables]) for k in ("period", "impacts", "rate", "n_isi_levels")),
            wall_time=float(wall_time),
        )


_MAP_ARRAYS = ("values", "omega", "period", "impacts", "rate", "n_isi_levels")
#: Unit of the dataset ``values`` by map parameter (obstacle position, forcing amplitude m0 e).
VALUE_UNITS = {"xI": "m", "m0e": "kg m"}


def save_map(path, m: MapResult, *, sources=None, **attrs) -> None:
    """Write a map (or a chunk of its rows) to HDF5 atomically, with units and provenance
    (`sources`: input files); a parameter missing from VALUE_UNITS is refused."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        for k in _MAP_ARRAYS:
            f.create_dataset(k, data=getattr(m, k))
        f.attrs["parameter"] = m.parameter
        f.attrs["wall_time"] = m.wall_time
        for k, v in attrs.items():
            f.attrs[k] = v
        unit = VALUE_UNITS.get(m.parameter)
        stamp_h5(f, sources=sources, units={"values": unit} if unit else None)


def load_map(path) -> MapResult:
    """Read a map (or a chunk of its rows) written by :func:`save_map`."""
    with h5py.File(path, "r") as f:
        arrays = {k: f[k][()] for k in _MAP_ARRAYS}
        return MapResult(parameter=str(f.attrs["parameter"]), wall_time=float(f.attrs["wall_time"]), **arrays)


def merge_maps(parts: list[MapResult]) -> MapResult:
    """Stack row chunks (in row order) into one map."""
    if not parts:
        raise ValueError("no map chunks to merge")
    for p in parts[1:]:
        if p.parameter != parts[0].parameter or not np.array_equal(p.omega, parts[0].omega):
            raise ValueError("map chunks differ in parameter or w grid")
    return MapResult(
        parts[0].parameter,
        np.concatenate([p.values for p in parts]),
        parts[0].omega.copy(),
        *(np.vstack([getattr(p, k) for p in parts]) for k in ("period", "impacts", "rate", "n_isi_levels")),
        wall_time=float(sum(p.wall_time for p in parts)),
    )
