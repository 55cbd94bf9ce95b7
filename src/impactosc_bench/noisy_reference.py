"""The forcing of a noisy run rebuilt from its run file alone, for the SciPy reference.

Why apart from the library: the check that a noisy run is event-exact must not share the core's
reading of the noise. This module reads only what a run file states -- the samples of each noise
(group ``noise``), their grid (attributes ``noise_<name>_grid``), the rule (attribute ``noise_rule``)
and the model -- and builds the forcing as the rule says, with SciPy's splines evaluated by SciPy;
:func:`impactosc_bench.scipy_reference.solve_reference` then integrates it piece by piece.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import make_interp_spline

from impactosc.io.files import read_run
from impactosc.model.parameters import ModelParams
from impactosc_bench.scipy_reference import solve_reference

#: The spline ends the rule states (third and fourth derivatives zero), written out again here.
_ENDS = ([(4, 0.0), (5, 0.0), (6, 0.0)], [(4, 0.0), (5, 0.0), (6, 0.0)])


def forcing_from_run(path):
    """(forcing(t) in N, omega, params) of the run file at `path`: m0e (phi'^2 sin phi - phi'' cos phi)
    with phi = omega t + theta(t), plus the random force, each noise rebuilt from its samples."""
    events, attrs, _ = read_run(path)
    if "noise" not in events or "noise_rule" not in attrs:
        raise ValueError(f"{path} holds no realisation of noise in the dynamics (write it with --write-noise)")
    params = ModelParams.from_attrs(attrs)
    omega = float(attrs["omega"])
    curves = {}
    for name, dataset in (("motor", "motor_speed"), ("force", "cart_force")):
        if dataset in events["noise"]:
            y = events["noise"][dataset]
            t = np.arange(y.size) * float(attrs[f"noise_{name}_grid"])
            curves[name] = make_interp_spline(t, y, k=7, bc_type=_ENDS)
    motor = curves.get("motor")
    theta = motor.antiderivative() if motor is not None else None
    accel = motor.derivative() if motor is not None else None
    force = curves.get("force")
    m0e = params.m0e

    def forcing(t):
        phi, dphi, ddphi = omega * t, omega, 0.0
        if motor is not None:
            phi += float(theta(t))
            dphi += float(motor(t))
            ddphi = float(accel(t))
        f = m0e * (dphi * dphi * math.sin(phi) - ddphi * math.cos(phi))
        return f + float(force(t)) if force is not None else f

    return forcing, omega, params


def noisy_reference(path, t_end: float, **options) -> dict:
    """SciPy's impacts and penetrations of the noisy run at `path` from its start state to `t_end`
    (options: those of :func:`solve_reference`, e.g. method, rtol, atol)."""
    forcing, omega, params = forcing_from_run(path)
    _, attrs, _ = read_run(path)
    return solve_reference(
        omega, t_end, x0=float(attrs["x0"]), v0=float(attrs["v0"]), params=params, forcing=forcing, **options
    )
