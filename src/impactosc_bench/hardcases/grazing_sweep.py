"""Hard case "grazing": the period-1 orbit swept through its grazing point.

Why a module: it needs its own independent reference, a fixed-step scan of SciPy's dense
output over one free flight (:func:`scan_free_flight`), and the grazing w located to 1e-12 m
of clearance by :func:`impactosc.dynamics.grazing.grazing_by_clearance_secant`, so that
contacts and near misses of a chosen size (down to 1e-9 m) can be set.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from impactosc.dynamics.grazing import grazing_by_clearance_secant, settle_orbit
from impactosc.model.parameters import ModelParams
from impactosc_bench.hardcases.checks import row


def scan_free_flight(omega, params, t_a, x_a, v_a, t_b, dt):
    """Independent look at one free-flight maximum: SciPy DOP853 (rtol 1e-13) from the
    state at t_a, its dense output sampled every dt. Between samples x can exceed the
    largest sample by at most A dt^2 / 8, A a bound on |x''| (doubled for safety).

    Returns (largest sample - xI, A dt^2/8): the true signed clearance lies in
    [value, value + bound] as long as the contact force is negligible (shallow contacts).
    """
    p = params

    def f(t, y):
        fr = p.T * y[1] / math.sqrt(y[1] ** 2 + p.eps**2)
        return [y[1], (p.m0e * omega**2 * math.sin(omega * t) - p.k * y[0] - p.c * y[1] - fr) / p.m]

    sol = solve_ivp(f, (t_a, t_b), [x_a, v_a], method="DOP853", rtol=1e-13, atol=1e-16, dense_output=True)
    if sol.status != 0:
        raise RuntimeError(f"scan failed: {sol.message}")
    ts = np.arange(t_a, t_b, dt)
    x, v = sol.sol(ts)
    a_max = 2.0 * (p.m0e * omega**2 + p.k * np.abs(x).max() + p.c * np.abs(v).max() + p.T) / p.m
    return float(x.max() - p.xI), a_max * dt * dt / 8.0


def grazing_case(
    params=None,
    depths=(1e-7, 1e-8, 1e-9),
    gaps=(1e-5, 1e-6, 1e-7, 1e-8, 1e-9),
    fine_points=0,
    fine_halfwidth=1e-5,
    periods=150,
    scan_dt=2e-6,
    log=print,
) -> list[dict]:
    """Sweep w through the grazing point of the period-1 branch so that its grazing maximum
    is a contact of each depth in `depths` or a near miss of each gap in `gaps` (plus
    `fine_points` w on a uniform grid of half-width `fine_halfwidth` rad/s around w*).

    At each w the core's event (an impact and a penetration, or a near miss) must agree in
    kind with an independent fixed-step scan, and its depth/gap with the scan's to within
    the scan's bound plus the effect of the contact force the free-flight scan ignores
    (4 kI d^2.5 / (m a) for a contact of depth d under deceleration a). A clearance within
    the scan's resolution (|value| <= bound + 1e-12 m) cannot be classified by the scan;
    there only the deviation is checked and the w is counted as unresolved. (Contacts
    deeper than ~1e-7 m leave the period-1 branch: the orbit jumps to the period-4 one.)
    """
    p = params or ModelParams()
    w_star, slope, s_star = grazing_by_clearance_secant(p)
    log(f"grazing at w* = {w_star!r} rad/s, dg/dw = {slope:.4g} m/(rad/s)")
    omegas = [w_star + d / slope for d in depths] + [w_star - g / slope for g in gaps]
    if fine_points:
        omegas += list(w_star + np.linspace(-fine_halfwidth, fine_halfwidth, fine_points))
    worst_ratio, n_ok, n_unresolved, shallowest, closest = 0.0, 0, 0, math.inf, math.inf
    for w in sorted(omegas):
        g, tg, _, res = settle_orbit(w, s_star, p, periods, window_dt=1e-4)
        in_contact = g > 0
        # the free-flight arc around the grazing maximum, +-60 ms: no other contact in it
        tw, xw, vw = res.trajectory["t"], res.trajectory["x"], res.trajectory["v"]
        j = int(np.argmin(np.abs(tw - (tg - 0.06))))
        t_a, t_b = float(tw[j]), tg + 0.06
        near = (tw >= t_a) & (tw <= t_b) & (np.abs(tw - tg) > 0.01)
        if np.any(xw[near] >= p.xI):
            raise RuntimeError(f"w = {w}: another contact lies within 60 ms of the grazing maximum")
        value, bound = scan_free_flight(w, p, t_a, float(xw[j]), float(vw[j]), t_b, scan_dt)
        a0 = abs(p.m0e * w * w * math.sin(w * tg) - p.k * (p.xI + max(value, 0.0))) / p.m  # |x''| at the maximum
        force_effect = 4 * p.kI * value**2.5 / (p.m * max(a0, 1e-12)) if value > 0 else 0.0
        tol = bound + force_effect + 1e-12
        resolved = abs(value) > bound + 1e-12
        kind_ok = (not resolved) or (in_contact == (value > 0))
        # the grazing contact is exactly one impact near the maximum; a near miss none
        n_imp = int(np.count_nonzero(np.abs(res.events["impacts"]["t"] - tg) < 0.01))
        count_ok = n_imp == (1 if in_contact else 0)
        dev = abs(g - value)
        ok = kind_ok and count_ok and dev <= tol
        n_ok += ok
        n_unresolved += not resolved
        worst_ratio = max(worst_ratio, dev / tol)
        if in_contact:
            shallowest = min(shallowest, g)
        else:
            closest = min(closest, -g)
        log(
            f"w = {w:.11f}: core {g:+.4e} m, scan {value:+.4e} (+{bound:.1e}) m, |dev| {dev:.1e} <= {tol:.1e}, "
            f"impacts at the maximum: {n_imp}, {'ok' if ok else 'FAIL'}{'' if resolved else ' (unresolved)'}"
        )
    n = len(omegas)
    detail = (
        f"w* = {w_star:.11f} rad/s (secant on the signed clearance, dg/dw = {slope:.4g} m s/rad); "
        f"{n} w values: contacts {', '.join(f'{d:g}' for d in depths)} m, gaps "
        f"{', '.join(f'{d:g}' for d in gaps)} m, {fine_points} on w* +- {fine_halfwidth:g}; "
        f"{n_unresolved} within the scan's resolution"
    )
    return [
        row(
            "grazing",
            "w values whose grazing event (contact with one impact, or near miss) the core "
            "classifies as an independent fixed-step scan (SciPy DOP853, dt 2e-6 s) does",
            n_ok,
            n,
            "count",
            passed=n_ok == n,
            detail=detail,
        ),
        row(
            "grazing",
            "worst |core - scan| depth or gap, over its allowed deviation (scan bound A dt^2/8 "
            "+ neglected contact force + 1e-12 m)",
            worst_ratio,
            1.0,
            "ratio",
        ),
        row(
            "grazing",
            "shallowest contact detected (bound: the smallest depth asked for)",
            shallowest,
            min(depths) * 1.5,
            "m",
        ),
        row(
            "grazing",
            "smallest near-miss gap resolved (bound: the smallest gap asked for)",
            closest,
            min(gaps) * 1.5,
            "m",
        ),
    ]
