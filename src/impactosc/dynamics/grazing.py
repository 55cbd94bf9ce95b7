"""Locate the grazing bifurcation: a near miss of the obstacle turns into a contact.

Why a dedicated module: the paper places a grazing bifurcation "at about w = 23" (between
23.05 and 23.03 rad/s on the branch followed with decreasing w) by eye. Here it is located
from the model: follow the attractor in w (:func:`impactosc.dynamics.sweep.continuation`), track the
smallest free-flight gap ``xI - max x`` (near miss) and the impacts per forcing period, find
the step of the branch where the near miss closing on zero is replaced by a contact
(:func:`find_grazing_step`), and bisect that step from the branch's own state
(:func:`bisect_transition`) until the bracket is narrower than a tolerance. The gap of a
near miss is a smooth function of w, so a straight line through the last gaps before the
transition gives an independent estimate of the zero (:func:`extrapolate_gap_zero`).

The generic pieces (:func:`find_grazing_step`, :func:`bisect_transition`,
:func:`extrapolate_gap_zero`) take plain arrays and callables so they are tested on
synthetic gap curves; :func:`model_trial` and :func:`locate_grazing` bind them to the core.

A second locator, :func:`grazing_by_clearance_secant`, finds where the clearance of one
orbit's near miss is zero (a secant in w), for runs that must set the depth or gap itself.

A third, :func:`locate_orbit_grazing`, treats the grazing of a periodic orbit (stable or not)
as a continuation event. At a grazing the orbit touches the obstacle with zero velocity; there
the stroboscopic map is not smooth (a square-root singularity of the new low-velocity impact),
so no test function of the monodromy matrix sees it. Along a branch followed in w, the smallest
gap between the obstacle and the orbit's free-flight maxima falls linearly to zero; past it the
near miss has become an impact. Bisection on "the orbit still has that near miss" locates it.

The paper's grazing claim (the attractor at its two w values, the evidence table) is the
study's: :mod:`impactosc_study.grazing_evidence`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np

from impactosc.core.simulation import Window, simulate, start_of
from impactosc.dynamics.shooting import ATOL, DEFAULT_STEP, RTOL, SCALE, PeriodicOrbit, ShootingError, shoot
from impactosc.dynamics.sweep import continuation
from impactosc.dynamics.sweep_chunks import merge_chunks

__all__ = [
    "Trial",
    "GrazingBracket",
    "GapFit",
    "find_grazing_step",
    "bisect_transition",
    "extrapolate_gap_zero",
    "sweep_summary",
    "model_trial",
    "locate_grazing",
    "scan_from_rest",
    "settle_orbit",
    "grazing_by_clearance_secant",
    "locate_orbit_grazing",
    "orbit_events",
]


@dataclass(frozen=True)
class Trial:
    """One evaluation of the attractor at a single w during the bisection.

    contact: True if the near miss of the branch became a contact (the impacts per
    forcing period changed); min_gap (m, NaN if no near miss), min_impact_v (m/s, NaN if
    no impact) and impacts_per_period describe the recorded attractor; x_end, v_end its
    end state (a whole number of forcing periods after the restart, i.e. at phi = 0).
    """

    omega: float
    contact: bool
    min_gap: float = math.nan
    min_impact_v: float = math.nan
    impacts_per_period: float = math.nan
    x_end: float = math.nan
    v_end: float = math.nan
    contact_v0_end: float = math.nan  # m/s: onset velocity of a restitution contact the end state lies in


@dataclass(frozen=True)
class GrazingBracket:
    """Bracket [omega_contact, omega_miss] (either order in w) around the grazing w.

    omega_miss: the w closest to grazing at which the near miss is still a miss;
    omega_contact: the w closest to grazing at which it is a contact; trials: every
    bisection evaluation in the order made.
    """

    omega_miss: float
    omega_contact: float
    trials: tuple = field(default=())

    @property
    def width(self) -> float:
        return abs(self.omega_miss - self.omega_contact)

    @property
    def midpoint(self) -> float:
        return 0.5 * (self.omega_miss + self.omega_contact)

    def to_dict(self) -> dict:
        return {
            "omega_miss": self.omega_miss,
            "omega_contact": self.omega_contact,
            "width": self.width,
            "midpoint": self.midpoint,
            "trials": [asdict(t) for t in self.trials],
        }


def _as_1d(values, name: str, allow_nan: bool = False) -> np.ndarray:
    a = np.asarray(values, dtype=float)
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array, got shape {a.shape}")
    bad = ~np.isfinite(a) if not allow_nan else np.isinf(a)
    if bad.any():
        raise ValueError(f"{name} contains non-finite values at index {int(np.flatnonzero(bad)[0])}")
    return a


def find_grazing_step(omegas, min_gap, impacts_per_period) -> int:
    """Index i of the branch step (i -> i+1) where a near miss closing on zero became a contact.

    Why: a branch followed in w passes several transitions (period doublings, jumps); the
    grazing one is where the impact count per period changes right after the smallest
    near-miss gap of the branch. Among all steps where impacts_per_period changes and
    point i had a near miss (finite gap), the one with the smallest gap at i is returned.

    Parameters: arrays in branch order (the order w was followed); min_gap in m, NaN where
    the attractor had no near miss; impacts_per_period as measured over the record.
    Raises ValueError when no such step exists (the branch never grazes).
    """
    w = _as_1d(omegas, "omegas")
    g = _as_1d(min_gap, "min_gap", allow_nan=True)
    n = _as_1d(impacts_per_period, "impacts_per_period")
    if not (w.size == g.size == n.size):
        raise ValueError(f"omegas, min_gap and impacts_per_period differ in length: {w.size}, {g.size}, {n.size}")
    if w.size < 2:
        raise ValueError("a branch needs at least 2 points to contain a transition")
    changed = ~np.isclose(n[1:], n[:-1], rtol=0, atol=1e-9)
    candidates = np.flatnonzero(changed & np.isfinite(g[:-1]) & (g[:-1] > 0))
    if candidates.size == 0:
        raise ValueError(
            "no step of the branch turns a near miss into a contact "
            "(impacts per period never change right after a near miss)"
        )
    return int(candidates[np.argmin(g[candidates])])


def bisect_transition(
    trial: Callable[[float, object], Trial],
    omega_miss: float,
    omega_contact: float,
    state,
    tol: float,
    max_trials: int = 60,
) -> GrazingBracket:
    """Shrink [omega_miss, omega_contact] to width <= tol by bisection on w.

    Why: locating the grazing w to a stated resolution rather than to the sweep step.
    ``trial(w, state)`` evaluates the attractor at w starting from `state` (the end state at
    the current miss end, so every trial continues the branch by a step smaller than the
    bracket) and returns a :class:`Trial`; a miss moves omega_miss (and the state) to w, a
    contact moves omega_contact.
    """
    for name, value in (("omega_miss", omega_miss), ("omega_contact", omega_contact), ("tol", tol)):
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value):
            raise ValueError(f"{name} must be a finite number, got {value!r}")
    if tol <= 0:
        raise ValueError(f"tol must be > 0, got {tol}")
    if omega_miss == omega_contact:
        raise ValueError("omega_miss and omega_contact must differ")
    lo_miss, hi_contact = float(omega_miss), float(omega_contact)
    trials = []
    while abs(lo_miss - hi_contact) > tol:
        if len(trials) >= max_trials:
            raise ValueError(f"bisection did not reach tol={tol} in {max_trials} trials")
        w = 0.5 * (lo_miss + hi_contact)
        t = trial(w, state)
        if not isinstance(t, Trial):
            raise ValueError("trial must return a Trial")
        trials.append(t)
        if t.contact:
            hi_contact = w
        else:
            lo_miss, state = w, (t.x_end, t.v_end, t.contact_v0_end)
    return GrazingBracket(lo_miss, hi_contact, tuple(trials))


@dataclass(frozen=True)
class GapFit:
    """Straight line gap = slope (w - omega_zero) through the last near-miss gaps.

    omega_zero (rad/s) where the fitted gap vanishes; slope in m per rad/s; rms residual
    (m) of the fit; omega (the w used, rad/s).
    """

    omega_zero: float
    slope: float
    rms: float
    omega: tuple

    def to_dict(self) -> dict:
        return {"omega_zero": self.omega_zero, "slope": self.slope, "rms": self.rms, "omega": list(self.omega)}


def extrapolate_gap_zero(omegas, gaps, n_fit: int = 5) -> GapFit:
    """Least-squares line through the last `n_fit` (w, gap) points and its zero.

    Why: an independent estimate of the grazing w that does not depend on how trials
    classify contacts; the gap of a regular near miss is smooth (linear to first order) in
    w near grazing. Points are in branch order, the last one closest to grazing; all gaps
    must be finite and > 0.
    """
    w = np.asarray(omegas, dtype=float)
    g = np.asarray(gaps, dtype=float)
    if w.ndim != 1 or w.shape != g.shape:
        raise ValueError(f"omegas and gaps must be 1-D of equal length, got shapes {w.shape}, {g.shape}")
    if not isinstance(n_fit, (int, np.integer)) or n_fit < 2:
        raise ValueError(f"n_fit must be an integer >= 2, got {n_fit!r}")
    if w.size < n_fit:
        raise ValueError(f"need at least n_fit={n_fit} points, got {w.size}")
    w, g = _as_1d(w[-n_fit:], "omegas"), _as_1d(g[-n_fit:], "gaps")
    if np.any(g <= 0):
        raise ValueError("gaps must be > 0 (near misses, not contacts)")
    slope, intercept = np.polyfit(w, g, 1)
    if slope == 0:
        raise ValueError("the gaps do not change with w; no zero to extrapolate")
    resid = g - (slope * w + intercept)
    return GapFit(float(-intercept / slope), float(slope), float(np.sqrt(np.mean(resid**2))), tuple(map(float, w)))


def sweep_summary(result) -> dict:
    """Per-w arrays of a :class:`impactosc.dynamics.sweep.SweepResult` that grazing needs.

    impacts_per_period (impacts in the record / recorded periods), min_impact_v (m/s, NaN
    without impacts), min_gap (m), omega; arrays in sweep order.
    """
    n_rec = result.poincare_x.shape[1]
    counts = np.diff(result.impact_offsets)
    min_v = np.array(
        [
            result.impact_v[a:b].min() if b > a else np.nan
            for a, b in zip(result.impact_offsets[:-1], result.impact_offsets[1:])
        ]
    )
    return {
        "omega": result.omega.copy(),
        "impacts_per_period": counts / n_rec,
        "min_impact_v": min_v,
        "min_gap": result.min_gap.copy(),
    }


def model_trial(settings, reference_impacts_per_period: float) -> Callable[[float, object], Trial]:
    """A :func:`bisect_transition` trial that runs the core at one w from a branch state.

    The attractor is classified as a contact when its impacts per forcing period differ
    from `reference_impacts_per_period` (that of the branch just before grazing).
    """

    def trial(omega: float, state) -> Trial:
        res = continuation([omega], settings, **start_of(state), first_transient=settings.n_transient)
        s = sweep_summary(res)
        ipp = float(s["impacts_per_period"][0])
        return Trial(
            omega=float(omega),
            contact=not math.isclose(ipp, reference_impacts_per_period, abs_tol=1e-9),
            min_gap=float(s["min_gap"][0]),
            min_impact_v=float(s["min_impact_v"][0]),
            impacts_per_period=ipp,
            x_end=float(res.x_end[0]),
            v_end=float(res.v_end[0]),
            contact_v0_end=float(res.contact_v0_end[0]),
        )

    return trial


def locate_grazing(branch, settings, tol: float) -> GrazingBracket:
    """Bracket the grazing w of a followed branch (a SweepResult in branch order) to `tol`.

    The bisection starts from the branch step found by :func:`find_grazing_step`, from the
    branch's end state at the miss side, with the same per-w lengths as the branch.
    """
    s = sweep_summary(branch)
    i = find_grazing_step(s["omega"], s["min_gap"], s["impacts_per_period"])
    trial = model_trial(settings, float(s["impacts_per_period"][i]))
    return bisect_transition(
        trial, float(s["omega"][i]), float(s["omega"][i + 1]),
        (float(branch.x_end[i]), float(branch.v_end[i]), float(branch.contact_v0_end[i])), tol,
    )  # fmt: skip


def scan_from_rest(omegas, settings, transient: float, progress=None):
    """Each w started from rest (x = v = 0 at t = 0): the attractor a single scene reaches.

    Why: the paper's scenes (Figs 4, 5) are single runs from rest; with coexisting
    attractors they need not sit on the branch. Each w discards `transient` seconds rounded
    up to whole forcing periods, then records settings.n_record periods. Returns one
    :class:`impactosc.dynamics.sweep.SweepResult` over `omegas` (monotone).
    """
    if not (isinstance(transient, (int, float, np.floating)) and math.isfinite(transient) and transient >= 0):
        raise ValueError(f"transient must be a finite number >= 0 s, got {transient!r}")
    parts = []
    for k, w in enumerate(np.asarray(omegas, dtype=float)):
        n_tr = int(math.ceil(transient * w / (2 * math.pi) - 1e-9))
        parts.append(continuation([w], settings, x0=0.0, v0=0.0, first_transient=n_tr))
        if progress is not None:
            progress(k, len(omegas), float(w))
    return merge_chunks(parts)


# ---------------------------------------------------------------- grazing of an orbit, by secant


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
    """Continue the attractor from `state` (x, v at phase 0, and a restitution contact's onset
    velocity inside one: the end state it returns) for `periods` forcing periods,
    record `record_periods` more; returns (signed clearance, its time, end state, result).

    The signed clearance is the x maximum closest to the obstacle: +depth of a contact,
    -gap of a near miss; the result records impacts, penetrations, near misses and the
    Poincare section (and the trajectory every `window_dt` s if given).
    """
    period = 2 * math.pi / omega
    t0, t1 = periods * period, (periods + record_periods) * period
    win = Window(t0, t1, window_dt) if window_dt else None
    res = simulate(
        omega,
        t0,
        t1 - t0,
        **start_of(state),
        params=params,
        rtol=rtol,
        atol=atol,
        window=win,
        record=("impacts", "penetrations", "near_misses", "poincare"),
    )
    g, tg = _signed_clearance(res.events)
    pc = res.events["poincare"]
    return g, tg, (float(pc["x"][-1]), float(pc["v"][-1]), res.attrs["contact_v0"]), res


def grazing_by_clearance_secant(
    params, w_far=23.06, w_near=23.05, settle_from_rest=800, periods=150, tol=1e-12, max_iter=12
):
    """Grazing w of the period-1 branch to `tol` metres of clearance: secant on the signed
    clearance g(w) of its near miss (:func:`settle_orbit`), each orbit continued from the
    previous one. Returns (w*, slope dg/dw, state at phase 0 of the orbit at w*).

    Unlike :func:`locate_grazing` (bisection on the impact count of a followed branch, a
    bracket for the paper's table) this converges on g = 0 itself, so that w can be set to
    give a contact or near miss of a chosen size (the grazing hard case,
    :mod:`impactosc_bench.hardcases.grazing_sweep`).
    """
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


def orbit_events(orbit: PeriodicOrbit, params=None) -> dict:
    """Impacts per orbit and the smallest near-miss gap (m; inf without a near miss) of one
    period of the orbit, from the core run over it."""
    run = simulate(
        orbit.omega, 0.0, orbit.n_periods * 2 * math.pi / orbit.omega, **start_of(orbit.state),
        params=params, rtol=RTOL, atol=ATOL, record=("impacts", "near_misses"),
    )  # fmt: skip
    gaps = run.events["near_misses"]["gap"]
    return {"impacts": int(run.events["impacts"]["t"].size), "min_gap": float(gaps.min()) if gaps.size else math.inf}


def locate_orbit_grazing(
    a: PeriodicOrbit, b: PeriodicOrbit, params=None, *, gap_floor: float = 1e-9, max_steps: int = 30
):
    """w where the smallest near-miss gap of a branch reaches zero, from two of its orbits
    (`a`, `b`, both with the near miss): secant steps on gap(w) = 0, each new orbit shot from
    the last, until the gap is below `gap_floor`; then the parabola through the last three
    points gives the grazing. Near the obstacle each orbit is shot with difference steps of
    1e-3 of the current gap, so that the monodromy's perturbed orbits miss the obstacle too
    (with the default 0.1 um they reach it once the gap is below 0.2 um, and the branch's
    Newton stalls). On model BC's period-1 branch, floors 1e-6, 1e-7, 1e-8 and 1e-9 m give
    23.04412235, 23.044122337, 23.044122336048 and 23.044122336048 rad/s, and two different
    starting pairs agree to 2e-8, 1e-9, 4e-13 and 4e-15 rad/s at those floors.
    Returns (w at zero gap, the orbit nearest to it, its gap in m)."""
    pts = [(o, orbit_events(o, params)["min_gap"]) for o in (a, b)]
    if not all(math.isfinite(g) and g > 0 for _, g in pts):
        raise ValueError("both orbits must have a near miss (a finite, positive gap) to follow to a grazing")
    for _ in range(max_steps):
        (o1, g1), (o2, g2) = pts[-2], pts[-1]
        w_zero = o2.omega - g2 * (o2.omega - o1.omega) / (g2 - g1)
        if g2 < gap_floor:
            return _quadratic_zero(pts[-3:], w_zero), o2, g2
        # aim at half the floor's gap rather than at zero, so the next orbit stays shootable
        w_next = o2.omega + (w_zero - o2.omega) * (1 - 0.5 * gap_floor / g2)
        # difference steps well inside the gap, so that the monodromy's perturbed orbits miss
        # the obstacle too (1e-3 of it: the map is still resolved, the core's error is 1e-14 m)
        step = min(DEFAULT_STEP, 1e-3 * g2 / SCALE[0])
        o3 = shoot(o2.state, w_next, o2.n_periods, params, step=step)
        g3 = orbit_events(o3, params)["min_gap"]
        if not (math.isfinite(g3) and g3 > 0):
            raise ShootingError(f"the near miss vanished at w = {w_next} before the gap fell below {gap_floor} m")
        pts.append((o3, g3))
    raise ShootingError(f"grazing: the gap did not fall below {gap_floor} m in {max_steps} steps")


def _quadratic_zero(pts, w_linear: float) -> float:
    """Root nearest `w_linear` of the parabola through (w, gap) of the last three points (the
    straight line's root where there are only two)."""
    if len(pts) < 3:
        return w_linear
    w = np.array([o.omega for o, _ in pts])
    roots = np.roots(np.polyfit(w - w_linear, [g for _, g in pts], 2))
    real = roots[np.isreal(roots)].real
    return float(w_linear + real[np.argmin(np.abs(real))]) if real.size else w_linear
