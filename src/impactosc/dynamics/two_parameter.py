"""A codimension-one bifurcation of periodic orbits followed in a second parameter (xI or m0e).

Why: the one-parameter table locates each bifurcation in w at the paper's obstacle and
unbalance; a two-parameter diagram shows how it moves with the obstacle (or the unbalance), and
where two such curves meet (codimension two) the dynamics changes character. A curve point is a
zero of an extended system in z = (x, v, w, p):
    P^N(y; w, p) - y = 0      the orbit (the shooting's stroboscopic map, y = (x, v) at phase 0)
    c(y; w, p) = 0            the bifurcation's defining condition:
      period doubling   det(M + I)                (M: shooting.monodromy, a multiplier at -1)
      fold              det(M - I)                (a multiplier at +1)
      grazing           the signed gap of the grazing excursion: xI - x at the free-flight maximum
                        that touches the obstacle (its velocity is zero there by definition),
                        continued past zero by minus the penetration of the contact it becomes
Three equations in four unknowns: a curve, followed by pseudo-arclength (Keller) in all four
scaled coordinates (x / 1 mm, v / 0.1 m/s, w / 1 rad/s, p / PARAMETER_SCALES), so that it can
turn in w and in p, and pass a cusp, where its (w, p) projection stops and turns back.

The grazing condition is smooth enough for Newton: with a contact force ~ h^1.5 a graze of depth
d changes the velocity by O(d^2), so the penetration equals the obstacle-free maximum to that
order and the map is C^1 through the grazing. The monodromy's difference stencil touches the
obstacle there, and M's error grows with the step: against the variational equations at the
paper's grazing, 1e-1 of max |M| at the default step 1e-4 of the scale, 1e-3 at 1e-6, 1e-4 at
1e-7, 2e-5 at 3e-8 and 3e-5 at 1e-8 (the solver's noise). A grazing curve uses 3e-8 (30 pm,
3 nm/s). The error of the Jacobian slows Newton, not the point it converges to.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

import numpy as np

from impactosc.core.simulation import simulate, start_of
from impactosc.dynamics.arclength import _tangent
from impactosc.dynamics.bifurcation_points import TEST_FUNCTIONS
from impactosc.dynamics.shooting import (
    ATOL,
    DEFAULT_STEP,
    RTOL,
    SCALE,
    PeriodicOrbit,
    ShootingError,
    _multipliers,
    central_difference,
    require_free_section,
    stroboscopic_map,
)
from impactosc.dynamics.shooting import monodromy as shooting_monodromy
from impactosc.model.parameters import ModelParams

__all__ = [
    "KINDS",
    "PARAMETER_SCALES",
    "Curve",
    "CurvePoint",
    "CurveProblem",
    "codim_two_points",
    "curve_record",
    "excursions",
    "point_at",
    "start_point",
    "trace_curve",
]

KINDS = ("period_doubling", "fold", "grazing")
PARAMETER_SCALES = {"xI": 1e-3, "m0e": 1e-3}  # m, kg m: one scaled unit of the second parameter
W_STEP = 1e-5  # rad/s: difference step of dP/dw (as arclength.W_STEP)
P_STEP = 1e-5  # difference step of dP/dp, in scaled units
C_STEP = 1e-4  # difference step of the gradient of the condition c, in scaled units
GRAZING_STEP = 3e-8  # monodromy difference step on a grazing curve (module docstring)
# Newton stops at a step below this (scaled): det(M + I) carries ~1e-9 of difference noise, so a
# period doubling's w jitters by ~5e-9 rad/s between iterations and a tighter stop is never met
NEWTON_TOL = 1e-8
MAX_TURN = math.radians(30)  # largest turn of the tangent in one accepted step


@dataclass(frozen=True)
class CurveProblem:
    """What is continued: the kind of bifurcation of period-N orbits, the second parameter and
    the model around it (its own value of that parameter is where curves start)."""

    kind: str
    parameter: str
    n_periods: int
    params: ModelParams = dataclasses.field(default_factory=ModelParams)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {self.kind!r}")
        if self.parameter not in PARAMETER_SCALES:
            raise ValueError(f"parameter must be one of {sorted(PARAMETER_SCALES)}, got {self.parameter!r}")
        if int(self.n_periods) < 1:
            raise ValueError(f"n_periods must be >= 1, got {self.n_periods}")

    @property
    def p_scale(self) -> float:
        return PARAMETER_SCALES[self.parameter]

    @property
    def step(self) -> float:
        return GRAZING_STEP if self.kind == "grazing" else DEFAULT_STEP

    def model(self, value: float) -> ModelParams:
        return dataclasses.replace(self.params, **{self.parameter: float(value)})

    def unscaled(self, z):
        """(y, w, p) of scaled z = (x, v, w, p)."""
        return z[:2] * SCALE, float(z[2]), float(z[3]) * self.p_scale


@dataclass(frozen=True)
class CurvePoint:
    """One point of a curve: the orbit there (at w, with the model's parameter set to `value`),
    the unit tangent in scaled (x, v, w, p), the condition's residual (scaled) and what the
    orbit does: impacts and sticking reversals per orbit, its closest approach to the obstacle
    (m, signed as in :func:`excursions`), and on a grazing curve the grazing excursion's gap and
    phase (a fraction of the orbit's period)."""

    orbit: PeriodicOrbit
    value: float
    tangent: np.ndarray
    condition: float
    events: dict


@dataclass
class Curve:
    """A traced curve: its points in order, why each end stopped, the located codimension-two points."""

    problem: CurveProblem
    points: list
    stops: dict
    codim_two: list


def excursions(y, omega: float, n_periods: int, params: ModelParams) -> dict:
    """Every maximum of x over one orbit from y: its phase (fraction of the orbit's period) and
    signed gap (m; xI - x at a near miss, minus the penetration of a contact); the impacts, and the
    reversals where the cart sticks or nearly does (the core's implicit phases: the map is not
    smooth where one appears)."""
    period = n_periods * 2 * math.pi / omega
    run = simulate(
        omega, 0.0, period, **start_of(y), params=params, rtol=RTOL, atol=ATOL,
        record=("impacts", "near_misses", "penetrations"),
    )  # fmt: skip
    near, pen = run.events["near_misses"], run.events["penetrations"]
    t = np.concatenate([near["t"], pen["t"]]) / period
    gap = np.concatenate([near["gap"], -pen["h"]])
    sticks = int(run.attrs["n_stick"] + run.attrs["n_slow_reversal"])
    return {"phase": t, "gap": gap, "impacts": int(run.events["impacts"]["t"].size), "sticks": sticks}


def _graze_gap(ex: dict, phase: float) -> tuple[float, float]:
    """(signed gap, phase) of the maximum nearest to `phase` (circular: it may cross phase 0)."""
    if ex["phase"].size == 0:
        raise ShootingError("the orbit has no maximum of x left to graze")
    d = np.abs(ex["phase"] - phase)
    k = int(np.argmin(np.minimum(d, 1 - d)))
    return float(ex["gap"][k]), float(ex["phase"][k])


def _summary(ex: dict, phase: float | None) -> dict:
    """What a curve point keeps of its orbit's excursions."""
    k = int(np.argmin(np.abs(ex["gap"]))) if ex["gap"].size else None
    out = {
        "impacts": ex["impacts"],
        "sticks": ex["sticks"],
        "closest": float(ex["gap"][k]) if k is not None else math.inf,
    }
    if phase is not None:
        out["graze_gap"], out["graze_phase"] = _graze_gap(ex, phase)
    return out


def _condition(problem: CurveProblem, y, w, p, M, phase) -> float:
    """c at (y, w, p): the test function of M, or the grazing excursion's signed gap / 1 mm."""
    if problem.kind == "grazing":
        return _graze_gap(excursions(y, w, problem.n_periods, problem.model(p)), phase)[0] / SCALE[0]
    return TEST_FUNCTIONS[problem.kind](M)


def _steps(problem: CurveProblem, y) -> tuple[float, float]:
    """Difference steps (scaled) of the monodromy and of the gradient of c at state y: the usual
    ones, but within a twentieth of |v| of the state. Where the orbit's phase-0 state nears a
    reversal (v -> 0), a stencil reaching v = 0 would start inside the friction band (slope
    T/eps), where the map's derivative changes by O(1) within eps = 1e-6 m/s."""
    room = abs(float(y[1])) / SCALE[1] / 20
    return min(problem.step, room), min(C_STEP, room)


def _condition_at(problem: CurveProblem, z, phase, step) -> float:
    """c at scaled z, M computed there (the gradient of c needs it away from the orbit)."""
    y, w, p = problem.unscaled(z)
    M = None
    if problem.kind != "grazing":
        M = shooting_monodromy(y, w, problem.n_periods, problem.model(p), step=step)[1]
    return _condition(problem, y, w, p, M, phase)


def _system(problem: CurveProblem, z, phase):
    """Residual G(z) (3,) of the scaled extended system, its Jacobian (3 x 4), and M."""
    y, w, p = problem.unscaled(z)
    n, model = problem.n_periods, problem.model(p)
    step, c_step = _steps(problem, y)
    image, M = shooting_monodromy(y, w, n, model, step=step)
    J = np.empty((3, 4))
    J[:2, :2] = (M - np.eye(2)) * SCALE[None, :] / SCALE[:, None]
    J[:2, 2] = central_difference(lambda s: stroboscopic_map(y, w + s, n, model), W_STEP) / SCALE
    dp = problem.p_scale * P_STEP
    J[:2, 3] = (
        central_difference(lambda s: stroboscopic_map(y, w, n, problem.model(p + s)), dp) / SCALE * problem.p_scale
    )
    for k in range(4):
        unit = np.eye(4)[k]
        J[2, k] = central_difference(lambda s, unit=unit: _condition_at(problem, z + s * unit, phase, step), c_step)
    G = np.concatenate([(image - y) / SCALE, [_condition(problem, y, w, p, M, phase)]])
    return G, J, M


def _point(problem: CurveProblem, z, G, J, M, previous_tangent, newton_steps, phase) -> CurvePoint:
    y, w, p = problem.unscaled(z)
    orbit = PeriodicOrbit(
        w, problem.n_periods, float(y[0]), float(y[1]), M, _multipliers(M), float(np.max(np.abs(G[:2]))), newton_steps
    )
    ex = excursions(y, w, problem.n_periods, problem.model(p))
    return CurvePoint(orbit, p, _tangent(J, previous_tangent), float(G[2]), _summary(ex, phase))


def _scaled(problem: CurveProblem, point: CurvePoint) -> np.ndarray:
    """The point's scaled z = (x, v, w, p)."""
    return np.array(
        [point.orbit.x0 / SCALE[0], point.orbit.v0 / SCALE[1], point.orbit.omega, point.value / problem.p_scale]
    )


def _newton(problem, z, constraint, phase, previous_tangent, *, tol, max_newton) -> CurvePoint | None:
    """Newton on G(z) = 0 and one linear constraint (row a, value b: a . z = b); None if it
    does not converge (or an orbit on the way cannot be integrated)."""
    a, b = constraint
    try:
        for k in range(1, max_newton + 1):
            G, J, M = _system(problem, z, phase)
            dz = np.linalg.solve(np.vstack([J, a]), -np.concatenate([G, [float(a @ z) - b]]))
            z = z + dz
            if np.max(np.abs(dz)) < tol:
                G, J, M = _system(problem, z, phase)
                return _point(problem, z, G, J, M, previous_tangent, k, phase)
    except (ShootingError, np.linalg.LinAlgError, ValueError, RuntimeError):
        return None
    return None


def _phase(point: CurvePoint):
    return point.events.get("graze_phase")


def start_point(problem: CurveProblem, omega: float, x0: float, v0: float, *, tol: float = NEWTON_TOL) -> CurvePoint:
    """The curve's point at the model's own value of the parameter, from a located bifurcation
    of the one-parameter table (w, and the orbit's x0, v0 there): Newton on the extended system
    with p held. Its tangent points towards increasing p."""
    require_free_section(x0, problem.params, "the two-parameter continuation")
    p0 = getattr(problem.params, problem.parameter)
    phase = None
    if problem.kind == "grazing":  # the grazing excursion: the near miss closest to the obstacle
        ex = excursions([x0, v0], omega, problem.n_periods, problem.params)
        near = ex["gap"] > 0
        if not near.any():
            raise ValueError(f"the orbit at w = {omega} has no near miss to graze")
        phase = float(ex["phase"][near][np.argmin(ex["gap"][near])])
    z = np.array([x0 / SCALE[0], v0 / SCALE[1], omega, p0 / problem.p_scale])
    point = _newton(problem, z, (np.eye(4)[3], z[3]), phase, np.eye(4)[3], tol=tol, max_newton=12)
    if point is None:
        raise ShootingError(f"{problem.kind}: no curve point at {problem.parameter} = {p0} near w = {omega}")
    return point


def point_at(problem: CurveProblem, near: CurvePoint, value: float, *, tol: float = NEWTON_TOL) -> CurvePoint:
    """The curve's point at parameter `value`, from a curve point `near` it (Newton with p held)."""
    z = _scaled(problem, near)
    z[3] = value / problem.p_scale
    point = _newton(problem, z, (np.eye(4)[3], z[3]), _phase(near), near.tangent, tol=tol, max_newton=12)
    if point is None:
        raise ShootingError(
            f"{problem.kind}: no curve point at {problem.parameter} = {value} near w = {near.orbit.omega}"
        )
    return point


def _step(problem, prev: CurvePoint, h: float, *, tol=NEWTON_TOL, max_newton=6) -> CurvePoint | None:
    """The point at arclength h along prev's tangent (corrector on the normal plane)."""
    t = prev.tangent
    z_pred = _scaled(problem, prev) + h * t
    nxt = _newton(problem, z_pred, (t, float(t @ z_pred)), _phase(prev), t, tol=tol, max_newton=max_newton)
    # a corrector that wandered off (onto another branch across a kink) or a tangent that turned by
    # more than MAX_TURN: the step was too long for the curve here
    if nxt is None or np.linalg.norm(_scaled(problem, nxt) - z_pred) > h or nxt.tangent @ t < math.cos(MAX_TURN):
        return None
    return nxt


def _inside(problem, point: CurvePoint, value_range, w_range) -> bool:
    return value_range[0] <= point.value <= value_range[1] and w_range[0] <= point.orbit.omega <= w_range[1]


def _stuck(problem, point: CurvePoint, ds_min) -> str:
    """Why the corrector failed, as far as the last point tells."""
    why = f"corrector failed at w = {point.orbit.omega:.6f}, {problem.parameter} = {point.value:.6g} (ds < {ds_min:g})"
    if abs(point.orbit.v0) < 1e-4:
        why += (f"; the orbit's phase-0 state is {abs(point.orbit.v0):.2g} m/s from a velocity reversal, where the "
                "difference stencils meet the friction band")  # fmt: skip
    return why


def _walk(problem, start: CurvePoint, *, ds, ds_min, value_range, w_range, max_points):
    """Points from `start` (excluded) along its tangent until the curve leaves the box, after
    `max_points`, or where the corrector fails at steps below ds_min; and why it stopped. The
    step halves on a failed corrector and grows by 1.5 (up to ds) after a quick one."""
    points, point, h = [], start, ds
    while len(points) < max_points:
        nxt = _step(problem, point, h)
        if nxt is None:
            h /= 2
            if h < ds_min:
                return points, _stuck(problem, point, ds_min)
            continue
        point = nxt
        points.append(point)
        if not _inside(problem, point, value_range, w_range):
            return points, f"left {problem.parameter} in {list(value_range)}, w in {list(w_range)}"
        h = min(ds, 1.5 * h) if nxt.orbit.newton_steps <= 3 else h
    return points, f"{max_points} points"


def trace_curve(problem: CurveProblem, start: CurvePoint, *, ds: float, ds_min: float, value_range, w_range,
                max_points: int, log=None) -> Curve:  # fmt: skip
    """The curve through `start` both ways (towards decreasing p first, then increasing), in
    order of increasing p at `start`, with the codimension-two points met on it."""
    if not ds > ds_min > 0:
        raise ValueError(f"need ds > ds_min > 0, got ds = {ds}, ds_min = {ds_min}")
    if not _inside(problem, start, value_range, w_range):
        raise ValueError(
            f"the start (w = {start.orbit.omega}, {problem.parameter} = {start.value}) lies outside the box"
        )
    box = dict(ds=ds, ds_min=ds_min, value_range=value_range, w_range=w_range, max_points=max_points)
    back = dataclasses.replace(start, tangent=-start.tangent)
    down, why_down = _walk(problem, back, **box)
    up, why_up = _walk(problem, start, **box)
    points = [dataclasses.replace(p, tangent=-p.tangent) for p in down[::-1]] + [start] + up
    if log:
        log(f"{problem.kind}: {len(points)} points; {why_down}; {why_up}")
    return Curve(problem, points, {"start": why_down, "end": why_up}, codim_two_points(problem, points))


def _along(problem, a: CurvePoint, b: CurvePoint, fn, *, tol=1e-7, max_steps=40):
    """Bisection on the arclength from a towards b for a sign change of fn(point): the last
    point on a's side, `tol` (scaled) from it. Where the corrector fails (the curve is not
    smooth past a sticking onset or a grazing of its orbit) counts as the far side; None if
    no point can be corrected."""
    lo, hi = 0.0, float(np.linalg.norm(_scaled(problem, b) - _scaled(problem, a)))
    f_lo, best = fn(a), None
    for _ in range(max_steps):
        if hi - lo < tol:
            break
        mid = 0.5 * (lo + hi)
        p = _step(problem, a, mid, max_newton=8)
        if p is not None and np.sign(fn(p)) == np.sign(f_lo):
            lo, best = mid, p
        else:
            hi = mid
    return best


def _wp_turn(a: CurvePoint):
    ref = a.tangent[2:] / np.linalg.norm(a.tangent[2:])
    return lambda p: float(p.tangent[2:] @ ref)


def _detectors(problem: CurveProblem):
    """(name, scalar along the curve whose sign change marks that codimension-two point)."""
    dets = []
    if problem.kind != "period_doubling":
        dets.append(("meets a period doubling", lambda p: TEST_FUNCTIONS["period_doubling"](p.orbit.monodromy)))
    if problem.kind != "fold":
        dets.append(("meets a fold (fold-flip)" if problem.kind == "period_doubling" else "meets a fold",
                     lambda p: TEST_FUNCTIONS["fold"](p.orbit.monodromy)))  # fmt: skip
    return dets


def codim_two_points(problem: CurveProblem, points: list) -> list[dict]:
    """Codimension-two points between neighbouring curve points, each located by bisection on
    the arclength (its w, p) or listed with its bracket: a sign change of the other test
    functions of M (the curve meets a period doubling or a fold of the same orbits), a change
    of the orbit's impacts (it meets a grazing) or sticking reversals (the onset of sticking, a
    non-smooth bifurcation of the dry friction), and on a fold curve a reversal of the (w, p)
    tangent (a cusp)."""
    found = []
    dets = _detectors(problem)
    for a, b in itertools.pairwise(points):
        hits = [(name, fn) for name, fn in dets if fn(a) * fn(b) < 0 and math.isfinite(fn(a) * fn(b))]
        for key, name in (("impacts", "meets a grazing"), ("sticks", "meets the onset of sticking")):
            if a.events[key] != b.events[key] and not (key == "impacts" and problem.kind == "grazing"):
                hits.append((name, lambda p, key=key, n=a.events[key]: 1.0 if p.events[key] == n else -1.0))
        if problem.kind == "fold" and _wp_turn(a)(b) < 0:
            hits.append(("cusp", _wp_turn(a)))
        for name, fn in hits:
            at = _along(problem, a, b, fn)
            row = {"what": name, "between": [[a.orbit.omega, a.value], [b.orbit.omega, b.value]]}
            if at is None:
                found.append({**row, "located": False, "omega": 0.5 * (a.orbit.omega + b.orbit.omega),
                              "value": 0.5 * (a.value + b.value)})  # fmt: skip
            else:
                found.append({**row, "located": True, "omega": at.orbit.omega, "value": at.value,
                              "multipliers": [complex(m) for m in at.orbit.multipliers]})  # fmt: skip
    return found


def curve_record(curve: Curve) -> dict:
    """A traced curve as plain data (the workflow's curve file): every point's w, parameter
    value, orbit start, multipliers, condition residual and events; the stops; the
    codimension-two points."""
    pb = curve.problem
    points = [
        {
            "omega": p.orbit.omega, "value": p.value, "x0": p.orbit.x0, "v0": p.orbit.v0,
            "mu_re": p.orbit.multipliers.real.tolist(), "mu_im": p.orbit.multipliers.imag.tolist(),
            "stable": p.orbit.stable, "condition": p.condition, "newton_steps": p.orbit.newton_steps, **p.events,
        }
        for p in curve.points
    ]  # fmt: skip
    codim = [{**c, "multipliers": [[m.real, m.imag] for m in c.get("multipliers", [])]} for c in curve.codim_two]
    return {"kind": pb.kind, "parameter": pb.parameter, "n_periods": pb.n_periods, "points": points,
            "stops": curve.stops, "codim_two": codim}  # fmt: skip
