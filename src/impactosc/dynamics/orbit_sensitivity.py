"""How a periodic orbit, at fixed w, moves with the model's parameters: the band of a branch.

Why: a branch continued for an identified model is one curve; within the model's covariance it
spans a band, and a reader must see whether two branches (or a branch and a rig's points) differ
by more than it.  The orbit solves F(y, p) = P^N(y; p) - y = 0 at fixed w, so by implicit
differentiation

    dy*/dp_i = (I - M)^{-1} dP^N/dp_i,

M the monodromy the shooting already has and dP^N/dp_i a central difference of the map at the
fixed point: no orbit is re-solved.  What the figures draw of the orbit (its Poincare points
x_k, its inter-impact intervals S_j) moves by the total derivative along (dy*/dp_i, e_i), a
central difference of one simulated orbit period.  The delta method turns these into standard
errors, se(q) = sqrt(diag(J C J^T)).

The band is undefined where the drawn quantities are not differentiable: at a grazing (the
number of impacts changes within the difference steps: nan there) and at a fold (I - M is
singular: the band widens without bound as the fold is approached, as it should).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactosc.dynamics.branch_segments import drawn_values
from impactosc.dynamics.point_sensitivity import FIELDS, parameter_step
from impactosc.dynamics.shooting import PeriodicOrbit, central_difference, require_free_section, stroboscopic_map
from impactosc.model.parameters import ModelParams

__all__ = ["orbit_sensitivities", "band_standard_errors"]

#: The drawn quantities, in the order of :func:`orbit_sensitivities`' rows.
QUANTITIES = ("poincare_x", "isis")


class _CountChanged(ValueError):
    """The orbit gained or lost an impact within a difference step."""


def orbit_sensitivities(orbit: PeriodicOrbit, params: ModelParams | None = None, fields=FIELDS) -> dict:
    """d/dp of the orbit's start state (``state``: 2 x n), of its Poincare points x_k
    (``poincare_x``: N x n, m per unit of each field) and of its inter-impact intervals
    (``isis``: impacts x n, s per unit; all nan when a step changes the number of impacts), for
    the n parameters ``fields`` at the orbit's w."""
    params = params or ModelParams()
    require_free_section(orbit.x0, params, "an orbit's sensitivity")
    y = np.array([orbit.x0, orbit.v0])
    w, n = orbit.omega, orbit.n_periods
    resolvent = np.eye(2) - orbit.monodromy
    base = drawn_values(orbit.x0, orbit.v0, w, n, params)
    state = np.empty((2, len(fields)))
    out = {q: np.empty((base[q].size, len(fields))) for q in QUANTITIES}
    for j, field in enumerate(fields):
        value, h = float(getattr(params, field)), parameter_step(params, field)

        def moved(s, field=field, value=value):
            return dataclasses.replace(params, **{field: value + s})

        dP = central_difference(lambda s, moved=moved: stroboscopic_map(y, w, n, moved(s)), h)
        dy = np.linalg.solve(resolvent, dP)
        state[:, j] = dy

        def along(s, dy=dy, moved=moved):
            d = drawn_values(y[0] + s * dy[0], y[1] + s * dy[1], w, n, moved(s))
            if d["isis"].size != base["isis"].size or d["poincare_x"].size != base["poincare_x"].size:
                raise _CountChanged
            return np.concatenate([d["poincare_x"], d["isis"]])

        try:
            total = central_difference(along, h)
        except _CountChanged:
            total = np.full(base["poincare_x"].size + base["isis"].size, np.nan)
        out["poincare_x"][:, j] = total[: base["poincare_x"].size]
        out["isis"][:, j] = total[base["poincare_x"].size :]
    return {"fields": tuple(fields), "state": state, **out}


def band_standard_errors(sensitivities: dict, names, covariance) -> dict:
    """Standard error of each drawn quantity (``poincare_x``, ``isis``, ``state``) from a
    covariance C of the parameters ``names`` (in C's order; a field the covariance does not name
    does not vary): sqrt(diag(J C J^T))."""
    C = np.asarray(covariance, dtype=float)
    if C.shape != (len(names), len(names)):
        raise ValueError(f"covariance of shape {C.shape} for {len(names)} names")
    fields = list(sensitivities["fields"])
    missing = [nm for nm in names if nm not in fields]
    if missing:
        raise ValueError(f"no sensitivities to {missing}")
    cols = [fields.index(nm) for nm in names]
    out = {}
    for q in ("state", *QUANTITIES):
        J = np.asarray(sensitivities[q])[:, cols]
        out[q] = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", J, C, J), 0.0))
    return out
