"""Cutting records into the windows of multiple shooting, with the forcing's phase of each.

Why windows: on a chaotic attractor (lambda1 = 2.7 /s at w = 40.86) a single trajectory fitted
to a minute of record is hopeless: an error of a micrometre at the start is a millimetre a few
seconds later.  Each window (a few forcing periods) gets its own initial state (x0, v0), fitted
with the parameters, so the core integrates only as far as the record pins the trajectory.

Window starts are placed in free flight where the cart moves fast (the largest |v| of the
smoothed record near each nominal boundary, at least ``margin`` below the obstacle): there the
start state is smooth in the parameters (no contact, no friction switch at v = 0) and its first
guess from a local polynomial is good.

The forcing's phase: with an encoder channel, each window's phase is a straight line fitted to
the encoder samples of the window, phase = w_j (t - t_start) + a_j, and the window is integrated
in the model's time tau = t - t_start + a_j / w_j at the constant w_j (the core's forcing has a
constant w).  Where the motor's speed varies within a window so that its phase bends away from
the line by more than PHASE_TOL, the window is halved (its halves keep their own lines).  Without one, tau = t and w is the record's omega.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactosc.records.record import check_motion

__all__ = ["WindowSet", "check_forcing_phase", "check_records_move", "cut_windows", "split_held_out"]

#: Largest deviation (rad) of a window's encoder phase from its straight line: a window whose
#: phase bends more (the motor's speed varies within it) is halved until it does not.  A phase
#: error d phi moves the forcing by (m0e/m) w^2 d phi, about 3.5e-4 m/s^2 at 1e-4 rad on model BC,
#: a displacement of some 0.2 um over a forcing period: below the noise of a sample.
PHASE_TOL = 1e-4
#: Windows are not halved below this many samples.
_MIN_SAMPLES = 16
#: Local polynomial for the first guess of a window's state: degree and half width (s).
_GUESS_DEGREE = 3
_GUESS_HALF = 4e-3


@dataclass
class WindowSet:
    """Windows of one or several records; samples of all windows concatenated in ``y``.

    record, start, n: record index, first sample and number of samples of each window;
    tau0, dt, omega: model time of the first sample, sample interval and forcing frequency of
    each window; offset: where each window's samples begin in y; x0, v0: first guesses of the
    start states; labels: the records' labels.
    """

    record: np.ndarray
    start: np.ndarray
    n: np.ndarray
    tau0: np.ndarray
    dt: np.ndarray
    omega: np.ndarray
    offset: np.ndarray
    y: np.ndarray
    x0: np.ndarray
    v0: np.ndarray
    labels: list

    @property
    def size(self) -> int:
        return int(self.start.size)

    def samples(self, j: int) -> np.ndarray:
        return self.y[self.offset[j] : self.offset[j] + self.n[j]]

    def subset(self, keep) -> WindowSet:
        """The windows selected by the index array or mask ``keep``."""
        keep = np.flatnonzero(keep) if np.asarray(keep).dtype == bool else np.asarray(keep, dtype=int)
        ys = [self.samples(j) for j in keep]
        n = np.array([a.size for a in ys], dtype=int)
        return WindowSet(
            self.record[keep],
            self.start[keep],
            n,
            self.tau0[keep],
            self.dt[keep],
            self.omega[keep],
            np.concatenate([[0], np.cumsum(n)[:-1]]).astype(int),
            np.concatenate(ys) if ys else np.empty(0),
            self.x0[keep],
            self.v0[keep],
            self.labels,
        )


def _local_state(t, x, i, half):
    """x and v at sample i from a cubic least-squares fit over +-half samples (a first guess)."""
    lo, hi = max(0, i - half), min(x.size, i + half + 1)
    s = t[lo:hi] - t[i]
    c = np.polynomial.polynomial.polyfit(s, x[lo:hi], _GUESS_DEGREE)
    return float(c[0]), float(c[1])


def _boundaries(t, x, length, level, half):
    """Window starts: near every multiple of ``length`` samples, the fastest free-flight sample."""
    from scipy.signal import savgol_filter

    v = savgol_filter(x, 2 * half + 1, 3, deriv=1, delta=float(t[1] - t[0]))
    xs = savgol_filter(x, 2 * half + 1, 3)
    starts = []
    reach = max(1, length // 4)
    for nominal in range(half, x.size - length // 2, length):
        lo, hi = max(half, nominal - reach), min(x.size - half, nominal + reach)
        if starts and lo <= starts[-1] + length // 2:
            lo = starts[-1] + length // 2
        if hi <= lo:
            continue
        speed = np.where(xs[lo:hi] < level, np.abs(v[lo:hi]), -1.0)
        k = int(np.argmax(speed))
        if speed[k] > 0:
            starts.append(lo + k)
    return starts


def _straight_phase(t, phase, a, b):
    """[a, b) halved until each piece's phase is a straight line within PHASE_TOL.

    The bend is measured between a fitted parabola and the fitted line, not sample by sample:
    an encoder's counts are steps of 2 pi / N (1.5e-3 rad at 4096 counts per revolution) that
    the line averages out, but a varying speed is a curvature the parabola sees.
    """
    s = t[a:b] - t[a]
    bend = np.max(np.abs(np.polyval(np.polyfit(s, phase[a:b], 2), s) - np.polyval(np.polyfit(s, phase[a:b], 1), s)))
    if bend <= PHASE_TOL or b - a < 2 * _MIN_SAMPLES:
        return [(a, b)]
    mid = (a + b) // 2
    return _straight_phase(t, phase, a, mid) + _straight_phase(t, phase, mid, b)


def check_forcing_phase(records) -> None:
    """Every record needs the forcing's phase: an encoder channel, or omega with t = 0 at phase 0."""
    for rec in records:
        if rec.omega is None and rec.phase is None:
            raise ValueError(
                f"{rec.path}: neither omega nor an encoder phase; identification needs the forcing's phase "
                "(declare omega, with t = 0 at the forcing's phase 0, or give the phase channel)"
            )


