"""Branch segments: one continued branch of periodic orbits, sampled for the figures and the
table, with its special points located (the unit of work of one workflow job).

Why: a brute-force sweep sees only stable orbits and reads a bifurcation to its grid step. A
segment follows one branch by pseudo-arclength (:mod:`.arclength`), stable and unstable, and at
every point keeps what Figs 2 and 3b draw (the orbit's Poincare points and inter-impact
intervals) and what its stability is (multipliers). Between neighbouring points it watches
  - the number of impacts per orbit: a change is a grazing (the non-smooth bifurcation), located
    on the near-miss side by :func:`.grazing.locate_orbit_grazing`;
  - det(M + I): a period doubling, bisected in w (:func:`.bifurcation_points.locate`);
  - the tangent's w component: a fold (:func:`.arclength.locate_fold`).
No Neimark-Sacker point can exist in this model, and none is searched by bisection: by
Liouville's formula det M = exp(-int (c + friction slope + contact damping slope)/m dt), and
every slope is >= 0, so |mu|^2 = det M <= exp(-c N 2 pi / (m w)) < 1 for a complex pair. Every
sampled point stores det M and that bound, so the claim is checked on every branch.
"""

from __future__ import annotations

import itertools
import math
import time

import numpy as np

from impactosc.core.simulation import simulate, start_of
from impactosc.dynamics.arclength import BranchPoint, branch_points, locate_fold, switch_at_period_doubling
from impactosc.dynamics.bifurcation_points import TEST_FUNCTIONS, locate
from impactosc.dynamics.grazing import locate_orbit_grazing
from impactosc.dynamics.shooting import ATOL, RTOL, PeriodicOrbit, ShootingError, shoot
from impactosc.model.parameters import ModelParams

__all__ = ["drawn_values", "orbit_sample", "seed_from_rest", "special_points", "trace", "trace_segment"]


def orbit_sample(orbit: PeriodicOrbit, params: ModelParams | None = None) -> dict:
    """What the figures and the table keep of one orbit: w, its Poincare points (x, v at
    t = k 2 pi / w, k = 1..N; the last is the start), its inter-impact intervals (cyclic, from
    the first impact after phase 0), impacts per orbit, the smallest near-miss gap (m; inf
    without one), the multipliers, and det M beside Liouville's bound exp(-c N 2 pi / (m w))."""
    p = params or ModelParams()
    period = orbit.n_periods * 2 * math.pi / orbit.omega
    drawn = drawn_values(orbit.x0, orbit.v0, orbit.omega, orbit.n_periods, params, contact_v0=orbit.contact_v0)
    gaps = drawn["gaps"]
    return {
        "omega": orbit.omega,
        "x0": orbit.x0,
        "v0": orbit.v0,
        "poincare_x": drawn["poincare_x"].tolist(),
        "poincare_v": drawn["poincare_v"].tolist(),
        "isis": drawn["isis"].tolist(),
        "impacts": int(drawn["isis"].size),
        "min_gap": float(gaps.min()) if gaps.size else math.inf,
        "mu_re": orbit.multipliers.real.tolist(),
        "mu_im": orbit.multipliers.imag.tolist(),
        "stable": orbit.stable,
        "det": float(np.linalg.det(orbit.monodromy)),
        "det_bound": math.exp(-p.c / p.m * period),
        "residual": orbit.residual,
    }


def drawn_values(
    x0: float, v0: float, omega: float, n_periods: int, params: ModelParams | None = None, *, contact_v0=math.nan
) -> dict:
    """What Figs 2 and 3b draw of one orbit period from (x0, v0) at phase 0 (inside a restitution
    contact with its onset velocity `contact_v0`): the Poincare points (x, v at t = k 2 pi / w,
    k = 1..N), the inter-impact intervals (cyclic, from the first impact after phase 0) and the
    near-miss gaps, at the shooting's tolerances."""
    period = n_periods * 2 * math.pi / omega
    run = simulate(
        omega, 0.0, period, **start_of([x0, v0, contact_v0]), params=params, rtol=RTOL, atol=ATOL,
        record=("impacts", "near_misses", "poincare"),
    )  # fmt: skip
    t = run.events["impacts"]["t"]
    return {
        "poincare_x": np.asarray(run.events["poincare"]["x"]),
        "poincare_v": np.asarray(run.events["poincare"]["v"]),
        "isis": np.diff(np.append(t, t[0] + period)) if t.size else np.empty(0),
        "gaps": np.asarray(run.events["near_misses"]["gap"]),
    }


