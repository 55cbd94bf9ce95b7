"""Hard cases for the core: each says what it checks, what it measured and the bound (issue 7).

Every case function returns rows ``{case, check, measured, bound, unit, passed, detail}``;
the tests (tests/test_hard_*.py) call them at reduced size and assert ``passed``; the
workflow (rule hard_cases) calls them at full size and writes results/tables/hard_cases.csv.
The references are independent of the core: SciPy's solvers, a fixed-step scan of SciPy's
dense output with an acceleration bound between samples, a piecewise closed-form Coulomb
(eps -> 0) solution, or an exact scaling law of the contact model.

Cases
-----
grazing      w swept through the grazing bifurcation; near misses and contacts of 1e-9 m
chattering   shrinking impact sequences (chaos at t < 1.1 s; a bouncing-to-rest set)
sticking     dry friction up to the forcing amplitude against the Coulomb limit; sticking
             on the obstacle (Hunt-Crossley |v|^n3 at v = 0) stays fast
regularisation  eps down to 1e-9 m/s and kI x 100: statistics and contact scaling
coincidence  an impact exactly at a Poincare time; events exactly at the end of a run
long_run     10^4 s of chaos: memory bounded by the stored events, no drift of the rate
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..model import ModelParams
from ..reference import solve_reference
from ..simulate import Window, simulate, warm_up
from .workprecision import run_scipy, train_statistics

ALL_RECORD = ("impacts", "penetrations", "near_misses", "poincare")


def row(case, check, measured, bound, unit, passed=None, detail=""):
    """One table row; `passed` defaults to measured <= bound."""
    measured = float(measured)
    if passed is None:
        passed = bool(measured <= bound)
    return {"case": case, "check": check, "measured": measured, "bound": bound, "unit": unit,
            "passed": bool(passed), "detail": detail}


# =============================================================================== grazing

def _signed_clearance(events):
    """(value, time) of the x maximum closest to the obstacle: +depth of a contact,
    -gap of a near miss."""
    nm, pen = events["near_misses"], events["penetrations"]
    vals = np.concatenate([-nm["gap"], pen["h"]])
    ts = np.concatenate([nm["t"], pen["t"]])
    if vals.size == 0:
        raise ValueError("no maximum of x recorded")
    k = int(np.argmin(np.abs(vals)))
    return float(vals[k]), float(ts[k])


def settle_orbit(omega, state, params, periods, record_periods=3, rtol=1e-10, atol=1e-12, window_dt=None):
    """Continue the attractor from `state` (x, v at phase 0) for `periods` forcing periods,
    record `record_periods` more; returns (signed clearance, its time, end state, result)."""
    period = 2 * math.pi / omega
    t0, t1 = periods * period, (periods + record_periods) * period
    win = Window(t0, t1, window_dt) if window_dt else None
    res = simulate(omega, t0, t1 - t0, x0=state[0], v0=state[1], params=params, rtol=rtol, atol=atol,
                   window=win, record=ALL_RECORD)
    g, tg = _signed_clearance(res.events)
    pc = res.events["poincare"]
    return g, tg, (float(pc["x"][-1]), float(pc["v"][-1])), res


def locate_grazing(params, w_far=23.06, w_near=23.05, settle_from_rest=800, periods=150, tol=1e-12, max_iter=12):
    """Grazing w of the period-1 branch: secant on the signed clearance g(w) of its near
    miss, each orbit continued from the previous one. Returns (w*, slope dg/dw, state)."""
    g_a, _, s_a, _ = settle_orbit(w_far, (0.0, 0.0), params, settle_from_rest)
    if g_a >= 0:
        raise RuntimeError(f"w = {w_far}: expected a near miss on the period-1 branch, got clearance {g_a:.3g} m")
    w_a, (g_b, _, s_b, _), w_b = w_far, settle_orbit(w_near, s_a, params, periods), w_near
    for _ in range(max_iter):
        slope = (g_b - g_a) / (w_b - w_a)
        w_n = w_b - g_b / slope
        g_n, _, s_n, _ = settle_orbit(w_n, s_b, params, periods)
        w_a, g_a, s_a, w_b, g_b, s_b = w_b, g_b, s_b, w_n, g_n, s_n
        if abs(g_n) < tol:
            return w_n, slope, s_n
    raise RuntimeError(f"grazing secant did not converge: |g| = {abs(g_b):.3g} m at w = {w_b}")


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


def grazing_case(params=None, depths=(1e-7, 1e-8, 1e-9), gaps=(1e-5, 1e-6, 1e-7, 1e-8, 1e-9), fine_points=0,
                 fine_halfwidth=1e-5, periods=150, scan_dt=2e-6, log=print) -> list[dict]:
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
    w_star, slope, s_star = locate_grazing(p)
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
        a0 = abs(p.m0e * w * w * math.sin(w * tg) - p.k * (p.xI + max(value, 0.0)) - p.c * 0.0) / p.m
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
        log(f"w = {w:.11f}: core {g:+.4e} m, scan {value:+.4e} (+{bound:.1e}) m, |dev| {dev:.1e} <= {tol:.1e}, "
            f"impacts at the maximum: {n_imp}, {'ok' if ok else 'FAIL'}{'' if resolved else ' (unresolved)'}")
    n = len(omegas)
    detail = (f"w* = {w_star:.11f} rad/s (secant on the signed clearance, dg/dw = {slope:.4g} m s/rad); "
              f"{n} w values: contacts {', '.join(f'{d:g}' for d in depths)} m, gaps "
              f"{', '.join(f'{d:g}' for d in gaps)} m, {fine_points} on w* +- {fine_halfwidth:g}; "
              f"{n_unresolved} within the scan's resolution")
    return [
        row("grazing", "w values whose grazing event (contact with one impact, or near miss) the core "
            "classifies as an independent fixed-step scan (SciPy DOP853, dt 2e-6 s) does", n_ok, n, "count",
            passed=n_ok == n, detail=detail),
        row("grazing", "worst |core - scan| depth or gap, over its allowed deviation (scan bound A dt^2/8 "
            "+ neglected contact force + 1e-12 m)", worst_ratio, 1.0, "ratio"),
        row("grazing", "shallowest contact detected (bound: the smallest depth asked for)", shallowest,
            min(depths) * 1.5, "m"),
        row("grazing", "smallest near-miss gap resolved (bound: the smallest gap asked for)", closest,
            min(gaps) * 1.5, "m"),
    ]


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


def chattering_case(params, omega, t_end, label, min_len=3, rtol=1e-12, atol=1e-14, ref_rtol=1e-13,
                    ref_atol=1e-15, log=print) -> list[dict]:
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
    log(f"{label}: {t.size} impacts (reference {tr.size}), {len(runs)} shrinking sequences, longest {longest}, "
        f"smallest v {vmin:.3g} m/s, |dt| {dt:.2e} s, |dv|/v {dv:.2e}, core {wall:.3f} s")
    detail = (f"w = {omega} rad/s, b = {params.b}, [0, {t_end}] s, core rtol {rtol:g}; {len(runs)} sequences of >= "
              f"{min_len} impacts with shrinking velocity, longest {longest}, down to {vmin:.2g} m/s")
    return [
        row("chattering", f"{label}: impacts found by the core minus the reference's (SciPy DOP853 "
            "1e-13)", abs(t.size - tr.size), 0, "count", detail=detail),
        row("chattering", f"{label}: longest shrinking sequence in the reference (at least)", longest,
            min_len, "count", passed=longest >= min_len),
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
    log(f"bounce to rest w = {omega}: {t.size} impacts, last at {t[-1]:.4f} s, {a['n_stick']} sticks, "
        f"{a['n_implicit_steps']} implicit steps, {wall:.3f} s")
    return [
        row("chattering", f"bouncing to rest (w = {omega}, b = {params.b}): impacts in the last half of "
            f"[0, {t_end}] s, with the cart resting on the obstacle", int(np.count_nonzero(t > t_end / 2)), 0,
            "count", detail=f"{t.size} impacts, the last at {t[-1]:.4f} s; {a['n_stick']} stick phase(s)"),
        row("chattering", f"bouncing to rest: core wall time for {t_end} s", wall, 2.0, "s",
            detail=f"{a['n_steps']} explicit + {a['n_implicit_steps']} implicit steps, {a['n_rhs']} RHS evaluations"),
    ]


# ============================================================================== sticking

class CoulombOscillator:
    """Closed-form stick-slip solution of m x'' + c x' + k x = F0 sin(w t) - T sgn(x') with
    exact Coulomb friction (the eps -> 0 limit of model BC) and no obstacle.

    Why: an independent reference for sticking. Each slip piece is the linear oscillator's
    closed form with the constant force -T sgn(v); it ends where v = 0 (located by sampling
    v every `scan` s and brentq); the cart then sticks while |F0 sin(w t) - k x| <= T (the
    breakaway time again by sampling and brentq), or reverses at once.
    """

    def __init__(self, params: ModelParams, omega: float, scan: float = 2e-5):
        p = params
        if not p.c ** 2 < 4 * p.k * p.m:
            raise ValueError("the closed form assumes an underdamped oscillator (c^2 < 4 k m)")
        self.p, self.w, self.scan = p, omega, scan
        self.F0 = p.m0e * omega**2
        d = (p.k - p.m * omega**2) ** 2 + (p.c * omega) ** 2
        self.A = self.F0 * (p.k - p.m * omega**2) / d  # x_p = A sin + B cos - sigma T / k
        self.B = -self.F0 * p.c * omega / d
        self.alpha = p.c / (2 * p.m)
        self.wd = math.sqrt(p.k / p.m - self.alpha**2)
        self.pieces = []  # (t0, t1, kind, data)

    def _xp(self, t, sigma):
        w = self.w
        return (self.A * np.sin(w * t) + self.B * np.cos(w * t) - sigma * self.p.T / self.p.k,
                w * (self.A * np.cos(w * t) - self.B * np.sin(w * t)))

    def _slip_state(self, t, t0, c1, c2, sigma):
        tau = t - t0
        e, cs, sn = np.exp(-self.alpha * tau), np.cos(self.wd * tau), np.sin(self.wd * tau)
        xp, vp = self._xp(t, sigma)
        x = xp + e * (c1 * cs + c2 * sn)
        v = vp + e * (-self.alpha * (c1 * cs + c2 * sn) + self.wd * (-c1 * sn + c2 * cs))
        return x, v

    def _net(self, t, x):
        return self.F0 * np.sin(self.w * t) - self.p.k * x

    def _first_root(self, f, t0, t_end, sign0):
        """First t in (t0, t_end] where f changes from the sign `sign0`; None if none."""
        n = max(int(math.ceil((t_end - t0) / self.scan)), 1)
        grid = np.linspace(t0, t_end, n + 1)[1:]
        vals = f(grid)
        bad = np.flatnonzero(np.sign(vals) != sign0)
        if bad.size == 0:
            return None
        j = bad[0]
        lo = t0 + 1e-12 if j == 0 else grid[j - 1]
        if np.sign(f(lo)) != sign0:  # the sign changes at once (e.g. a stick of zero length)
            return lo
        return brentq(f, lo, grid[j], xtol=1e-15, rtol=1e-15)

    def solve(self, t_end: float, x0: float = 0.0, v0: float = 0.0):
        """Fill self.pieces on [0, t_end] from (x0, v0) at t = 0."""
        p, t, x, v = self.p, 0.0, x0, v0
        self.pieces = []
        while t < t_end:
            if v == 0.0 and abs(self._net(t, x)) <= p.T:
                # stick until the net force reaches T
                tb = self._first_root(lambda s: np.abs(self._net(s, x)) - p.T, t, t_end, -1.0)
                t1 = t_end if tb is None else tb
                self.pieces.append((t, t1, "stick", (x,)))
                t = t1
                continue
            sigma = np.sign(v) if v != 0.0 else np.sign(self._net(t, x))
            xp, vp = self._xp(t, sigma)
            c1 = x - xp
            c2 = (v - vp + self.alpha * c1) / self.wd
            ts = self._first_root(lambda s: self._slip_state(s, t, c1, c2, sigma)[1], t, t_end, sigma)
            t1 = t_end if ts is None else ts
            self.pieces.append((t, t1, "slip", (c1, c2, sigma)))
            x, v = self._slip_state(t1, t, c1, c2, sigma)
            x, v, t = float(x), 0.0 if ts is not None else float(v), t1
        return self

    def state(self, ts):
        """x, v at the times ts (within the solved span)."""
        ts = np.asarray(ts, float)
        x, v = np.empty_like(ts), np.zeros_like(ts)
        for t0, t1, kind, data in self.pieces:
            sel = (ts >= t0) & (ts <= t1)
            if kind == "stick":
                x[sel] = data[0]
            else:
                x[sel], v[sel] = self._slip_state(ts[sel], t0, *data)
        return x, v

    @property
    def stick_time(self) -> float:
        return sum(t1 - t0 for t0, t1, kind, _ in self.pieces if kind == "stick")

    @property
    def n_sticks(self) -> int:
        return sum(1 for *_, kind, _ in self.pieces if kind == "stick")


def stick_slip_case(ratios=(0.3, 0.6, 0.9, 0.95), omega=23.03, periods=10, eps_values=(1e-6, 1e-7, 1e-8, 1e-9),
                    v_th=1e-3, dt=1e-4, rtol=1e-10, atol=1e-12, log=print) -> list[dict]:
    """Dry friction T = ratio * F0 (F0 = m0e w^2, the forcing amplitude), obstacle out of
    reach: the cart sticks at most reversals. Against the closed-form Coulomb solution:

    * time spent with |v| < v_th (both sampled every dt): must agree to 2 samples per
      stick (the sampling) - the regularised creep is far below v_th;
    * max |x - x_Coulomb|, which for the regularised model is the creep ~ eps * t_stick,
      must shrink in proportion to eps (bound: 3 x the linear scaling from eps = 1e-6);
    * no collapse to explicit stability-limited steps: implicit steps per second stuck,
      against the explicit limit T / (m eps) steps per second, must stay below 1 %.
    """
    base = ModelParams()
    period = 2 * math.pi / omega
    t_end = periods * period
    F0 = base.m0e * omega**2
    rows = []
    for ratio in ratios:
        errs = {}
        for eps in eps_values:
            p = dataclasses.replace(base, T=ratio * F0, eps=eps, xI=1.0)
            ref = CoulombOscillator(p, omega).solve(t_end)
            t0 = time.perf_counter()
            res = simulate(omega, 0.0, t_end, params=p, rtol=rtol, atol=atol, window=Window(0.0, t_end, dt),
                           record=("poincare",))
            wall = time.perf_counter() - t0
            tw, xw, vw = res.trajectory["t"], res.trajectory["x"], res.trajectory["v"]
            xr, vr = ref.state(tw)
            stuck_core = np.count_nonzero(np.abs(vw) < v_th) * dt
            stuck_ref = np.count_nonzero(np.abs(vr) < v_th) * dt
            errs[eps] = float(np.abs(xw - xr).max())
            a = res.attrs
            rate = a["n_implicit_steps"] / max(a["time_implicit"], 1e-300)
            limit = p.T / (p.m * eps)
            log(f"T/F0 {ratio} eps {eps:g}: stuck {stuck_core:.4f} s (Coulomb {stuck_ref:.4f} s, "
                f"{ref.n_sticks} sticks, exact stick time {ref.stick_time:.4f} s), max|dx| {errs[eps]:.2e} m, "
                f"{a['n_implicit_steps']} implicit steps in {a['time_implicit']:.3f} s, wall {wall:.3f} s")
            if eps == eps_values[0]:
                detail = (f"w = {omega}, T = {p.T:.4g} N, {periods} periods; Coulomb: {ref.n_sticks} sticks, "
                          f"{ref.stick_time:.4f} s stuck; core wall {wall:.3f} s")
                rows.append(row("sticking", f"T = {ratio:g} F0, eps {eps:g}: |time with |v| < {v_th:g} m/s - "
                                "Coulomb's|", abs(stuck_core - stuck_ref), 2 * dt * max(ref.n_sticks, 1), "s",
                                detail=detail))
            rows.append(row("sticking", f"T = {ratio:g} F0, eps {eps:g}: implicit steps per stuck second / "
                            "explicit stability limit T/(m eps)", rate / limit, 0.01, "ratio",
                            detail=f"{a['n_implicit_steps']} implicit steps over {a['time_implicit']:.3f} s; wall "
                            f"{wall:.3f} s"))
        e0 = eps_values[0]
        for eps in eps_values[1:]:
            allowed = 3 * errs[e0] * eps / e0 + 1e-12
            rows.append(row("sticking", f"T = {ratio:g} F0: max |x - x_Coulomb| at eps {eps:g} (creep ~ eps; "
                            f"bound: 3 x eps-scaled value at eps {e0:g})", errs[eps], allowed, "m",
                            detail=f"{errs[e0]:.3g} m at eps {e0:g}"))
    return rows