def check_records_move(records) -> None:
    """Every record moves: one whose x is constant has nothing to identify (and would be
    refused as too short for a window, which it is not)."""
    for rec in records:
        if rec.x.size:
            check_motion(rec.path, float(np.min(rec.x)), float(np.max(rec.x)), "identify")


def cut_windows(records, *, periods: float = 2.0, level: float, margin: float = 50e-6) -> WindowSet:
    """Windows of about ``periods`` forcing periods over every record.

    level : the obstacle's first estimate (m); window starts lie ``margin`` below it.
    Each record needs its forcing phase: an encoder channel (``phase``) or ``omega``.
    """
    if not periods > 0:
        raise ValueError(f"window length must be > 0 forcing periods, got {periods}")
    cols = {k: [] for k in ("record", "start", "n", "tau0", "dt", "omega", "x0", "v0")}
    ys = []
    check_forcing_phase(records)
    check_records_move(records)
    for r, rec in enumerate(records):
        t, x = rec.t, rec.x
        dt = float(np.median(np.diff(t)))
        w_nominal = rec.omega if rec.omega is not None else float(np.polyfit(t, rec.phase, 1)[0])
        length = max(8, int(round(periods * 2 * math.pi / w_nominal / dt)))
        half = max(3, int(round(_GUESS_HALF / dt)))
        starts = _boundaries(t, x, length, level - margin, half)
        ends = [*starts[1:], min(x.size, starts[-1] + length)] if starts else []
        pieces = [(a, b) for a, b in zip(starts, ends) if b - a >= length // 2]
        if rec.phase is not None:
            pieces = [p for a, b in pieces for p in _straight_phase(t, rec.phase, a, b)]
        for a, b in pieces:
            x0, v0 = _local_state(t, x, a, half)
            if rec.phase is not None:
                w, c = np.polyfit(t[a:b] - t[a], rec.phase[a:b], 1)
                tau0 = c / w
            else:
                w, tau0 = rec.omega, t[a]
            for k, val in (("record", r), ("start", a), ("n", b - a), ("tau0", tau0), ("dt", dt), ("omega", w)):
                cols[k].append(val)
            cols["x0"].append(x0)
            cols["v0"].append(v0)
            ys.append(x[a:b])
    if not ys:
        raise ValueError("the records are too short for one identification window; give longer records")
    n = np.array(cols["n"], dtype=int)
    return WindowSet(
        np.array(cols["record"], dtype=int),
        np.array(cols["start"], dtype=int),
        n,
        np.array(cols["tau0"], dtype=float),
        np.array(cols["dt"], dtype=float),
        np.array(cols["omega"], dtype=float),
        np.concatenate([[0], np.cumsum(n)[:-1]]).astype(int),
        np.concatenate(ys),
        np.array(cols["x0"], dtype=float),
        np.array(cols["v0"], dtype=float),
        [rec.label for rec in records],
    )


def split_held_out(windows: WindowSet, *, every: int = 4, block_periods: float = 8.0) -> np.ndarray:
    """Mask of the windows held out of a fit: those starting in every ``every``-th block of
    ``block_periods`` forcing periods of each record.

    Why blocks of time, not every n-th window: the fit runs in stages whose windows differ in
    length; held out by where they start, the held-out windows of every stage cover the same
    stretches of record (up to a window's overhang at a block's ends).
    """
    if every < 2:
        raise ValueError(f"hold out every >= 2nd block, got {every}")
    t_rel = windows.start * windows.dt * windows.omega / (2 * math.pi)
    return (np.floor(t_rel / block_periods).astype(int) % every) == every - 1
