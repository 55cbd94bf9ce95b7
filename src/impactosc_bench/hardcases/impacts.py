"""Hard cases on impact sequences and event timing: chattering (shrinking impact
sequences, bouncing to rest on the obstacle) and coincidence (an impact exactly on a
Poincare time, events exactly at the end of a run).

Why a module: these cases check the event detection itself, impact by impact, against
SciPy DOP853 split at contact (:func:`impactosc_bench.scipy_reference.solve_reference`) or
against the same run ended elsewhere.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from impactosc.core.simulation import Window, simulate
from impactosc.model.parameters import ModelParams
from impactosc_bench.hardcases.checks import row, work_row
from impactosc_bench.scipy_reference import solve_reference

ALL_RECORD = ("impacts", "penetrations", "near_misses", "poincare")


# ============================================================================ chattering


def _shrinking_runs(t, v, min_len):
    """Index ranges of >= min_len consecutive impacts with strictly decreasing velocity."""
    runs, start = [], 0
    for j in range(1, len(v) + 1):
        if j == len(v) or not v[j] < v[j - 1]:
            if j - start >= min_len:
                runs.append((start, j))
            start = j
    return runs


def chattering_case(
    params, omega, t_end, label, min_len=3, rtol=1e-12, atol=1e-14, ref_rtol=1e-13, ref_atol=1e-15, log=print
) -> list[dict]:
    """Shrinking impact sequences against SciPy DOP853 (rtol 1e-13, split at contact
    onset/exit) from rest, up to `t_end` (chosen before any sticking on the obstacle, where
    SciPy's step collapses at v = 0 inside contact).

    Checks: every impact of the sequences found, none invented (same count as the
    reference over [0, t_end]), the impact times to 1e-9 s and the impact velocities, which
    shrink to ~1e-3 m/s, to 1e-6 relative.
    """
    t0 = time.perf_counter()
    res = simulate(omega, 0.0, t_end, params=params, rtol=rtol, atol=atol, record=("impacts",))
    wall = time.perf_counter() - t0
    ref = solve_reference(omega, t_end, params=params, rtol=ref_rtol, atol=ref_atol)
    t, v = res.events["impacts"]["t"], res.events["impacts"]["v"]
    tr, vr = ref["impacts_t"], ref["impacts_v"]
    runs = _shrinking_runs(tr, vr, min_len)
    longest = max((b - a for a, b in runs), default=0)
    same = t.size == tr.size
    dt = float(np.abs(t - tr).max()) if same else math.inf
    dv = float(np.max(np.abs(v - vr) / np.abs(vr))) if same else math.inf
    vmin = float(min(vr[a:b].min() for a, b in runs)) if runs else math.nan
    log(
        f"{label}: {t.size} impacts (reference {tr.size}), {len(runs)} shrinking sequences, longest {longest}, "
        f"smallest v {vmin:.3g} m/s, |dt| {dt:.2e} s, |dv|/v {dv:.2e}, core {wall:.3f} s"
    )
    detail = (
        f"w = {omega} rad/s, b = {params.b}, [0, {t_end}] s, core rtol {rtol:g}; {len(runs)} sequences of >= "
        f"{min_len} impacts with shrinking velocity, longest {longest}, down to {vmin:.2g} m/s"
    )
    return [
        row(
            "chattering",
            f"{label}: impacts found by the core minus the reference's (SciPy DOP853 1e-13)",
            abs(t.size - tr.size),
            0,
            "count",
            detail=detail,
        ),
        row(
            "chattering",
            f"{label}: longest shrinking sequence in the reference (at least)",
            longest,
            min_len,
            "count",
            passed=longest >= min_len,
        ),
        row("chattering", f"{label}: max |impact time - reference|", dt, 1e-9, "s"),
        row("chattering", f"{label}: max relative impact-velocity error", dv, 1e-6, "1"),
    ]


def bounce_to_rest_case(params, omega, t_end, rtol=1e-10, atol=1e-12, log=print) -> list[dict]:
    """After the last impact of a bouncing sequence the cart rests on the obstacle: the core
    must neither invent impacts there nor slow down (the Hunt-Crossley |v|^n3 has an
    infinite slope at the v = 0 of the resting cart)."""
    t0 = time.perf_counter()
    res = simulate(omega, 0.0, t_end, params=params, rtol=rtol, atol=atol, record=("impacts", "penetrations"))
    wall = time.perf_counter() - t0
    t = res.events["impacts"]["t"]
    a = res.attrs
    log(
        f"bounce to rest w = {omega}: {t.size} impacts, last at {t[-1]:.4f} s, {a['n_stick']} sticks, "
        f"{a['n_implicit_steps']} implicit steps, {wall:.3f} s"
    )
    return [
        row(
            "chattering",
            f"bouncing to rest (w = {omega}, b = {params.b}): impacts in the last half of "
            f"[0, {t_end}] s, with the cart resting on the obstacle",
            int(np.count_nonzero(t > t_end / 2)),
            0,
            "count",
            detail=f"{t.size} impacts, the last at {t[-1]:.4f} s; {a['n_stick']} stick phase(s)",
        ),
        work_row("chattering", "bouncing to rest", a, t_end, wall),
    ]


# ============================================================ coincident and final events


def _events_equal(a, b, t_max):
    """Whether two runs' events with t < t_max are identical (bitwise)."""
    for name in a:
        for col in a[name]:
            x, y = a[name][col], b[name][col]
            x, y = x[a[name]["t"] < t_max], y[b[name]["t"] < t_max]
            if x.shape != y.shape or not np.array_equal(x, y):
                return False
    return True


def coincidence_case(omega=40.86, x0=-8e-3, v0=-0.2, horizon_after=1.0, log=print) -> list[dict]:
    """An impact exactly at a Poincare time, and events exactly at the end of a run.

    (a) From rest at x0 (obstacle out of reach) take the first Poincare point with v > 0
    that is the highest x so far (the cart still on its first rise); put the obstacle there. The impact then falls on
    the section time t_i itself. It must be recorded once, at t_i, with the Poincare point
    on the obstacle, and the next `horizon_after` s must agree with SciPy DOP853 (split at
    contact) and with the obstacle moved by +-1e-12 m (impact just after/before t_i) to 1e-9 s.
    (b) A run ending exactly at a Poincare time records that point once and all earlier
    events bitwise as the longer run does; a run ending exactly at an impact time records
    all earlier events as the longer run and the final impact at most once.
    """
    base = ModelParams()
    period = 2 * math.pi / omega
    far = dataclasses.replace(base, xI=1.0)
    free = simulate(
        omega, 0.0, 10 * period, x0=x0, v0=v0, params=far, window=Window(0.0, 10 * period, 1e-4), record=("poincare",)
    )
    pc = free.events["poincare"]
    tw, xw = free.trajectory["t"], free.trajectory["x"]
    found = [k for k in range(len(pc["t"])) if pc["v"][k] > 0 and xw[tw < pc["t"][k]].max() < pc["x"][k]]
    if not found:
        raise ValueError(
            f"from x0 = {x0}, v0 = {v0} no Poincare point in 10 periods is a first rise to a new "
            "height; choose another start"
        )
    i = found[0]
    t_i, x_i = float(pc["t"][i]), float(pc["x"][i])
    horizon = t_i + horizon_after
    rows = []
    runs = {}
    for shift in (0.0, 1e-12, -1e-12):
        q = dataclasses.replace(base, xI=x_i + shift)
        runs[shift] = simulate(omega, 0.0, horizon, x0=x0, v0=v0, params=q, record=ALL_RECORD)
    ev = runs[0.0].events
    imp = ev["impacts"]["t"]
    at = np.abs(imp - t_i) < 1e-9
    on_section = np.abs(ev["poincare"]["t"] - t_i) < 1e-12
    x_sec = float(ev["poincare"]["x"][on_section][0]) if on_section.sum() == 1 else math.nan
    ref = solve_reference(omega, horizon, x0=x0, v0=v0, params=dataclasses.replace(base, xI=x_i))
    same_n = imp.size == ref["impacts_t"].size
    dev_ref = float(np.abs(imp - ref["impacts_t"]).max()) if same_n else math.inf
    dev_shift = max(
        float(np.abs(runs[s].events["impacts"]["t"] - imp).max())
        if runs[s].events["impacts"]["t"].size == imp.size
        else math.inf
        for s in (1e-12, -1e-12)
    )
    log(
        f"impact on the section t_i = {t_i:.12f} s: {int(at.sum())} impact(s) there, first at {imp[0]:.15f}; "
        f"Poincare x - xI {x_sec - x_i:.2e} m; {imp.size} impacts vs SciPy {ref['impacts_t'].size}, "
        f"dev {dev_ref:.2e} s; +-1e-12 m: dev {dev_shift:.2e} s"
    )
    detail = f"w = {omega}, x(0) = {x0} m, v(0) = {v0} m/s, obstacle at x(t_i) = {x_i:.9e} m, t_i = {t_i:.12f} s (section {i + 1})"
    rows += [
        row(
            "coincidence",
            "impacts recorded within 1e-9 s of the section time they fall on",
            int(at.sum()),
            1,
            "count",
            passed=int(at.sum()) == 1,
            detail=detail,
        ),
        row(
            "coincidence",
            "Poincare points recorded at that section time, and |x - xI| of it (bound 1e-12 m)",
            abs(x_sec - x_i) if on_section.sum() == 1 else math.inf,
            1e-12,
            "m",
            passed=on_section.sum() == 1 and abs(x_sec - x_i) <= 1e-12,
        ),
        row(
            "coincidence",
            f"max |impact time - SciPy DOP853| over {horizon - t_i:.0f} s after it (same count)",
            dev_ref,
            1e-9,
            "s",
        ),
        row(
            "coincidence",
            "max |impact time shift| when the obstacle moves by +-1e-12 m (impact just before/after the section)",
            dev_shift,
            1e-9,
            "s",
        ),
    ]
    # (b) runs that end exactly on an event
    rows += _run_end_rows(omega, x0, v0, dataclasses.replace(base, xI=x_i), horizon, runs[0.0], log)
    return rows


def _run_end_rows(omega, x0, v0, params, horizon, long, log) -> list[dict]:
    """Part (b) of :func:`coincidence_case`: runs from (x0, v0) with `params` that end exactly
    on a Poincare time, and exactly at an impact time, against `long` (the run to `horizon`)."""
    period = 2 * math.pi / omega
    imp = long.events["impacts"]["t"]
    rows = []
    n_sec = int(math.floor(horizon / period)) - 1
    t_sec = n_sec * period
    short = simulate(omega, 0.0, t_sec, x0=x0, v0=v0, params=params, record=ALL_RECORD)
    n_end = int(np.count_nonzero(short.events["poincare"]["t"] == t_sec))
    same = _events_equal(short.events, long.events, t_sec)
    rows.append(
        row(
            "coincidence",
            "run ending exactly on a Poincare time: that point recorded once, earlier events "
            "bitwise those of the longer run",
            n_end,
            1,
            "count",
            passed=n_end == 1 and same,
            detail=f"t_end = {n_sec} periods = {t_sec:.12f} s; earlier events identical: {same}",
        )
    )
    t_imp = float(imp[imp.size // 2])
    short = simulate(omega, 0.0, t_imp, x0=x0, v0=v0, params=params, record=ALL_RECORD)
    s_imp = short.events["impacts"]["t"]
    before = np.array_equal(s_imp[s_imp < t_imp - 1e-9], imp[imp < t_imp - 1e-9])
    n_final = int(np.count_nonzero(np.abs(s_imp - t_imp) <= 1e-9))
    rows.append(
        row(
            "coincidence",
            "run ending exactly at an impact time: impacts there (at most one), earlier "
            "impacts identical to the longer run's",
            n_final,
            1,
            "count",
            passed=n_final <= 1 and before,
            detail=f"t_end = {t_imp:.12f} s; earlier impacts identical: {before}",
        )
    )
    log(f"end on a section: {n_end} point(s), identical: {same}; end on an impact: {n_final}, identical: {before}")
    return rows
