"""Poincare points of a measured record: at the crossings of 2 pi i by the measured forcing phase
(an encoder on the unbalance), else at the nominal t_i = 2 pi i / omega.

Why a module: the rig's motor speed is not exactly nominal, so the section of a record is
found on its own phase channel, where it has one; the points of one record make the model's
``poincare`` dataset (:func:`impactosc.records.extract.extract_events`), those of a record set
the experimental panel of Fig 2 (:func:`record_set_poincare`), and the phase crossings cut a
slow-sweep record by its measured w (:mod:`impactosc.records.slow_sweep`).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.records.record import Record

__all__ = [
    "phase_crossings",
    "poincare_points",
    "poincare_between",
    "poincare_margin",
    "stream_poincare_points",
    "poincare_phase_source",
    "poincare_attrs",
    "record_set_poincare",
]

#: Samples either side of a phase crossing in its straight-line fit.  Why 10: the fit
#: averages the encoder's quantization (one count, 1.5 mrad at 4096 per revolution) over 20
#: samples, while w changes by less than 1e-4 of itself in those 10 ms at 2 kHz.
PHASE_FIT_HALF = 10


def phase_crossings(t, phase, half: int = PHASE_FIT_HALF) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where a measured (unwrapped, advancing) phase crosses 2 pi i: (i, t_i, w_i).

    t_i: root of a least-squares line through the ``2 half`` samples around the crossing
    (the first sample at or past 2 pi i, found on the running maximum, so noise cannot
    make a crossing twice); w_i: 4 pi / (t_(i+1) - t_(i-1)), the mean forcing frequency
    over the two periods around t_i (one period at the ends; the line's slope when the
    record holds a single crossing).
    """
    t = np.asarray(t, dtype=float)
    phase = np.asarray(phase, dtype=float)
    two_pi = 2 * math.pi
    i = np.arange(math.ceil(phase[0] / two_pi), math.floor(phase[-1] / two_pi) + 1)
    if i.size == 0:
        return i, np.empty(0), np.empty(0)
    level = two_pi * i
    k = np.searchsorted(np.maximum.accumulate(phase), level, side="left")
    width = min(2 * half, t.size)
    lo = np.clip(k - width // 2, 0, t.size - width)
    idx = lo[:, None] + np.arange(width)
    s = t[idx] - t[k][:, None]  # local time, and the phase relative to the level: no cancellation
    y = phase[idx] - level[:, None]
    sm, ym = s.mean(axis=1), y.mean(axis=1)
    slope = ((s - sm[:, None]) * (y - ym[:, None])).sum(axis=1) / ((s - sm[:, None]) ** 2).sum(axis=1)
    tc = t[k] + sm - ym / slope
    if tc.size >= 3:
        w = np.empty(tc.size)
        w[1:-1] = 2 * two_pi / (tc[2:] - tc[:-2])
        w[0], w[-1] = two_pi / (tc[1] - tc[0]), two_pi / (tc[-1] - tc[-2])
    elif tc.size == 2:
        w = np.full(2, two_pi / (tc[1] - tc[0]))
    else:
        w = slope
    return i, tc, w


def poincare_phase_source(rec: Record, source: str = "auto") -> str:
    """Which phase the Poincare points of ``rec`` are taken at: "encoder" (the measured
    phase) or "nominal omega" (t_i = 2 pi i / omega); ``source`` "auto" prefers the encoder."""
    if source not in ("auto", "encoder", "nominal"):
        raise ValueError(f"Poincare source must be auto, encoder or nominal, got {source!r}")
    if source == "encoder" or (source == "auto" and rec.phase is not None):
        if rec.phase is None:
            raise ValueError(f"{rec.path}: no phase channel; the encoder's Poincare points need one")
        return "encoder"
    if rec.omega is None:
        raise ValueError(
            f"{rec.path}: no omega and no phase channel; Poincare points need the forcing frequency or phase"
        )
    return "nominal omega"


def poincare_points(rec: Record, half=3, source: str = "auto") -> dict:
    """Poincare points t, x, v of a record (local quadratic fits), at the crossings of 2 pi i
    by the measured phase (then also ``omega``, w measured there; :func:`phase_crossings`) or
    at t_i = 2 pi i / omega; ``source`` as :func:`poincare_phase_source`."""
    how = poincare_phase_source(rec, source)
    out = {}
    if how == "encoder":
        _, tp, w = phase_crossings(rec.t, rec.phase)
        keep = (tp >= rec.t[0]) & (tp <= rec.t[-1])  # a line fit at the record's edge may land outside
        tp, out["omega"] = tp[keep], w[keep]
    else:
        period = 2 * math.pi / rec.omega
        i0, i1 = math.ceil(rec.t[0] / period), math.floor(rec.t[-1] / period)
        tp = np.arange(i0, i1 + 1) * period
    xs, vs = _smoothed_between(rec.t, rec.x, tp, half, rec.dt)
    return {"t": tp, "x": xs, "v": vs, **out}


def _smoothed_between(t, x, tp, half, dt):
    """x and v of the local quadratic (Savitzky-Golay, 2 half + 1 samples) interpolated to the
    times tp: the filter evaluated only at the two samples around each tp (one section per
    forcing period: filtering every sample cost a third of extraction), its edge fits at the
    record's ends as savgol_filter makes them."""
    from scipy.signal import savgol_coeffs, savgol_filter

    win = 2 * half + 1
    if x.size < 2 * win:
        xs, vs = savgol_filter(x, win, 2), savgol_filter(x, win, 2, deriv=1, delta=dt)
        return np.interp(tp, t, xs), np.interp(tp, t, vs)
    k = np.clip(np.searchsorted(t, tp, side="right") - 1, 0, x.size - 2)
    idx = np.concatenate([k, k + 1])
    xs, vs = np.empty(idx.size), np.empty(idx.size)
    inner = (idx >= half) & (idx < x.size - half)
    rows = x[idx[inner][:, None] + np.arange(-half, half + 1)]
    xs[inner] = rows @ savgol_coeffs(win, 2, use="dot")
    vs[inner] = rows @ savgol_coeffs(win, 2, deriv=1, delta=dt, use="dot")
    # the record's first and last half samples: the polynomial fit to its first or last win samples
    for edge, part in ((idx < half, slice(0, 2 * win)), (idx >= x.size - half, slice(x.size - 2 * win, x.size))):
        if edge.any():
            xs[edge] = savgol_filter(x[part], win, 2)[idx[edge] - part.start]
            vs[edge] = savgol_filter(x[part], win, 2, deriv=1, delta=dt)[idx[edge] - part.start]
    f = (tp - t[k]) / (t[k + 1] - t[k])
    m = k.size
    return xs[:m] + f * (xs[m:] - xs[:m]), vs[:m] + f * (vs[m:] - vs[:m])


def poincare_between(rec: Record, lo: float, hi: float, source: str = "auto") -> dict:
    """The Poincare points of ``rec`` with lo <= t < hi (one buffer of a record read in chunks:
    the points whose fits, and w's neighbouring crossings, lie inside it)."""
    p = poincare_points(rec, source=source)
    inside = (p["t"] >= lo) & (p["t"] < hi)
    return {k: v[inside] for k, v in p.items()}


def poincare_margin(rec: Record) -> int:
    """Samples a section's Poincare point reaches out on either side: its w from the
    neighbouring crossings (a forcing period each way, three at the slowest w of ``rec``'s end)
    and the fits around them."""
    rate = 1.0 / rec.dt
    if rec.phase is not None and rec.t.size > 1:
        half = rec.t.size // 2
        turns = (rec.phase[-1] - rec.phase[half]) / (2 * math.pi)
        period = (rec.t[-1] - rec.t[half]) / turns if turns > 0 else rec.t[-1] - rec.t[0]
    elif rec.omega is not None:
        period = 2 * math.pi / rec.omega
    else:
        return 0
    return int(3 * period * rate) + 2 * PHASE_FIT_HALF + 8


def stream_poincare_points(stream, source: str = "auto", chunk_samples: int = 1 << 20) -> dict:
    """:func:`poincare_points` of a record read in chunks (a
    :class:`impactosc.records.streams.RecordStream`): memory bounded by the chunk and the
    margin each point needs (:func:`poincare_margin`), the same points as the whole record's."""
    parts, carry, done = [], None, -math.inf
    chunks = stream.chunks(chunk_samples)
    chunk = next(chunks, None)
    while chunk is not None:
        following = next(chunks, None)
        t, x, phase = chunk.t, chunk.x, chunk.phase
        if carry is not None:
            t, x = np.concatenate([carry[0], t]), np.concatenate([carry[1], x])
            phase = None if phase is None else np.concatenate([carry[2], phase])
        rec = Record(t, x, stream.omega, stream.meta, stream.path, phase)
        margin = poincare_margin(rec)
        final = following is None
        end = t.size if final else max(t.size - margin, 0)
        hi = math.inf if final else (t[end] if end < t.size else t[-1])
        if final or hi > done:
            parts.append(poincare_between(rec, done, hi, source))
            done = max(done, hi)
        k = max(end - margin, 0)
        carry = (t[k:], x[k:], None if phase is None else phase[k:])
        chunk = following
    keys = parts[0].keys() if parts else ("t", "x", "v")
    return {key: np.concatenate([p[key] for p in parts]) if parts else np.empty(0) for key in keys}


def poincare_attrs(rec: Record, points: dict) -> dict:
    """Attributes saying where the Poincare points were taken (and w measured by the encoder)."""
    how = poincare_phase_source(rec)
    attrs = {"poincare_phase_source": how}
    w = points.get("omega")
    if how == "encoder" and w is not None and w.size:
        attrs.update(
            omega_measured_median=float(np.median(w)),
            omega_measured_min=float(np.min(w)),
            omega_measured_max=float(np.max(w)),
        )
        if rec.omega is None:
            attrs["omega"] = float(np.median(w))
            attrs["omega_source"] = "encoder (median of the measured w)"
    return attrs


def record_set_poincare(records) -> dict:
    """Flat Poincare diagram of a bifurcation experiment (one record per w).

    Returns ``omega`` and ``x`` (one row per Poincare point, the format of the Fig 2
    experimental panel) and per record ``record_omega`` and ``n_points``.
    """
    w, x, rw, n = [], [], [], []
    for rec in records:
        p = poincare_points(rec)
        w.append(np.full(p["x"].size, rec.omega))
        x.append(p["x"])
        rw.append(rec.omega)
        n.append(p["x"].size)
    return {
        "omega": np.concatenate(w),
        "x": np.concatenate(x),
        "record_omega": np.asarray(rw),
        "n_points": np.asarray(n),
    }
