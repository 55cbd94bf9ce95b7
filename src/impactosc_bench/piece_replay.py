"""The core's pieces, collected and replayed: where a run of the core spends its step attempts.

Why: the time of one kind of piece cannot be read off a full run. The core is run step by step
(:func:`core_pieces`, the loop of ``driver.run`` one iteration at a time), the state at the start
of every piece is kept with every step attempt's time, and the pieces of one kind are replayed by
the core's own step functions from those states (:func:`replay`), so that their time can be
measured alone.

A piece's kind is read from the state vector (:func:`kind_code`): why the implicit solver runs
(S_SLOW), the vector field (S_FIELD), the variable of the explicit steps (S_MODE) and its
orientation (S_SGN). A kind the core gains later (a new variable, a new field) is a kind of its
own here without an edit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from impactosc.core.driver import initial_state, on_section, resume, run_settings, step_piece, workspace
from impactosc.core.events import record_poincare
from impactosc.core.layout import (
    C_BY_MODE,
    CLOSED,
    EXPLICIT,
    MODE_NAMES,
    N_COUNT,
    N_STATE,
    R_PERIOD,
    S_FIELD,
    S_ISEC,
    S_MODE,
    S_SGN,
    S_SLOW,
    S_T,
    S_V,
    S_X,
    TIME,
)
from impactosc.model.parameters import ModelParams
from impactosc_bench.scene import OMEGA

__all__ = ["CorePieces", "core_pieces", "kind", "kind_code", "kind_of", "replay", "RTOL"]

RTOL = 1e-10  # the benchmarks' tolerance (benchmark_taylor's), atol = rtol / 100
KIND_BASE = 16  # more than the core's implicit reasons, vector fields and variables: a code's digits
E_T, E_X, E_V = range(3)  # columns of CorePieces.ends


@njit(cache=True, inline="always")
def kind_code(st):
    """The kind of the piece the state st is on, one integer (:func:`kind_of` unpacks it). Time
    has no orientation (S_SGN then holds the last transformed piece's), nor has the closed form
    (S_SGN: the sign of v) or the implicit solver: their orientation is 0."""
    slow = int(st[S_SLOW])
    mode = int(st[S_MODE])
    sgn = 0
    if slow == EXPLICIT and mode != TIME and mode != CLOSED:
        sgn = 1 if st[S_SGN] > 0.0 else -1
    return ((slow * KIND_BASE + int(st[S_FIELD])) * KIND_BASE + mode) * 3 + sgn + 1


def kind(slow: int, field: int, mode: int, sgn: int) -> int:
    """The kind_code of (implicit reason, vector field, variable, orientation)."""
    return ((int(slow) * KIND_BASE + int(field)) * KIND_BASE + int(mode)) * 3 + int(sgn) + 1


def kind_of(code: int) -> tuple[int, int, int, int]:
    """(implicit reason, vector field, variable, orientation) of a kind_code."""
    rest, o = divmod(int(code), 3)
    rest, mode = divmod(rest, KIND_BASE)
    slow, field = divmod(rest, KIND_BASE)
    return slow, field, mode, o - 1


@njit(cache=True)
def _one_step(p, st, cnt, rs, ws, ev, n_ev, win, period):
    """One iteration of core.run's loop (a Poincare time, or one step of the current piece)."""
    t_sec = st[S_ISEC] * period
    if on_section(st, t_sec):
        ev, n_ev = record_poincare(st, rs, ev, n_ev, t_sec, st[S_X], st[S_V])
        return ev, n_ev, False
    ev, n_ev = step_piece(p, st, cnt, rs, ws, ev, n_ev, win, win, t_sec)
    return ev, n_ev, True


@njit(cache=True)
def _collect(p, st, rs, t_end, starts, codes, ends, n_att, att_t, att_v, att_piece, by_mode):
    """Run the core from ``st`` to t_end as core.run does. Every piece (a stretch of steps of one
    kind) gets its start state (a copy of st) in starts, its kind in codes, (t, x, v) at its end
    in ends and its step attempts in n_att; every attempt its start time, velocity and piece in
    att_*. by_mode: the core's own counters of explicit attempts per variable (C_BY_MODE).
    Returns (pieces, attempts), or -1 for both when an array is too short."""
    ws = workspace()
    cnt = np.zeros(N_COUNT, dtype=np.int64)
    ev = np.empty((16, 4))
    win = np.empty(0)
    resume(p, st, cnt, ws[3])
    period = rs[R_PERIOD]
    n_p, n_a, cur = 0, 0, -1
    while st[S_T] < t_end:
        code = kind_code(st)
        if code != cur:
            if n_p > 0:
                ends[n_p - 1, E_T], ends[n_p - 1, E_X], ends[n_p - 1, E_V] = st[S_T], st[S_X], st[S_V]
            if n_p == starts.shape[0]:
                return -1, -1
            starts[n_p, :] = st
            codes[n_p] = code
            n_att[n_p] = 0
            n_p += 1
            cur = code
        t0, v0 = st[S_T], st[S_V]
        ev, _, stepped = _one_step(p, st, cnt, rs, ws, ev, 0, win, period)
        if stepped:
            if n_a == att_t.shape[0]:
                return -1, -1
            att_t[n_a], att_v[n_a], att_piece[n_a] = t0, v0, n_p - 1
            n_att[n_p - 1] += 1
            n_a += 1
    if n_p > 0:
        ends[n_p - 1, E_T], ends[n_p - 1, E_X], ends[n_p - 1, E_V] = st[S_T], st[S_X], st[S_V]
    for m in range(by_mode.shape[0]):
        by_mode[m] = cnt[C_BY_MODE + m]
    return n_p, n_a


@njit(cache=True)
def replay(p, rs, starts, which, t_end):
    """The core's own step functions over the pieces starts[which == 1], each from its saved
    state until the piece's kind changes (or t_end): the work the timing measures. Returns
    (attempts, sum of the end times: a result the compiler cannot drop)."""
    ws = workspace()
    cnt = np.zeros(N_COUNT, dtype=np.int64)
    ev = np.empty((16, 4))
    win = np.empty(0)
    st = np.empty(N_STATE)
    period = rs[R_PERIOD]
    attempts, acc = 0, 0.0
    for i in range(starts.shape[0]):
        if which[i] == 0:
            continue
        st[:] = starts[i]
        code = kind_code(st)
        resume(p, st, cnt, ws[3])
        while kind_code(st) == code and st[S_T] < t_end:
            ev, _, stepped = _one_step(p, st, cnt, rs, ws, ev, 0, win, period)
            attempts += 1 if stepped else 0
        acc += st[S_T]
    return attempts, acc


@dataclass
class CorePieces:
    """The pieces of one run of the core from rest, in order, and its step attempts.

    Per piece: starts (the state vector at its start), codes (its kind_code), ends (t, x, v at its
    end: columns E_T, E_X, E_V), attempts (its step attempts); the last piece is cut by t_end.
    Per attempt: attempt_t and attempt_v (time and velocity where it started), attempt_piece.
    by_mode: the core's counters of explicit attempts per variable (layout.C_BY_MODE + mode).
    """

    p: np.ndarray
    rs: np.ndarray
    t_end: float
    period: float
    starts: np.ndarray
    codes: np.ndarray
    ends: np.ndarray
    attempts: np.ndarray
    attempt_t: np.ndarray
    attempt_v: np.ndarray
    attempt_piece: np.ndarray
    by_mode: np.ndarray

    @property
    def periods(self) -> float:
        """Forcing periods in the run."""
        return self.t_end / self.period

    def replay(self, which) -> tuple[int, float]:
        """Replay the pieces where ``which`` (one flag per piece) is set: (attempts, checksum)."""
        return replay(self.p, self.rs, self.starts, np.asarray(which, dtype=np.int64), self.t_end)


def core_pieces(
    t_end: float, rtol: float = RTOL, params: ModelParams | None = None, omega: float = OMEGA
) -> CorePieces:
    """The core on the scene from rest to t_end (atol = rtol / 100), collected piece by piece."""
    params = params or ModelParams()
    p = params.as_array(omega)
    period = 2 * math.pi / omega
    rs = run_settings(t_end, t_end, rtol, rtol / 100, 0, period)
    pieces, attempts = int(16 * t_end / period) + 64, int(200 * t_end / period) + 4096
    while True:
        st = initial_state(p, 0.0, 0.0, 0.0, period, params.cut_velocity)
        starts, codes, ends = np.empty((pieces, N_STATE)), np.empty(pieces, np.int64), np.empty((pieces, 3))
        n_att = np.empty(pieces, np.int64)
        att_t, att_v, att_piece = np.empty(attempts), np.empty(attempts), np.empty(attempts, np.int64)
        by_mode = np.zeros(len(MODE_NAMES), np.int64)
        n_p, n_a = _collect(p, st, rs, t_end, starts, codes, ends, n_att, att_t, att_v, att_piece, by_mode)
        if n_p >= 0:
            break
        pieces, attempts = 2 * pieces, 2 * attempts
    return CorePieces(
        p, rs, t_end, period, starts[:n_p], codes[:n_p], ends[:n_p], n_att[:n_p], att_t[:n_a], att_v[:n_a],
        att_piece[:n_a], by_mode,
    )  # fmt: skip
