"""HDF5 records: the datasets ``record/t``, ``record/x`` (and ``record/phase``) and the root's
attributes as metadata (format: :mod:`impactosc.records.formats`).

Why a module: the datasets are read by slices, so that a long record is read in chunks
(:mod:`impactosc.records.streams`) by the same code that reads it whole.
"""

from __future__ import annotations

import h5py

from impactosc.io.files import PROVENANCE_ATTRS

__all__ = ["H5Source", "attrs_meta"]


def attrs_meta(attrs) -> dict:
    """HDF5 attributes as record metadata: strings decoded, numpy scalars as Python ones, the
    provenance attributes left out (they describe the file, not the record)."""
    return {
        k: (v.decode() if isinstance(v, bytes) else (v.item() if hasattr(v, "item") else v))
        for k, v in attrs.items()
        if k not in PROVENANCE_ATTRS
    }


class H5Source:
    """An HDF5 record's metadata and shapes, read on opening, and its samples by slices."""

    random_access = True
    validated = False

    def __init__(self, path, *, units, omega):
        self.path = path
        self.source = source = str(path)
        self._file = f = h5py.File(path, "r")
        try:
            if "record" not in f or "t" not in f["record"] or "x" not in f["record"]:
                raise ValueError(f"{source}: no record/t and record/x datasets; not a record file")
            g = f["record"]
            self._t, self._x = g["t"], g["x"]
            self._phase = g.get("phase")
            self.meta = attrs_meta(f.attrs)
            if self._phase is not None:
                self.meta.setdefault("phase_units", "rad")
            if self._t.ndim != 1 or self._t.shape != self._x.shape:
                raise ValueError(
                    f"{source}: t and x must be 1-D of equal length, got {self._t.shape} and {self._x.shape}"
                )
            self.n = self._t.shape[0]
            if self._phase is not None and self._phase.shape != (self.n,):
                raise ValueError(f"{source}: phase has {self._phase.size} samples, the displacement {self.n}")
        except BaseException:
            f.close()
            raise
        self.has_phase = self._phase is not None
        self.header_options = dict(units=units, omega=omega, phase_units=None, counts_per_rev=None)

    def blocks(self, start, stop, size, phase_only=False):
        """(t, x, phase or None, None) of the samples [start, stop) in slices of ``size``
        (``phase_only``: (None, None, phase, None))."""
        for a in range(start, stop, size):
            b = min(a + size, stop)
            phase = self._phase[a:b] if self._phase is not None else None
            if phase_only:
                yield None, None, phase, None
            else:
                yield self._t[a:b], self._x[a:b], phase, None

    def close(self):
        self._file.close()
