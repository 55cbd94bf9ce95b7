"""How far a located bifurcation point moves with the model's parameters, and its standard error.

Why: a rig's identified model comes with a covariance; a predicted period doubling at w* means
little without the range w* spans within that uncertainty.  Relocating the point for every
parameter (or for every Monte Carlo draw) costs a bisection of shots each; the point's own
defining equation gives its sensitivities at the price of a few shots.

A point located by :func:`impactosc.dynamics.bifurcation_points.locate` solves g(w, p) = 0, g the
test function of the orbit's monodromy matrix (det(M + I) for a period doubling, det M - 1 for
a Neimark-Sacker pair).  By implicit differentiation

    dw*/dp_i = -(dg/dp_i) / (dg/dw),

both partial derivatives at the located point by fourth-order central differences of g on the
orbit shot at (w* +- h, p) and (w*, p +- h_i) (:func:`impactosc.dynamics.shooting.central_difference`):
the orbit is re-shot, the point is not relocated.  A grazing (:func:`impactosc.dynamics.grazing.locate_orbit_grazing`)
solves gap(w, p) = 0, gap the orbit's smallest near-miss gap, which exists on one side only: its
derivatives are taken on orbits with gaps of 2e-7 and 1e-7 m on that side, with steps that keep
the gap open, and extrapolated to gap 0 (Richardson: the error linear in the gap cancels).  A
fold, where the branch turns and no orbit exists on one side of w*, moves by the part of a
parameter's push on the map that its orbit cannot absorb: dw*/dp = -(psi . dP/dp) / (psi . dP/dw),
psi the left null vector of M - I (:func:`_fold_sensitivities`).  The delta method then gives the point's
standard error from a covariance C of the parameters, se(w*) = sqrt(s^T C s).

The check beside it (:func:`relocated_draws`): parameters drawn from C, the point relocated for
each draw; the spread of the relocated points is what the delta method's se must match where the
point depends linearly on the parameters within their uncertainty (not near a codimension-2
point, where the test function's w-derivative vanishes).
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np

from impactosc.dynamics.bifurcation_points import TEST_FUNCTIONS
from impactosc.dynamics.shooting import (
    DEFAULT_STEP,
    SCALE,
    PeriodicOrbit,
    ShootingError,
    central_difference,
    monodromy,
    require_free_section,
    shoot,
    stroboscopic_map,
)
from impactosc.model.parameters import ModelParams

__all__ = [
    "FIELDS",
    "parameter_step",
    "point_sensitivities",
    "delta_method_se",
    "normal_draws",
    "relocated_draws",
    "fold_near",
]

#: The model's parameters an identification fits (ModelParams fields), in its order.
FIELDS = ("k", "c", "T", "m0e", "kI", "b", "n3", "xI")
#: Difference step in w (rad/s) and, per parameter, relative to its value (absolute where it is
#: zero, e.g. b = 0 of a Hertz contact); xI in metres: 1e-7 m, a tenth of a micrometre contact.
#: The test functions carry ~1e-8 of difference noise (M from differences of the map): a weak
#: parameter such as c moves det(M + I) by ~1e-7 per 1e-6 of its value, so steps of 1e-6 left
#: 0.6-1 % of noise in dw*/dc, dT, dn3, dkI (measured against the doubling relocated); at 1e-4
#: they agree within 1e-4, and the fourth-order stencil's truncation stays far below that. For
#: dw*/dxI of the first doubling a step of 1e-8 m left 1.7e-4 of noise on one machine (1.4e-5 on
#: another: the last bits of the compiled core differ); 1e-7 m and 1e-6 m agree with the
#: relocated doubling within 2e-5.
OMEGA_STEP = 1e-4
RELATIVE_STEP = 1e-4
ABSOLUTE_STEP = {"b": 1e-6, "n3": 1e-6, "T": 1e-6, "xI": 1e-7, "cI": 1e-6}
#: A grazing's steps keep its near-miss gap of 1e-7 m open: 1e-8 of the value, 1e-2 of the
#: absolute steps, 1e-10 m of xI.
GRAZING_XI_STEP = 1e-10
GRAZING_RELATIVE_STEP = 1e-8


def parameter_step(params: ModelParams, field: str) -> float:
    """The difference step of ``field``: RELATIVE_STEP of its value, or its ABSOLUTE_STEP."""
    value = float(getattr(params, field))
    return ABSOLUTE_STEP[field] if field == "xI" or value == 0.0 else RELATIVE_STEP * abs(value)


def _grazing_step(params: ModelParams, field: str) -> float:
    value = float(getattr(params, field))
    if field == "xI":
        return GRAZING_XI_STEP
    return 1e-2 * ABSOLUTE_STEP[field] if value == 0.0 else GRAZING_RELATIVE_STEP * abs(value)


def point_sensitivities(
    kind: str, omega: float, orbit: PeriodicOrbit, params: ModelParams | None = None, fields=FIELDS
) -> dict:
    """dw*/dp for each field of ``fields`` (rad/s per unit of the field) of the point of ``kind``
    ("period_doubling", "fold", "neimark_sacker" or "grazing") located at ``omega``, ``orbit``
    the orbit its locator returned (for a grazing, the last one on the near-miss side)."""
    if kind not in (*TEST_FUNCTIONS, "grazing"):
        raise ValueError(f"kind must be one of {sorted([*TEST_FUNCTIONS, 'grazing'])}, got {kind!r}")
    unknown = [f for f in fields if f not in {f.name for f in dataclasses.fields(ModelParams)}]
    if unknown:
        raise ValueError(f"unknown model parameter(s) {unknown}")
    params = params or ModelParams()
    require_free_section(orbit.x0, params, "the sensitivity of a bifurcation point")
    if kind == "grazing":
        return _grazing_sensitivities(orbit, params, fields)
    if kind == "fold":
        return _fold_sensitivities(orbit, params, fields)
    g = TEST_FUNCTIONS[kind]
    start = [orbit.x0, orbit.v0]

    def test_function(w, p):
        return g(shoot(start, w, orbit.n_periods, p).monodromy)

    return _implicit(test_function, omega, OMEGA_STEP, params, fields, parameter_step, kind)


def _implicit(f, omega, w_step, params, fields, step_of, what) -> dict:
    """-(df/dp) / (df/dw) at (omega, params) by central differences (steps ``w_step`` and
    ``step_of(params, field)``), for each field."""
    f_w = central_difference(lambda s: f(omega + s, params), w_step)
    if not (math.isfinite(f_w) and f_w != 0.0):
        raise ValueError(f"{what} at w = {omega}: its defining function does not cross zero there (slope {f_w})")
    out = {}
    for field in fields:
        base = float(getattr(params, field))
        f_p = central_difference(
            lambda s, fd=field, b=base: f(omega, dataclasses.replace(params, **{fd: b + s})), step_of(params, field)
        )
        out[field] = -f_p / f_w
    return out


def _fold_sensitivities(orbit, params, fields) -> dict:
    """A fold's w* moves by dw*/dp = -(psi . dP/dp) / (psi . dP/dw), psi the left null vector of
    M - I: the part of a parameter's push that the orbit cannot absorb by moving along the
    branch (which turns there, so no orbit exists on one side of w* and the test function's
    w-derivative cannot be taken). The map's derivatives at the fold's own state; no Newton."""
    y, w, n = np.array([orbit.x0, orbit.v0]), orbit.omega, orbit.n_periods
    # M afresh at the state (a corrector's M may be of a neighbouring point): psi must be M's at the fold
    psi = np.linalg.svd(monodromy(y, w, n, params)[1] - np.eye(2))[0][:, -1]
    f_w = float(psi @ central_difference(lambda s: stroboscopic_map(y, w + s, n, params), OMEGA_STEP))
    if not (math.isfinite(f_w) and f_w != 0.0):
        raise ValueError(f"fold at w = {w}: the map does not move across the fold's direction with w")
    out = {}
    for field in fields:
        base = float(getattr(params, field))
        push = central_difference(
            lambda s, fd=field, b=base: stroboscopic_map(y, w, n, dataclasses.replace(params, **{fd: b + s})),
            parameter_step(params, field),
        )
        out[field] = -float(psi @ push) / f_w
    return out


#: Near-miss gaps (m) of the two orbits a grazing's derivatives are taken on.
GRAZING_GAPS = (2e-7, 1e-7)


def _grazing_sensitivities(orbit, params, fields) -> dict:
    """Sensitivities of a grazing from its near-miss side, extrapolated to gap 0 (module docstring)."""
    from impactosc.dynamics.grazing import orbit_events

    def gap(w, p, ref, size):
        step = min(DEFAULT_STEP, 1e-3 * size / SCALE[0])  # the monodromy's orbits miss the obstacle too
        return orbit_events(shoot([ref.x0, ref.v0], w, ref.n_periods, p, step=step), p)["min_gap"]

    g0 = orbit_events(orbit, params)["min_gap"]
    slope = (gap(orbit.omega + 1e-6, params, orbit, g0) - g0) / 1e-6
    found = []
    for size in GRAZING_GAPS:
        w = orbit.omega + (size - g0) / slope
        ref = shoot([orbit.x0, orbit.v0], w, orbit.n_periods, params, step=min(DEFAULT_STEP, 1e-3 * size / SCALE[0]))
        g_ref = gap(w, params, ref, size)
        found.append(
            _implicit(
                lambda om, p, ref=ref, g_ref=g_ref: gap(om, p, ref, g_ref),
                w,
                0.2 * g_ref / abs(slope),
                params,
                fields,
                _grazing_step,
                "grazing",
            )
        )
    far, near = found  # error linear in the gap: 2 near - far is the value at gap 0
    return {f: 2 * near[f] - far[f] for f in fields}


def delta_method_se(sensitivities: dict, names, covariance) -> float:
    """sqrt(s^T C s): the standard error of a point whose sensitivities to the parameters
    ``names`` (in C's order; a name without a sensitivity counts as 0) are ``sensitivities``."""
    C = np.asarray(covariance, dtype=float)
    if C.shape != (len(names), len(names)):
        raise ValueError(f"covariance of shape {C.shape} for {len(names)} names")
    s = np.array([sensitivities.get(n, 0.0) for n in names])
    return float(math.sqrt(max(s @ C @ s, 0.0)))


def normal_draws(rng, mean, covariance, size: int) -> np.ndarray:
    """``size`` draws from N(mean, covariance), by the Cholesky factor of the correlation.

    Why not numpy's multivariate_normal: an identified model's variances span 30 orders of
    magnitude (kI in N/m^1.5 against xI in m); numpy checks the matrix with an absolute
    tolerance of 1e-8 and warns that such a positive-definite matrix is not, and it factors the
    matrix itself by SVD, which is not scale-invariant. Scaled to a correlation first, the
    factor does not depend on the units."""
    C = np.asarray(covariance, dtype=float)
    sd = np.sqrt(np.diag(C))
    L = np.linalg.cholesky(C / np.outer(sd, sd))
    z = rng.standard_normal((int(size), sd.size))
    return np.asarray(mean, dtype=float) + (z @ L.T) * sd


def relocated_draws(
    kind: str,
    omega: float,
    orbit: PeriodicOrbit,
    params: ModelParams,
    names,
    covariance,
    draws: int,
    *,
    seed: int = 0,
    sensitivities: dict | None = None,
    width: float = 6.0,
    with_linear: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """The point of ``kind`` (located at ``omega`` on ``orbit``'s branch) relocated for each of
    ``draws`` parameter sets drawn from N(params, covariance) over the fields ``names``; with
    ``with_linear``, also the delta method's prediction for each draw (where they differ, the
    point is not linear in the parameters over their uncertainty).

    Each draw starts from the delta method's prediction and a half width of ``width`` standard
    errors (at least 1e-6 rad/s), doubled until the relocation finds the point: a bracket of the
    test function bisected to 1e-4 of the standard error, or for a grazing two near-miss orbits
    beyond the prediction (from half a standard error out, at least GRAZING_START).  nan where
    none was found within 10 doublings (the point has left the branch).
    """
    C = np.asarray(covariance, dtype=float)
    s = sensitivities or point_sensitivities(kind, omega, orbit, params, fields=tuple(names))
    se = delta_method_se(s, names, C)
    slope = np.array([s.get(n, 0.0) for n in names])
    rng = np.random.default_rng(seed)
    base = np.array([float(getattr(params, n)) for n in names])
    relocate = {"grazing": _grazing_relocation, "fold": _fold_relocation}.get(kind, _bracket_relocation)(
        kind, omega, orbit
    )
    out, linear = np.full(int(draws), math.nan), np.empty(int(draws))
    for i, values in enumerate(normal_draws(rng, base, C, int(draws))):
        p = dataclasses.replace(params, **dict(zip(names, map(float, values))))
        guess = linear[i] = omega + float(slope @ (values - base))
        # a grazing is approached from close near-miss orbits (the secant overshoots from far ones)
        half = max(0.5 * se, GRAZING_START) if kind == "grazing" else max(width * se, 1e-6)
        for _ in range(10):
            try:
                w = relocate(p, guess, half, se)
            except ShootingError:  # a draw whose orbit cannot be shot is left out (nan)
                break
            if w is not None:
                out[i] = w
                break
            half *= 2
    return (out, linear) if with_linear else out


def _bracket_relocation(kind, omega, orbit):
    """Relocation of a test function's root: bisection between guess -+ half, or None when the
    test function has one sign there."""
    from impactosc.dynamics.bifurcation_points import locate

    g = TEST_FUNCTIONS[kind]

    def relocate(p, guess, half, se):
        lo = shoot([orbit.x0, orbit.v0], guess - half, orbit.n_periods, p)
        hi = shoot([lo.x0, lo.v0], guess + half, orbit.n_periods, p)
        if g(lo.monodromy) * g(hi.monodromy) >= 0:
            return None
        return locate(kind, lo, hi, p, tol=max(1e-4 * se, 1e-12))[0]

    return relocate


#: A fold is relocated by following the branch from the fold's orbit both ways (its first
#: point corrected onto the drawn parameters' branch) for at most this many points.
FOLD_POINTS = 20


def fold_near(orbit: PeriodicOrbit, params: ModelParams, ds: float):
    """The fold of ``params``' branch nearest to ``orbit`` (a fold's orbit, e.g. of other
    parameters): the branch followed from it along its null direction, both ways, with
    arclength steps ``ds`` (its first point corrected onto the branch), until it turns in w; the
    turning point located on the arclength (its BranchPoint), or None where it does not turn
    within FOLD_POINTS points."""
    from impactosc.dynamics.arclength import BranchPoint, locate_fold
    from impactosc.dynamics.branch_segments import trace

    null = np.linalg.svd((orbit.monodromy - np.eye(2)) * SCALE[None, :])[2][-1]  # scaled (x, v)
    tangent = np.array([null[0], null[1], 0.0]) / np.linalg.norm(null)
    options = {"ds": ds, "w_range": (orbit.omega - 1.0, orbit.omega + 1.0), "max_points": FOLD_POINTS, "params": params}
    ahead, _ = trace(orbit, tangent=tangent, **options)
    behind, _ = trace(orbit, tangent=-tangent, **options)
    # one line through the start, which is left out (it is not on these parameters' branch), its
    # tangents pointing one way; the fold may lie between the first points of either side
    line = [BranchPoint(b.orbit, -b.tangent) for b in behind[:0:-1]] + ahead[1:]
    for a, b in itertools.pairwise(line):
        if np.sign(a.tangent[2]) != np.sign(b.tangent[2]):
            return locate_fold(a, b, params, tol=1e-12)
    return None


def _fold_relocation(kind, omega, orbit):
    """Relocation of a fold (:func:`fold_near`), with arclength steps of about the guessed
    shift (4 half)."""

    def relocate(p, guess, half, se):
        found = fold_near(orbit, p, float(np.clip(4 * half, 1e-5, 2e-3)))
        return None if found is None else found.orbit.omega

    return relocate


#: A grazing is relocated from near-miss orbits at least this far (rad/s) from its predicted w,
#: shot with difference steps of 1e-6 of the scale (1 nm): nearer, with gaps of a few nm, the
#: shooting's default stencil (0.1 um) reaches the obstacle and its Newton fails, which left
#: every draw of an identified model (se 7.7e-6 rad/s) unrelocated.
GRAZING_START = 1e-3
GRAZING_SHOT_STEP = 1e-6


def _grazing_relocation(kind, omega, orbit):
    """Relocation of a grazing from two orbits half and 2 half beyond the guess on the near-miss
    side (that of ``orbit``), or None when either has no near miss there."""
    from impactosc.dynamics.grazing import locate_orbit_grazing, orbit_events

    side = 1.0 if orbit.omega >= omega else -1.0

    def relocate(p, guess, half, se):
        step = {"step": GRAZING_SHOT_STEP}
        far = shoot([orbit.x0, orbit.v0], guess + 2 * side * half, orbit.n_periods, p, **step)
        near = shoot([far.x0, far.v0], guess + side * half, orbit.n_periods, p, **step)
        gaps = [orbit_events(o, p)["min_gap"] for o in (far, near)]
        if not all(math.isfinite(g) and g > 0 for g in gaps):
            return None
        try:
            return locate_orbit_grazing(far, near, p)[0]
        except ShootingError:  # the secant overshot the grazing: try from further out
            return None

    return relocate
