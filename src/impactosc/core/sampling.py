"""Inside one accepted step: locate a crossing on the dense output, fill trajectory-window samples.

Explicit steps carry DOP853's 7th-order interpolant (coefficients F, see dop853.dense_prepare);
implicit steps carry only their end points, between which the slow creep is sampled by a cubic
Hermite in x. The window is the optional uniform-time trajectory a caller asked for
(samples win_t0 + j win_dt, the next one due is st[S_WIN]).
"""

from __future__ import annotations

from numba import njit

from impactosc.core import dop853
from impactosc.core.layout import R_WIN_DT, R_WIN_T0, S_WIN, TIME
from impactosc.model.contact_laws.kernel import surface_reads, surface_residual


@njit(cache=True)
def bisect(F, y0, c, level, lo, hi, sign_lo):
    """Crossing of component c through `level` in (lo, hi]; returns the first theta past it."""
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        g = dop853.dense_eval(F, y0, mid, c) - level
        if g * sign_lo > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def locate_surface(p, vcut, surface, F, x0, v0, lo, hi, sign_lo):
    """Crossing of a contact law's switching surface (its residual, contact_laws.kernel.
    surface_residual, on the step's dense output) in (lo, hi], the residual's sign before it
    `sign_lo`; returns the first theta past it. One root-finding for every surface of every law."""
    reads_x, reads_v = surface_reads(p, surface)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        xm = dop853.dense_eval(F, x0, mid, 1) if reads_x else 0.0
        vm = dop853.dense_eval(F, v0, mid, 2) if reads_v else 0.0
        g = surface_residual(p, vcut, surface, xm, vm)
        if g * sign_lo > 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def window_due(st, rs, win_x, t1):
    """Is a window sample due at or before absolute time t1?"""
    j = int(st[S_WIN])
    return j < win_x.shape[0] and rs[R_WIN_T0] + j * rs[R_WIN_DT] <= t1


@njit(cache=True)
def sample_window(F, mode, tref, t0, x0, v0, h, t1, st, rs, win_x, win_v):
    """Fill the window samples due up to absolute time t1 from the step's dense output
    (whose time component starts at t0, measured from tref)."""
    j = int(st[S_WIN])
    n = win_x.shape[0]
    while j < n:
        ts = rs[R_WIN_T0] + j * rs[R_WIN_DT]
        if ts > t1:
            break
        if mode == TIME:
            th = (ts - t0) / h
        else:  # t is a component: invert the monotone t(s)
            th = bisect(F, t0, 0, ts - tref, 0.0, 1.0, -1.0)
        win_x[j] = dop853.dense_eval(F, x0, th, 1)
        win_v[j] = dop853.dense_eval(F, v0, th, 2)
        j += 1
    st[S_WIN] = j


@njit(cache=True)
def sample_hermite(t0, x0, v0, t1, x1, v1, st, rs, win_x, win_v):
    """Window samples inside an implicit (sticking) step: cubic Hermite in x (x' = v known
    at both ends), linear in v; the creep inside such a step is slow and smooth."""
    j = int(st[S_WIN])
    n = win_x.shape[0]
    h = t1 - t0
    while j < n:
        ts = rs[R_WIN_T0] + j * rs[R_WIN_DT]
        if ts > t1:
            break
        th = (ts - t0) / h if h > 0.0 else 1.0
        h00 = (1.0 + 2.0 * th) * (1.0 - th) ** 2
        h10 = th * (1.0 - th) ** 2
        h01 = th * th * (3.0 - 2.0 * th)
        h11 = th * th * (th - 1.0)
        win_x[j] = h00 * x0 + h10 * h * v0 + h01 * x1 + h11 * h * v1
        win_v[j] = v0 + th * (v1 - v0)
        j += 1
    st[S_WIN] = j