def seed_from_rest(omega: float, n_periods: int, params=None, *, settle_periods: int = 500) -> PeriodicOrbit:
    """The stable period-N orbit the time simulation from rest settles on at `omega`: the last
    Poincare point after `settle_periods` forcing periods, polished by shooting."""
    run = simulate(
        omega, settle_periods * 2 * math.pi / omega, 2 * math.pi / omega, params=params, rtol=RTOL, atol=ATOL,
        record=("poincare",),
    )  # fmt: skip
    y = [run.events["poincare"]["x"][-1], run.events["poincare"]["v"][-1], run.attrs["contact_v0"]]
    try:
        return shoot(y, omega, n_periods, params)
    except ShootingError as e:
        raise ShootingError(
            f"no period-{n_periods} orbit at w = {omega} near where the simulation from rest settles "
            f"({settle_periods} periods; x = {y[0]:.6e} m, v = {y[1]:.6e} m/s): {e}"
        ) from None


def trace(
    start: PeriodicOrbit, *, ds: float, w_range, max_points: int, params=None, direction=1.0, tangent=None
) -> tuple[list[BranchPoint], str]:
    """The branch from `start` (first) until w leaves `w_range` (that point is kept), after
    `max_points` points, or where the corrector gives up; and the reason it stopped."""
    points = []
    try:
        for point in branch_points(start, ds, params, direction=direction, tangent=tangent):
            points.append(point)
            if not w_range[0] <= point.orbit.omega <= w_range[1]:
                return points, f"w left [{w_range[0]}, {w_range[1]}]"
            if len(points) >= max_points:
                return points, f"{max_points} points"
    except ShootingError as e:
        return points, f"corrector failed: {e}"
    raise AssertionError("unreachable: branch_points has no end")


def _grazing(points, samples, i, params):
    """The grazing between points i and i + 1 (their impact counts differ), located from the
    near-miss side: that neighbour and the next point beyond it, or, where the branch has no
    such point (it ends there, or that point has another impact count), an orbit shot half a
    step further from the grazing. None where the near-miss side has no near miss."""
    near, far = (i, i + 1) if samples[i]["impacts"] < samples[i + 1]["impacts"] else (i + 1, i)
    if not math.isfinite(_gap(samples[near])):
        return None
    beyond = near + (near - far)
    orbit = points[near].orbit
    if (
        0 <= beyond < len(points)
        and samples[beyond]["impacts"] == samples[near]["impacts"]
        and math.isfinite(_gap(samples[beyond]))
    ):
        partner = points[beyond].orbit
    else:
        w = orbit.omega + 0.5 * (orbit.omega - points[far].orbit.omega)
        partner = shoot(orbit.state, w, orbit.n_periods, params)
    w, located, _ = locate_orbit_grazing(partner, orbit, params)
    return w, located


def _gap(sample) -> float:
    return math.inf if sample["min_gap"] is None else float(sample["min_gap"])


def _located(kind, omega, orbit, bracket, **extra) -> dict:
    return {
        "kind": kind,
        "omega": float(omega),
        "n_periods": orbit.n_periods,
        "x0": orbit.x0,
        "v0": orbit.v0,
        **({} if math.isnan(orbit.contact_v0) else {"contact_v0": orbit.contact_v0}),
        "mu_re": orbit.multipliers.real.tolist(),
        "mu_im": orbit.multipliers.imag.tolist(),
        "bracket": [float(w) for w in bracket],
        **extra,
    }


def _locate(kind, i, points, samples, params, tol) -> dict:
    a, b = points[i], points[i + 1]
    bracket = (a.orbit.omega, b.orbit.omega)
    if kind == "period_doubling":
        w, orbit = locate("period_doubling", a.orbit, b.orbit, params, tol=tol)
        return _located(kind, w, orbit, bracket, located=True)
    if kind == "fold":
        fold = locate_fold(a, b, params)
        return _located(kind, fold.orbit.omega, fold.orbit, bracket, located=True)
    hit = _grazing(points, samples, i, params)
    if hit is None:
        return _located(
            kind, np.mean(bracket), a.orbit, bracket, located=False, why="no two near-miss orbits beside it"
        )
    return _located(kind, hit[0], hit[1], bracket, located=True)


def _near_one(orbit: PeriodicOrbit, within: float = 0.2) -> bool:
    """A multiplier within `within` of +1: where a smooth fold's neighbours are."""
    return bool(np.any(np.abs(orbit.multipliers - 1.0) < within))


