"""The closed-form free-flight piece (:mod:`impactosc.core.closed_flight`) as the benchmark
times it, and its friction residual.

The closed form takes the friction as -T sign(v). The regularised friction differs from it by
dF = T (1 - |v| / sqrt(v^2 + eps^2)) <= T eps^2 / (2 v^2) (3.2e-7 N at model BC's band edge, |v| = 1e-3
m/s), and by Duhamel's integral the closed form is off by at most
|dx| <= I / (m wd), |dv| <= wn I / (m wd), I = integral of dF over the piece
(:func:`friction_residual`); :func:`friction_correction` adds that integral's first-order
effect by quadrature.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from impactosc.core.closed_flight import EV_BAND, EV_IMPACT, EV_NONE, flight_piece, flight_state
from impactosc.model.parameters import ModelParams
from impactosc_bench.scene import OMEGA

__all__ = [
    "EV_BAND",
    "EV_IMPACT",
    "EV_NONE",
    "all_flights",
    "flight_piece",
    "flight_state",
    "friction_correction",
    "friction_residual",
]


@njit(cache=True)
def all_flights(p, starts, isecs, period):
    """The prototype on every start state (t, x, v): the work the timing measures; returns the
    sum of the end times (kept so nothing is optimised away) and the evaluations."""
    sections = np.empty((4, 3))
    acc, evals = 0.0, 0
    for i in range(starts.shape[0]):
        _, t, x, _, _, n = flight_piece(p, starts[i, 0], starts[i, 1], starts[i, 2], isecs[i], period, sections)
        acc += t + x
        evals += n
    return acc, evals


# --- the friction residual ------------------------------------------------------------------
def friction_residual(params: ModelParams, t0, x0, v0, t1, omega: float = OMEGA, n: int = 4001) -> dict:
    """I = integral of dF = T (1 - |v| / sqrt(v^2 + eps^2)) over [t0, t1] on the closed form (the
    trapezoid on a grid graded towards both ends, where |v| is smallest), and the bounds it gives
    on the closed form's error at t1: |dx| <= I / (m wd), |dv| <= wn I / (m wd)."""
    p = params.as_array(omega)
    ts = _graded(t0, t1, n)
    v = np.array([flight_state(p, t0, x0, v0, t)[1] for t in ts])
    df = params.T * (1.0 - np.abs(v) / np.sqrt(v * v + params.eps**2))
    integral = float(np.trapezoid(df, ts))
    wn = math.sqrt(params.k / params.m)
    wd = math.sqrt(wn * wn - (params.c / (2 * params.m)) ** 2)
    return {
        "integral": integral,
        "max_dF": float(df.max()),
        "bound_x": integral / (params.m * wd),
        "bound_v": wn * integral / (params.m * wd),
    }


def friction_correction(params: ModelParams, t0, x0, v0, t1, omega: float = OMEGA, n: int = 4001):
    """First-order correction (dx, dv) at t1 of the closed form for the regularised friction:
    Duhamel's integral of s dF against the impulse response exp(-alpha u) sin(wd u) / (m wd)."""
    p = params.as_array(omega)
    s = 1.0 if v0 > 0 else -1.0
    ts = _graded(t0, t1, n)
    v = np.array([flight_state(p, t0, x0, v0, t)[1] for t in ts])
    df = s * params.T * (1.0 - np.abs(v) / np.sqrt(v * v + params.eps**2))
    alpha = params.c / (2 * params.m)
    wd = math.sqrt(params.k / params.m - alpha * alpha)
    u = t1 - ts
    e = np.exp(-alpha * u)
    hx = e * np.sin(wd * u) / (params.m * wd)
    hv = e * (np.cos(wd * u) - alpha / wd * np.sin(wd * u)) / params.m
    return float(np.trapezoid(hx * df, ts)), float(np.trapezoid(hv * df, ts))


def _graded(t0, t1, n):
    """n points on [t0, t1] clustered quadratically at both ends (dF ~ 1/v^2 peaks there)."""
    u = np.linspace(-1.0, 1.0, n)
    return t0 + (t1 - t0) * 0.5 * (1.0 + np.sign(u) * (1.0 - (1.0 - np.abs(u)) ** 4))


# --- the core's pieces, replayed --------------------------------------------------------------
