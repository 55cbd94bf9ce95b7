"""How a two-parameter curve moves with the model's other parameters: its confidence band.

Why: a curve of period doublings (or grazings, folds) in (w, xI) drawn for an identified model
is one curve among those its records allow; with a band of w +- 2 se at each point a reader sees
where it is pinned and where it is not.  A curve point solves the extended system of
:mod:`impactosc.dynamics.two_parameter`, G(u; q, p) = 0 with u = (x, v, w) (scaled), q the curve's
parameter and p the model's other parameters.  At fixed q, by implicit differentiation

    du/dp_i = -(dG/du)^{-1} dG/dp_i,

dG/du the curve's own Jacobian without its q column (what Newton already builds) and dG/dp_i a
central difference of the residual at the point: no curve is re-traced.  dw*/dp_i is du's third
component; the delta method over the covariance of p gives the band.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactosc.dynamics.point_sensitivity import parameter_step
from impactosc.dynamics.shooting import SCALE, central_difference, stroboscopic_map
from impactosc.dynamics.shooting import monodromy as shooting_monodromy
from impactosc.dynamics.two_parameter import CurveProblem, _condition, _steps, _system

__all__ = ["curve_point_sensitivities"]


def _residual(problem: CurveProblem, z, phase) -> np.ndarray:
    """G at scaled z (as :func:`impactosc.dynamics.two_parameter._system`, without its Jacobian)."""
    y, w, p = problem.unscaled(z)
    model = problem.model(p)
    if problem.kind == "grazing":
        image, M = stroboscopic_map(y, w, problem.n_periods, model), None
    else:
        image, M = shooting_monodromy(y, w, problem.n_periods, model, step=_steps(problem, y)[0])
    return np.concatenate([(image - y) / SCALE, [_condition(problem, y, w, p, M, phase)]])


def curve_point_sensitivities(problem: CurveProblem, point: dict, fields) -> dict:
    """dw*/dp (rad/s per unit of each field of ``fields``) at a curve ``point`` (an entry of
    :func:`impactosc.dynamics.two_parameter.curve_record`'s points), the curve's parameter held."""
    if problem.parameter in fields:
        raise ValueError(f"{problem.parameter} is the curve's own parameter (its axis), not one to vary")
    z = np.array([point["x0"] / SCALE[0], point["v0"] / SCALE[1], point["omega"], point["value"] / problem.p_scale])
    phase = point.get("graze_phase")
    _G, J, _M = _system(problem, z, phase)
    solve_u = np.linalg.inv(J[:, :3])
    out = {}
    for field in fields:
        base = float(getattr(problem.params, field))

        def moved(s, field=field, base=base):
            return dataclasses.replace(problem, params=dataclasses.replace(problem.params, **{field: base + s}))

        dG = central_difference(
            lambda s, moved=moved: _residual(moved(s), z, phase), parameter_step(problem.params, field)
        )
        out[field] = float(-(solve_u @ dG)[2])
    return out
