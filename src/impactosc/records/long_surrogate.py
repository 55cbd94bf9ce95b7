"""Long surrogate records written chunk by chunk: the model sampled like the rig for as long as a
rig runs (an hour at 50 kHz is 180 M samples) in the memory of one segment.

Why: :func:`impactosc.records.surrogate.surrogate_record` holds the whole simulation and record
in memory, and records that long are what the chunked reader
(:mod:`impactosc.records.streams`) is for.  The model is simulated in segments of whole
forcing periods, each started from the previous segment's end state at forcing phase 0 (as
:func:`impactosc.records.surrogate.surrogate_driven` chains periods), and a segment's samples
are written before the next one is simulated.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from impactosc.core.simulation import Window, end_state, simulate, start_of
from impactosc.io.files import atomic_write, check_writable, stamp_h5
from impactosc.model.parameters import ModelParams
from impactosc.records.surrogate import SurrogateOptions, mismatched_params, sensor_samples
from impactosc.records.surrogate_truth import surrogate_meta

__all__ = ["write_long_surrogate", "read_truth", "SEGMENT_KEYS"]

#: The metadata a long surrogate adds to surrogate_meta's (how its segments were cut).
SEGMENT_KEYS = ("surrogate_segment_periods",)
_H5_CHUNK = 1 << 16  # samples per HDF5 chunk (512 kB of float64)


def _segments(omega, transient, t_end, periods):
    """Forcing-period ranges [a, b) of the runs: the first starts at the last phase 0 at or
    before ``transient``, each holds ``periods`` periods, the last ends at or after ``t_end``."""
    P = 2 * math.pi / omega
    n0 = math.floor(transient / P)
    while n0 > 0 and n0 * P > transient:
        n0 -= 1
    n_end = max(n0 + 1, math.ceil(t_end / P))
    while n_end * P < t_end:
        n_end += 1
    return n0, [(a, min(a + periods, n_end)) for a in range(n0, n_end, periods)]


class _H5Out:
    def __init__(self, tmp, omega, meta, compression):
        import h5py

        self.f = h5py.File(tmp, "w")
        g = self.f.create_group("record")
        opts = dict(shape=(0,), maxshape=(None,), dtype=float, chunks=(_H5_CHUNK,))
        if compression is not None:
            opts.update(compression=compression, shuffle=True)
        self.t, self.x = g.create_dataset("t", **opts), g.create_dataset("x", **opts)
        self.f.attrs["units"] = "m"
        self.f.attrs["omega"] = float(omega)
        for k, v in meta.items():
            self.f.attrs[k] = v

    def write(self, t, x):
        n = self.t.shape[0]
        for ds, data in ((self.t, t), (self.x, x)):
            ds.resize((n + data.size,))
            ds[n:] = data

    def close(self, ok):
        if ok:
            stamp_h5(self.f)
        self.f.close()


class _TdmsOut:
    """One TDMS segment per chunk: channel record/x in m, time from its waveform properties."""

    def __init__(self, tmp, omega, meta, t0, dt):
        from nptdms import TdmsWriter

        self.w = TdmsWriter(tmp)
        self.w.open()
        self.root = {"omega": float(omega), **meta}
        self.props = {"unit_string": "m", "wf_start_offset": float(t0), "wf_increment": float(dt)}
        self.first = True

    def write(self, t, x):
        from nptdms import ChannelObject, GroupObject, RootObject

        if self.first:
            objs = [RootObject(self.root), GroupObject("record"), ChannelObject("record", "x", x, self.props)]
            self.first = False
        else:
            objs = [ChannelObject("record", "x", x)]
        self.w.write_segment(objs)

    def close(self, ok):
        self.w.close()


def _check_arguments(path, truth_path, h5_compression, *, omega, transient, duration, segment) -> None:
    """The errors of :func:`write_long_surrogate`'s arguments, each named, before any work."""
    if path.suffix.lower() not in (".h5", ".hdf5", ".tdms"):
        raise ValueError(f"{path}: a long surrogate is written as .h5 or .tdms, not {path.suffix!r}")
    if h5_compression not in ("gzip", None):
        raise ValueError(f"h5_compression must be 'gzip' or None, got {h5_compression!r}")
    for name, v in (("omega", omega), ("duration", duration), ("segment", segment)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be > 0, got {v}")
    if not (math.isfinite(transient) and transient >= 0):
        raise ValueError(f"transient must be >= 0 s, got {transient}")
    check_writable(path)
    if truth_path is not None:
        check_writable(truth_path)


def write_long_surrogate(
    path,
    omega,
    duration,
    options: SurrogateOptions | None = None,
    *,
    transient=100.0,
    segment=60.0,
    params: ModelParams | None = None,
    x0=0.0,
    v0=0.0,
    rtol=1e-10,
    atol=1e-12,
    truth_path=None,
    h5_compression="gzip",
):
    """Write the surrogate record of the model at ``omega`` on [transient, transient + duration]
    to ``path`` (``.h5``/``.hdf5`` or ``.tdms``), simulated and written in segments of about
    ``segment`` s (whole forcing periods); returns (path, truth).

    The samples are :func:`impactosc.records.surrogate.surrogate_record`'s (same grid
    ``transient + j / rate``, same noise from ``options.seed``, drawn chunk by chunk; the
    chained runs differ from its single run by the solver's tolerance, ~1e-13 m on a periodic
    attractor); with ``drift`` or ``clock_jitter`` on those are drawn chunk by chunk
    (:func:`impactosc.records.surrogate.sensor_samples`).  Metadata: ``surrogate_meta``'s
    plus ``surrogate_segment_periods``.  HDF5: ``record/t``, ``record/x`` (chunked; gzip with
    the shuffle filter, or ``h5_compression=None`` for an uncompressed file as a DAQ writes it);
    TDMS: group ``record``, channel ``x`` (unit m, ``wf_start_offset`` = transient,
    ``wf_increment`` = 1 / rate), one TDMS segment per simulated segment.  Written atomically.

    truth: the exact events, ``impacts`` t, v and ``poincare`` t, x, v (the state at each
    forcing phase 0) in [transient, transient + duration]; also written to ``truth_path``
    (``.npz``, :func:`read_truth`) when given.  Peak memory: one segment's samples (the
    simulation grid is 8 times finer under the anti-aliasing filter).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    omega, transient, duration, segment = float(omega), float(transient), float(duration), float(segment)
    _check_arguments(
        path, truth_path, h5_compression, omega=omega, transient=transient, duration=duration, segment=segment
    )
    o = options or SurrogateOptions()
    p = mismatched_params(params, o.mismatch)
    P = 2 * math.pi / omega
    periods = max(1, round(segment / P))
    k = o.oversample
    dt = 1.0 / (o.rate * k)  # the simulation grid; samples every k-th point
    t_end = transient + duration
    n_fine = Window(transient, t_end, dt).n
    meta = surrogate_meta(o, p, {"surrogate_segment_periods": int(periods)})
    solver = dict(params=p, rtol=rtol, atol=atol)
    n0, segments = _segments(omega, transient, t_end, periods)
    start = np.array([x0, v0], float)  # each segment's, with a restitution contact's onset velocity inside one
    if n0 > 0:
        start = end_state(simulate(omega, 0.0, n0 * P, **start_of(start), record=(), **solver))

    def first_point(t):  # index of the first grid point transient + j dt at or after t
        return min(n_fine, max(0, math.ceil((t - transient) / dt - 1e-9)))

    rng, state = np.random.default_rng(o.seed), {}
    truth = {"impacts": {"t": [], "v": []}, "poincare": {"t": [], "x": [], "v": []}}
    if n0 > 0:  # the phase-0 state the first segment starts from (a run's own start is not a point)
        truth["poincare"] = {"t": [n0 * P], "x": [float(start[0])], "v": [float(start[1])]}
    held = np.empty(0), np.empty(0), np.empty(0), 0  # fine points not yet sampled: x, v, t, first index

    def emit(out, x, v, j0, final):
        """Sample the fine points from index j0 (a multiple of k); keep back an incomplete group."""
        hx, hv, _, hj = held
        x, v, j0 = np.concatenate((hx, x)), np.concatenate((hv, v)), hj if hx.size else j0
        m = x.size if final else (x.size // k) * k
        if m:
            t = transient + dt * np.arange(j0, j0 + m)
            y = sensor_samples({"t": t, "x": x[:m], "v": v[:m]}, o, rng, state)
            out.write(t[::k], y)
        return x[m:], v[m:], None, j0 + m

    with atomic_write(path) as tmp:
        if suffix == ".tdms":
            out = _TdmsOut(tmp, omega, meta, transient, 1.0 / o.rate)
        else:
            out = _H5Out(tmp, omega, meta, h5_compression)
        ok = False
        try:
            for i, (a, b) in enumerate(segments):
                Ta, L = a * P, (b - a) * P
                js, je = first_point(Ta), first_point(b * P)
                win = None
                if je > js:
                    s0 = max(transient + js * dt - Ta, 0.0)
                    win = Window(s0, min(s0 + (je - js - 0.5) * dt, L), dt)
                res = simulate(omega, 0.0, L, **start_of(start), window=win, record=("impacts", "poincare"), **solver)
                start = end_state(res)
                for kind, cols in (("impacts", ("t", "v")), ("poincare", ("t", "x", "v"))):
                    ev = res.events[kind]
                    truth[kind]["t"].append(Ta + ev["t"])
                    for c in cols[1:]:
                        truth[kind][c].append(ev[c])
                if win is not None:
                    traj = res.trajectory
                    held = emit(out, traj["x"][: je - js], traj["v"][: je - js], js, i == len(segments) - 1)
                elif i == len(segments) - 1:
                    held = emit(out, np.empty(0), np.empty(0), held[3], True)
            ok = True
        finally:
            out.close(ok)
    truth = _truth_within(truth, transient, t_end)
    if truth_path is not None:
        _write_truth(truth_path, truth, omega=omega, transient=transient, duration=duration)
    return path, truth


def _truth_within(truth, transient, t_end) -> dict:
    """The exact events gathered per segment, joined, on [transient, t_end]."""
    out = {}
    for kind in truth:
        cols = {
            c: np.concatenate([np.atleast_1d(np.asarray(v, dtype=float)) for v in vs]) for c, vs in truth[kind].items()
        }
        keep = (cols["t"] >= transient) & (cols["t"] <= t_end)
        out[kind] = {c: v[keep] for c, v in cols.items()}
    return out


def _write_truth(truth_path, truth, **settings) -> None:
    """The truth as an .npz (``impacts_t``, ``poincare_x``, ... and the settings), atomically."""
    with atomic_write(truth_path) as tmp, open(tmp, "wb") as f:
        flat = {f"{kind}_{c}": v for kind, cols in truth.items() for c, v in cols.items()}
        np.savez(f, **settings, **flat)


def read_truth(path) -> dict:
    """The truth :func:`write_long_surrogate` wrote: {"impacts": {t, v}, "poincare": {t, x, v}}."""
    with np.load(path) as z:
        out = {}
        for key in z.files:
            kind, _, col = key.partition("_")
            if col:
                out.setdefault(kind, {})[col] = z[key]
        return out
