"""Slow sweeps: one record whose forcing frequency drifts (a whole experimental bifurcation
diagram in one file), cut into quasi-stationary segments by the measured w.

Why: the paper's experimental Fig 2 is a slow sweep of w, and a rig records it in one go --
one long file whose motor speed is ramped (or stepped), not one file per w.  The w that
matters is the one the encoder measured, not the one the speed controller was asked for.

Method
------
* Poincare points where the encoder's phase crosses 2 pi i, each with the w measured around
  it (:func:`impactosc.records.poincare.phase_crossings`): w(t) comes from the record.
* Bins of width ``bin_width`` centred on its multiples: a point belongs to bin
  k = round(w_i / bin_width), with hysteresis -- the current bin is left only when w_i is
  more than (1/2 + ``edge_hysteresis``) bin widths from its centre, so noise in the measured w
  at a bin edge cannot chop the record into slivers.
* A segment is a run of consecutive points in one bin (a sweep up and then down gives two
  segments per bin, kept apart: they show the diagram's hysteresis).  Its first ``settle``
  seconds are discarded: after a step of w the motion needs a few relaxation times (about
  2.6 s for model BC's damping alone) to reach the new attractor, and on a ramp it lags
  behind.  Segments left with fewer than ``min_points`` points are dropped.
* Each kept point is reported at its segment's w (the median of its points' measured w), so
  the panel shows one column per segment like a stepped experiment; the point's own w
  (``point_omega``) and each segment's spread of w (``omega_spread``, how stationary it was)
  are kept too.

Measured on the surrogate ramp 20 -> 45 rad/s in 2500 s (0.01 rad/s^2, 2 kHz, 5 um noise,
4096-count encoder, bins 0.25 rad/s, settle 10 s; 100 segments): a segment's median point
lies within 6 um (median 1.8 um) of the model's attractor at the segment's w on the flat
parts of the period-1 branch, within 17 um on period 2 away from the doublings, but up to
45 um on the steep part of the period-1 branch (24.5-27 rad/s, 5 mm per rad/s): the lag
behind the ramp, slope x dw/dt x 0.9 s; it halves with the ramp rate.  Within ~0.3 rad/s
after a bifurcation the sweep still follows the old, now unstable, orbit (bifurcation delay:
1.4 mm off at 37.57 rad/s) -- a property of sweeping that a rig's sweep shares.

The result has the layout of the Fig 2 experimental panel (``omega``, ``x``; see
:func:`impactosc.records.poincare.record_set_poincare`) plus the segment datasets.
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.io.files import atomic_write, check_writable, stamp_h5
from impactosc.model.parameters import ParameterError
from impactosc.records.poincare import poincare_points, stream_poincare_points
from impactosc.records.record import Record

__all__ = ["sweep_segments", "write_sweep_points"]

#: Narrowest w bin, rad/s. Why: a point's bin index w / width must stay an exact integer (below
#: 2^53) for any w below 9e6 rad/s; far narrower than the w a forcing period's noise measures.
MIN_BIN_WIDTH = 1e-9


def _bins(w, bin_width, edge_hysteresis):
    """Bin index of each point, with hysteresis at the edges (see the module docstring)."""
    out = np.empty(w.size, dtype=np.int64)
    if not w.size:
        return out
    reach = (0.5 + edge_hysteresis) * bin_width
    k = round(w[0] / bin_width)
    for j, wj in enumerate(w.tolist()):
        if abs(wj - k * bin_width) > reach:
            k = round(wj / bin_width)
        out[j] = k
    return out


def sweep_segments(
    rec, bin_width: float, settle: float, *, min_points: int = 5, edge_hysteresis: float = 0.1
) -> tuple[dict, dict]:
    """Cut a slow-sweep record into segments of quasi-constant measured w.

    ``rec``: a :class:`Record`, or a :class:`impactosc.records.streams.RecordStream` read in
    chunks (the same points, memory bounded whatever the record's length).

    ``bin_width`` (rad/s): width of the w bins; ``settle`` (s): time discarded at the start of
    each segment (and of the record); ``min_points``: fewest Poincare points a kept segment
    has.  Returns (points, info): points holds per point ``omega`` (the segment's w), ``x``,
    ``t``, ``point_omega`` and per segment ``record_omega``, ``n_points``, ``segment_start``,
    ``segment_stop`` (time of its first and last kept point), ``omega_spread``; info holds
    the counts of segments kept and dropped and of points discarded while settling.
    """
    streamed = not isinstance(rec, Record)
    if (not rec.has_phase) if streamed else rec.phase is None:
        raise ValueError(
            f"{rec.path}: a sweep record needs a phase (encoder) channel: w(t) is measured from it "
            "(name it with phase_channel / --phase-channel)"
        )
    if not (math.isfinite(bin_width) and bin_width >= MIN_BIN_WIDTH):
        raise ParameterError("bin_width", f"bin width must be >= {MIN_BIN_WIDTH:g} rad/s, got {bin_width}")
    if not (math.isfinite(settle) and settle >= 0):
        raise ParameterError("settle", f"settle must be >= 0 s, got {settle}")
    if not (0 <= edge_hysteresis < 0.5):
        raise ValueError(f"edge_hysteresis must be in [0, 0.5) bin widths, got {edge_hysteresis}")
    if min_points < 1:
        raise ParameterError("min_points", f"min_points must be >= 1, got {min_points}")
    p = stream_poincare_points(rec, "encoder") if streamed else poincare_points(rec, source="encoder")
    t_first = rec.t0 if streamed else rec.t[0]
    t, x, w = p["t"], p["x"], p["omega"]
    b = _bins(w, bin_width, edge_hysteresis)
    starts = np.flatnonzero(np.diff(b, prepend=b[:1] - 1)) if b.size else np.empty(0, int)
    stops = np.append(starts[1:], b.size)
    out = {k: [] for k in ("omega", "x", "t", "point_omega")}
    seg = {k: [] for k in ("record_omega", "n_points", "segment_start", "segment_stop", "omega_spread")}
    n_short = n_settling = 0
    for a, z in zip(starts.tolist(), stops.tolist()):
        t_enter = t_first if a == 0 else t[a]
        keep = np.arange(a, z)[t[a:z] >= t_enter + settle]
        n_settling += (z - a) - keep.size
        if keep.size < min_points:
            n_short += 1
            continue
        wk = float(np.median(w[keep]))
        out["omega"].append(np.full(keep.size, wk))
        out["x"].append(x[keep])
        out["t"].append(t[keep])
        out["point_omega"].append(w[keep])
        seg["record_omega"].append(wk)
        seg["n_points"].append(keep.size)
        seg["segment_start"].append(t[keep[0]])
        seg["segment_stop"].append(t[keep[-1]])
        seg["omega_spread"].append(float(np.ptp(w[keep])))
    if not seg["record_omega"]:
        span = f", measured w {np.min(w):.4g}..{np.max(w):.4g} rad/s" if w.size else ""
        raise ValueError(
            f"{rec.path}: no segment of w bins {bin_width:g} rad/s wide holds {min_points} Poincare points "
            f"after {settle:g} s of settling ({t.size} points{span}); widen the bins or shorten the settling"
        )
    points = {k: np.concatenate(v) for k, v in out.items()}
    points.update({k: np.asarray(v) for k, v in seg.items()})
    info = {
        "n_segments": len(seg["record_omega"]),
        "n_segments_dropped": n_short,
        "n_points_settling": n_settling,
        "n_points_total": int(t.size),
        "bin_width": float(bin_width),
        "settle": float(settle),
        "min_points": int(min_points),
        "edge_hysteresis": float(edge_hysteresis),
        "omega_measured_min": float(np.min(w)),
        "omega_measured_max": float(np.max(w)),
    }
    return points, info


def write_sweep_points(path, points: dict, info: dict, *, label: str, sources=None) -> None:
    """Write the segment Poincare points (the Fig 2 experimental panel's ``omega``, ``x`` and
    the segment datasets) to HDF5, atomically, with units, the settings and provenance."""
    path = check_writable(path)
    with atomic_write(path) as tmp:
        import h5py

        with h5py.File(tmp, "w") as f:
            for k, v in points.items():
                f.create_dataset(k, data=v)
            f.attrs["label"] = label
            f.attrs["poincare_phase_source"] = "encoder"
            f.attrs["method"] = "slow-sweep record cut into segments of quasi-constant measured w"
            for k, v in info.items():
                f.attrs[k] = v
            stamp_h5(f, sources=sources)