def _text(orbit: PeriodicOrbit) -> str:
    return ", ".join(f"{m.real:.3g}" if abs(m.imag) < 1e-12 else f"{m:.3g}" for m in orbit.multipliers)


def special_points(points: list[BranchPoint], samples: list[dict], params=None, *, tol: float = 1e-9) -> list[dict]:
    """Grazings, period doublings and folds between neighbouring points of one traced branch,
    each located (tol rad/s for the doubling; the grazing and the fold to their own accuracy,
    see their functions). A point that cannot be located is listed with `located` False and
    the reason, so the table shows the bracket instead of dropping it."""
    found = []
    pd = TEST_FUNCTIONS["period_doubling"]
    for i, (a, b) in enumerate(itertools.pairwise(points)):
        bracket = (a.orbit.omega, b.orbit.omega)
        kinds = []
        if samples[i]["impacts"] != samples[i + 1]["impacts"]:
            kinds.append("grazing")
        elif pd(a.orbit.monodromy) * pd(b.orbit.monodromy) < 0:
            kinds.append("period_doubling")
        if a.tangent[2] * b.tangent[2] < 0:
            kinds.append("fold")
        sides = {  # the neighbours: a grazing makes the multipliers jump
            "impacts": [samples[i]["impacts"], samples[i + 1]["impacts"]],
            "w_before": samples[i]["omega"], "w_after": samples[i + 1]["omega"],
            "mu_before_re": samples[i]["mu_re"], "mu_before_im": samples[i]["mu_im"],
            "mu_after_re": samples[i + 1]["mu_re"], "mu_after_im": samples[i + 1]["mu_im"],
        }  # fmt: skip
        for kind in kinds:
            try:
                found.append({**_locate(kind, i, points, samples, params, tol), **sides})
            except (ShootingError, ValueError) as e:
                why = str(e)
                if kind == "fold" and not _near_one(a.orbit) and not _near_one(b.orbit):
                    why = (f"a non-smooth turn of the branch: no multiplier near +1 on either side "
                           f"(they jump from {_text(a.orbit)} to {_text(b.orbit)}); {why}")  # fmt: skip
                found.append(_located(kind, np.mean(bracket), a.orbit, bracket, located=False, why=why, **sides))
    return found


def trace_segment(
    *, seed: PeriodicOrbit | None = None, parent_doubling: dict | None = None, ds: float, w_range,
    max_points: int, params=None, tol: float = 1e-9, log=None,
) -> dict:  # fmt: skip
    """One branch segment, as the workflow stores it: from a `seed` orbit followed both ways,
    or from a located period doubling of the parent branch (`parent_doubling`, an entry of its
    special points) switched onto the doubled branch and followed away from it. Returns the
    samples in branch order, the special points, why each end stopped and the cost."""
    wall, cpu = time.perf_counter(), time.process_time()
    if (seed is None) == (parent_doubling is None):
        raise ValueError("give exactly one of seed and parent_doubling")
    options = {"ds": ds, "w_range": w_range, "max_points": max_points, "params": params}
    if seed is not None:
        down, why_down = trace(seed, direction=-1.0, **options)
        up, why_up = trace(seed, direction=1.0, **options)
        # the downward points, reversed, with their tangents turned to the branch's direction
        down = [BranchPoint(p.orbit, -p.tangent) for p in down[::-1]]
        points, stops = down + up[1:], {"start": why_down, "end": why_up}
    else:
        d = parent_doubling
        at = shoot([d["x0"], d["v0"], d.get("contact_v0", math.nan)], d["omega"], d["n_periods"], params)
        first = switch_at_period_doubling(at, params)[-1]
        points, why = trace(first.orbit, tangent=first.tangent, **options)
        stops = {"start": f"period doubling of the period-{d['n_periods']} branch at w = {d['omega']:.10f}", "end": why}
    if log:
        log(f"{len(points)} points, w from {points[0].orbit.omega:.4f} to {points[-1].orbit.omega:.4f}; locating")
    samples = [orbit_sample(p.orbit, params) for p in points]
    special = special_points(points, samples, params, tol=tol)
    return {
        "n_periods": points[0].orbit.n_periods,
        "points": samples,
        "special_points": special,
        "stops": stops,
        "wall_seconds": time.perf_counter() - wall,
        "cpu_seconds": time.process_time() - cpu,
    }
