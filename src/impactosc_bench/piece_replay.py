"""The core's pieces, collected and replayed: where a run of the core spends its step attempts.

Why: the time of one kind of piece cannot be read off a full run; the core is run step by step,
the state at the start of every piece is kept, and the pieces of one kind are replayed by the
core's own step functions from those states, so that their time can be measured alone.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core.driver import initial_state, resume, run_settings, step_piece
from impactosc.core.events import record_poincare
from impactosc.core.layout import (
    EXPLICIT,
    N_COUNT,
    N_STATE,
    R_PERIOD,
    S_FIELD,
    S_ISEC,
    S_MODE,
    S_SLOW,
    S_T,
    S_TAU,
    S_V,
    S_X,
    TIME,
    UVEL,
)
from impactosc.model.equations import FREE
from impactosc.model.parameters import ModelParams
from impactosc_bench.scene import OMEGA

__all__ = ["core_pieces", "replay", "KEY_FLIGHT", "KEY_BAND"]

RTOL = 1e-10  # the benchmark's tolerance (benchmark_taylor's), atol = rtol / 100
KEY_FLIGHT, KEY_BAND = 0, 1  # the piece kinds replayed (free flight in time; the band in asinh(v/eps))


@njit(cache=True, inline="always")
def _key(st):
    """KEY_FLIGHT, KEY_BAND, or -1 for any other piece (contact, implicit phase, ...)."""
    if st[S_SLOW] != EXPLICIT or st[S_FIELD] != FREE:
        return -1
    if st[S_MODE] == TIME:
        return KEY_FLIGHT
    if st[S_MODE] == UVEL:
        return KEY_BAND
    return -1


@njit(cache=True)
def _one_step(p, st, cnt, rs, ws, ev, n_ev, win, period):
    """One iteration of core.run's loop (a Poincare time, or one step of the current piece)."""
    t_sec = st[S_ISEC] * period
    if st[S_MODE] == TIME and st[S_TAU] >= t_sec:
        ev, n_ev = record_poincare(st, rs, ev, n_ev, t_sec, st[S_X], st[S_V])
        return ev, n_ev, False
    ev, n_ev = step_piece(p, st, cnt, rs, ws, ev, n_ev, win, win, t_sec)
    return ev, n_ev, True


@njit(cache=True)
def _collect(p, st, rs, t_end, starts, ends):
    """Run the core from ``st`` to t_end as core.run does; every stretch of one kind (KEY_FLIGHT,
    KEY_BAND, or -1: everything else, contact and implicit phases) gets its start state (a copy
    of st) in starts and (key, t, x, v, attempts, key and field after) at its end in ends.
    Returns the number of pieces."""
    ws = (np.zeros((16, 3)), np.zeros((7, 3)), np.zeros((8, 6)), np.zeros(3))
    cnt = np.zeros(N_COUNT, dtype=np.int64)
    ev = np.empty((16, 4))
    win = np.empty(0)
    resume(p, st, cnt, ws[3])
    period = rs[R_PERIOD]
    n_p, cur, attempts = 0, -2, 0
    while st[S_T] < t_end:
        key = _key(st)
        if key != cur:
            if n_p > 0:
                ends[n_p - 1, 0], ends[n_p - 1, 1], ends[n_p - 1, 2] = cur, st[S_T], st[S_X]
                ends[n_p - 1, 3], ends[n_p - 1, 4], ends[n_p - 1, 5] = st[S_V], attempts, key
                ends[n_p - 1, 6] = st[S_FIELD]
            if n_p < starts.shape[0]:
                starts[n_p, :] = st
                n_p += 1
            cur, attempts = key, 0
        ev, _, stepped = _one_step(p, st, cnt, rs, ws, ev, 0, win, period)
        attempts += 1 if stepped else 0
    if n_p > 0:  # the piece the run ended in: not a full piece
        n_p -= 1
    return n_p


@njit(cache=True)
def replay(p, rs, starts, which, t_end):
    """The core's own step functions over the pieces starts[which == 1], each from its saved
    state until the piece kind changes: the work the timing measures. Returns (attempts, sum t)."""
    ws = (np.zeros((16, 3)), np.zeros((7, 3)), np.zeros((8, 6)), np.zeros(3))
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
        key = _key(st)
        resume(p, st, cnt, ws[3])
        while _key(st) == key and st[S_T] < t_end:
            ev, _, stepped = _one_step(p, st, cnt, rs, ws, ev, 0, win, period)
            attempts += 1 if stepped else 0
        acc += st[S_T]
    return attempts, acc


def core_pieces(t_end: float, rtol: float = RTOL, params: ModelParams | None = None, omega: float = OMEGA):
    """The core on the scene from rest to t_end: (p, rs, starts, ends) of its free-flight pieces,
    band pieces and the stretches between them (ends rows: key, t, x, v, attempts, key and field of the next piece)."""
    params = params or ModelParams()
    p = params.as_array(omega)
    period = 2 * math.pi / omega
    rs = run_settings(t_end, t_end, rtol, rtol / 100, 0, period)
    st = initial_state(p, 0.0, 0.0, 0.0, period, params.cut_velocity)
    cap = int(12 * t_end / period) + 64
    starts, ends = np.empty((cap, N_STATE)), np.empty((cap, 7))
    n = _collect(p, st, rs, t_end, starts, ends)
    return p, rs, starts[:n], ends[:n]
