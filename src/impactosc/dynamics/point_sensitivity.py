"""How far a located bifurcation point moves with the model's parameters, and its standard error.

Why: a rig's identified model comes with a covariance; a predicted period doubling at w* means
little without the range w* spans within that uncertainty.  Relocating the point for every
parameter (or for every Monte Carlo draw) costs a bisection of shots each; the point's own
defining equation gives its sensitivities at the price of a few shots.

A point located by :func:`impactosc.dynamics.bifurcation_points.locate` solves g(w, p) = 0, g the
test function of the orbit's monodromy matrix (det(M + I) for a period doubling, det(M - I) for
a fold, det M - 1 for a Neimark-Sacker pair).  By implicit differentiation

    dw*/dp_i = -(dg/dp_i) / (dg/dw),

both partial derivatives at the located point by fourth-order central differences of g on the
orbit shot at (w* +- h, p) and (w*, p +- h_i) (:func:`impactosc.dynamics.shooting.central_difference`):
the orbit is re-shot, the point is not relocated.  The delta method then gives the point's
standard error from a covariance C of the parameters, se(w*) = sqrt(s^T C s).

The check beside it (:func:`relocated_draws`): parameters drawn from C, the point relocated for
each draw; the spread of the relocated points is what the delta method's se must match where the
point depends linearly on the parameters within their uncertainty (not near a codimension-2
point, where the test function's w-derivative vanishes).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from impactosc.dynamics.bifurcation_points import TEST_FUNCTIONS
from impactosc.dynamics.shooting import PeriodicOrbit, ShootingError, central_difference, shoot
from impactosc.model.parameters import ModelParams

__all__ = ["FIELDS", "point_sensitivities", "delta_method_se", "relocated_draws"]

#: The model's parameters an identification fits (ModelParams fields), in its order.
FIELDS = ("k", "c", "T", "m0e", "kI", "b", "n3", "xI")
#: Difference step in w (rad/s) and, per parameter, relative to its value (absolute where it is
#: zero, e.g. b = 0 of a Hertz contact); xI in metres: 1e-8 m, far below a micrometre contact.
OMEGA_STEP = 1e-4
RELATIVE_STEP = 1e-6
ABSOLUTE_STEP = {"b": 1e-6, "n3": 1e-6, "T": 1e-6, "xI": 1e-8}


def _step(params: ModelParams, field: str) -> float:
    value = float(getattr(params, field))
    return ABSOLUTE_STEP[field] if field == "xI" or value == 0.0 else RELATIVE_STEP * abs(value)


def point_sensitivities(
    kind: str, omega: float, orbit: PeriodicOrbit, params: ModelParams | None = None, fields=FIELDS
) -> dict:
    """dw*/dp for each field of ``fields`` (rad/s per unit of the field) of the point of ``kind``
    located at ``omega`` on the branch of ``orbit`` (the orbit returned by ``locate``)."""
    if kind not in TEST_FUNCTIONS:
        raise ValueError(f"kind must be one of {sorted(TEST_FUNCTIONS)}, got {kind!r}")
    unknown = [f for f in fields if f not in {f.name for f in dataclasses.fields(ModelParams)}]
    if unknown:
        raise ValueError(f"unknown model parameter(s) {unknown}")
    params = params or ModelParams()
    g = TEST_FUNCTIONS[kind]
    start = [orbit.x0, orbit.v0]

    def test_function(w, p):
        return g(shoot(start, w, orbit.n_periods, p).monodromy)

    g_w = central_difference(lambda s: test_function(omega + s, params), OMEGA_STEP)
    if not (math.isfinite(g_w) and g_w != 0.0):
        raise ValueError(f"{kind} at w = {omega}: the test function does not cross zero there (dg/dw = {g_w})")
    out = {}
    for field in fields:
        base = float(getattr(params, field))
        g_p = central_difference(
            lambda s, field=field, base=base: test_function(omega, dataclasses.replace(params, **{field: base + s})),
            _step(params, field),
        )
        out[field] = -g_p / g_w
    return out


def delta_method_se(sensitivities: dict, names, covariance) -> float:
    """sqrt(s^T C s): the standard error of a point whose sensitivities to the parameters
    ``names`` (in C's order; a name without a sensitivity counts as 0) are ``sensitivities``."""
    C = np.asarray(covariance, dtype=float)
    if C.shape != (len(names), len(names)):
        raise ValueError(f"covariance of shape {C.shape} for {len(names)} names")
    s = np.array([sensitivities.get(n, 0.0) for n in names])
    return float(math.sqrt(max(s @ C @ s, 0.0)))


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
) -> np.ndarray:
    """The point of ``kind`` (located at ``omega`` on ``orbit``'s branch) relocated for each of
    ``draws`` parameter sets drawn from N(params, covariance) over the fields ``names``.

    Each draw's bracket is the delta method's prediction +- ``width`` standard errors (at least
    1e-6 rad/s), widened until the test function changes sign; bisection to 1e-4 of the standard
    error.  nan where no bracket was found within 10 widenings (the point has left the branch).
    """
    from impactosc.dynamics.bifurcation_points import locate

    C = np.asarray(covariance, dtype=float)
    s = sensitivities or point_sensitivities(kind, omega, orbit, params, fields=tuple(names))
    se = delta_method_se(s, names, C)
    slope = np.array([s.get(n, 0.0) for n in names])
    rng = np.random.default_rng(seed)
    base = np.array([float(getattr(params, n)) for n in names])
    g = TEST_FUNCTIONS[kind]
    start = [orbit.x0, orbit.v0]
    out = np.full(int(draws), math.nan)
    for i, values in enumerate(rng.multivariate_normal(base, C, size=int(draws))):
        p = dataclasses.replace(params, **dict(zip(names, map(float, values))))
        guess = omega + float(slope @ (values - base))
        half = max(width * se, 1e-6)
        for _ in range(10):
            try:
                lo = shoot(start, guess - half, orbit.n_periods, p)
                hi = shoot([lo.x0, lo.v0], guess + half, orbit.n_periods, p)
            except ShootingError:  # a draw whose orbit cannot be shot is left out (nan)
                break
            if g(lo.monodromy) * g(hi.monodromy) < 0:
                out[i] = locate(kind, lo, hi, p, tol=max(1e-4 * se, 1e-12))[0]
                break
            half *= 2
    return out
