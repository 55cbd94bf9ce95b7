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
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import numpy as np

from impactosc.core.simulate import Window, simulate
from impactosc.dynamics.sweep import continuation, load_sweep
from impactosc.dynamics.sweep_chunks import merge_chunks
from impactosc.io.files import read_json
from impactosc.statistics.periods import poincare_period
from impactosc_study.paper.numbers import GRAZING

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
    "branch_grid",
    "grazing_statistics",
    "scan_from_rest",
    "regular_grid",
    "grazing_summary_file",
    "settle_orbit",
    "grazing_by_clearance_secant",
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
            lo_miss, state = w, (t.x_end, t.v_end)
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
        res = continuation([omega], settings, x0=state[0], v0=state[1], first_transient=settings.n_transient)
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
        trial, float(s["omega"][i]), float(s["omega"][i + 1]), (float(branch.x_end[i]), float(branch.v_end[i])), tol
    )


def branch_grid(start: float, fine_from: float, stop: float, coarse_step: float, fine_step: float) -> np.ndarray:
    """Decreasing w grid: start, start - coarse_step, ... (> fine_from), then fine_from to stop by fine_step.

    Why: the paper follows the attractor down from w = 40.86; only the neighbourhood of
    the grazing needs fine steps. Grid points are start - i*step rounded to 1e-9 rad/s, so
    round values such as 23.05 and 23.03 are hit exactly when they lie on the fine grid.
    """
    vals = {"start": start, "fine_from": fine_from, "stop": stop, "coarse_step": coarse_step, "fine_step": fine_step}
    for name, value in vals.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if not start >= fine_from > stop:
        raise ValueError(f"need start >= fine_from > stop (a decreasing branch), got {start}, {fine_from}, {stop}")
    n_c = int(math.floor((start - fine_from) / coarse_step * (1 + 1e-12)))
    coarse = np.round(start - coarse_step * np.arange(n_c + 1), 9)
    coarse = coarse[coarse > fine_from + 1e-9]
    n_f = int(math.floor((fine_from - stop) / fine_step * (1 + 1e-12)))
    fine = np.round(fine_from - fine_step * np.arange(n_f + 1), 9)
    return np.concatenate([coarse, fine])


def _attractor_at(summary: dict, omega: float, periods=None) -> dict | None:
    w = np.asarray(summary["omega"])
    i = int(np.argmin(np.abs(w - omega)))
    if abs(w[i] - omega) > 1e-9:
        return None
    out = {k: float(np.asarray(summary[k])[i]) for k in ("impacts_per_period", "min_gap", "min_impact_v")}
    if periods is not None:
        out["period"] = int(periods[i])
    return out


def grazing_statistics(
    branch: dict,
    bracket: dict,
    from_rest: dict,
    paper_omegas=GRAZING["omegas"],
    n_fit: int = 5,
    branch_periods=None,
    rest_periods=None,
) -> dict:
    """Everything the grazing claim rests on, as a JSON-ready dict.

    branch / from_rest: per-w summaries (:func:`sweep_summary`), branch in branch order;
    bracket: :meth:`GrazingBracket.to_dict`. Adds the straight-line gap extrapolation, the
    attractor at each paper w on the branch and from rest, where w_g sits relative to the
    paper's w values, and the from-rest grid points on either side of the attractor switch.
    """
    i = find_grazing_step(branch["omega"], branch["min_gap"], branch["impacts_per_period"])
    fit = extrapolate_gap_zero(branch["omega"][: i + 1], branch["min_gap"][: i + 1], n_fit)
    wg = 0.5 * (bracket["omega_miss"] + bracket["omega_contact"])
    ref = float(branch["impacts_per_period"][i])
    pre = float(np.asarray(branch["omega"])[i])
    out = {
        "omega_g": wg,
        "bracket": bracket,
        "branch_step": {
            "omega_miss": pre,
            "omega_contact": float(branch["omega"][i + 1]),
            "impacts_per_period_before": ref,
            "impacts_per_period_after": float(branch["impacts_per_period"][i + 1]),
        },
        "gap_fit": fit.to_dict(),
        "fit_minus_bracket": fit.omega_zero - wg,
        "fit_inside_bracket": bool(
            min(bracket["omega_miss"], bracket["omega_contact"])
            <= fit.omega_zero
            <= max(bracket["omega_miss"], bracket["omega_contact"])
        ),
        "paper_omegas": list(map(float, paper_omegas)),
        "between_paper_omegas": bool(min(paper_omegas) < wg < max(paper_omegas)),
        "branch_at_paper_omegas": {f"{w:g}": _attractor_at(branch, w, branch_periods) for w in paper_omegas},
        "from_rest_at_paper_omegas": {f"{w:g}": _attractor_at(from_rest, w, rest_periods) for w in paper_omegas},
    }
    # from rest: which grid points land on the pre-grazing orbit (ref impacts per period
    # with a near miss) and which on something else
    rw = np.asarray(from_rest["omega"])
    on_pre = np.isclose(np.asarray(from_rest["impacts_per_period"]), ref, atol=1e-9) & np.isfinite(
        np.asarray(from_rest["min_gap"])
    )
    out["from_rest_on_pre_grazing_orbit"] = {"omega": rw[on_pre].tolist(), "other": rw[~on_pre].tolist()}
    return out


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


def regular_grid(start: float, stop: float, step: float) -> np.ndarray:
    """start, start +/- step, ... up to stop inclusive, rounded to 1e-9 (hits round values exactly)."""
    for name, value in (("start", start), ("stop", stop), ("step", step)):
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    n = int(math.floor(abs(stop - start) / step * (1 + 1e-12)))
    return np.round(start + math.copysign(step, stop - start) * np.arange(n + 1), 9)


def grazing_summary_file(
    branch_path, bisection_path, from_rest_path, paper_omegas=GRAZING["omegas"], n_fit: int = 5
) -> dict:
    """:func:`grazing_statistics` from the workflow's files, plus the per-w arrays to plot.

    Each per-w summary gets the Poincare period of the recorded attractor (forcing
    periods, 0 = none up to half the record: chaotic or unsettled).
    """
    branch, _ = load_sweep(branch_path)
    rest, _ = load_sweep(from_rest_path)
    bracket = read_json(bisection_path)
    summaries = {}
    for name, sweep in (("branch", branch), ("from_rest", rest)):
        s = sweep_summary(sweep)
        s["period"] = np.array([poincare_period(x, v) for x, v in zip(sweep.poincare_x, sweep.poincare_v)])
        summaries[name] = s
    for t in bracket["trials"]:  # JSON null -> NaN
        for k in ("min_gap", "min_impact_v"):
            t[k] = math.nan if t[k] is None else t[k]
    out = grazing_statistics(
        summaries["branch"],
        bracket,
        summaries["from_rest"],
        paper_omegas,
        n_fit,
        summaries["branch"]["period"],
        summaries["from_rest"]["period"],
    )
    out["per_w"] = {name: {k: np.asarray(v).tolist() for k, v in s.items()} for name, s in summaries.items()}
    return out


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
    """Continue the attractor from `state` (x, v at phase 0) for `periods` forcing periods,
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
        x0=state[0],
        v0=state[1],
        params=params,
        rtol=rtol,
        atol=atol,
        window=win,
        record=("impacts", "penetrations", "near_misses", "poincare"),
    )
    g, tg = _signed_clearance(res.events)
    pc = res.events["poincare"]
    return g, tg, (float(pc["x"][-1]), float(pc["v"][-1])), res


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
