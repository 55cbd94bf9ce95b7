"""A noise's realisation for one seed: exact Ornstein-Uhlenbeck draws on a grid, the spline through
them, and the parameter array that carries it into the core.

Why a spline of exact draws: an OU process has no derivative, and the motor's force needs phi''. Drawn
exactly on a grid much finer than its correlation time (:data:`impactosc.model.noise.GRID_PER_TAU`) and
interpolated by a spline of degree 7, the process keeps its rms and correlation time while the forcing
becomes C^5 in t (the motor's, through phi'' = u'; the random force C^6): every piece stays a smooth ODE,
and the core's error control keeps its accuracy across the knots, where only the 8th derivative of x jumps,
the order of its DOP853 steps. How accuracy is kept, measured (chaotic scene, 3 s, errors of the first
impacts against the core at rtol 1e-14): with a quintic spline (x^(6) jumps) the steps over knots lost
10x accuracy at rtol 1e-12; with degree 7 they are as accurate as without noise (1e-14..1e-12). The knots
do not cap the steps; they cost steps (about 3.4x those of the noise-free run at tau = 0.02 s), not events.
The samples and :data:`RULE` are all another solver needs to integrate the very same forcing
(:func:`realisation_datasets` writes them to a run file, :func:`splines` rebuilds it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline, PPoly, make_interp_spline
from scipy.signal import lfilter

from impactosc.model.noise import PROCESSES, Noise
from impactosc.model.noise_kernel import (
    FORCE_DEGREE,
    MOTOR_DEGREE,
    NZ_FORCE_CELLS,
    NZ_FORCE_DT,
    NZ_HEADER,
    NZ_MOTOR_CELLS,
    NZ_MOTOR_DT,
    SPLINE_DEGREE,
)
from impactosc.model.parameters import ParameterError

#: End conditions of the spline: derivatives (k+1)/2 to k-1 zero at both ends (with odd degree k every
#: draw is then a knot, so the cells are the grid's).
_END = [(j, 0.0) for j in range((SPLINE_DEGREE + 1) // 2, SPLINE_DEGREE)]
SPLINE_ENDS = (_END, _END)
#: How the samples of a run file become its forcing (stored beside them as the attribute noise_rule).
RULE = (
    "samples y_k at t_k = k * grid (dataset noise/motor_speed or noise/cart_force; grid: attribute "
    "noise_motor_grid or noise_force_grid), drawn by the exact Ornstein-Uhlenbeck update "
    "y_{k+1} = a y_k + rms sqrt(1 - a^2) xi_k, a = exp(-grid / tau), y_0 from the stationary law; "
    f"y(t) = scipy.interpolate.make_interp_spline(t_k, y_k, k={SPLINE_DEGREE}, bc_type=({_END}, {_END})). "
    "motor: y is the speed deviation u, theta(t) = integral_0^t u, phi = omega t + theta, and the unbalance forces "
    "the cart with m0e (phi'^2 sin phi - phi'' cos phi); force: y is a force on the cart (N), added to the "
    "right-hand side"
)
#: Most cells a realisation may hold (per process). Why: 9 float64 coefficients per cell ride in the
#: parameter array; 2e7 cells are 1.4 GB, beyond which a run should take a coarser grid or a shorter span.
MAX_CELLS = 20_000_000


@dataclass(frozen=True)
class Realisation:
    """A noise drawn for its seed over [0, t_end]: samples y_k at t_k = k * spacing[name] per process."""

    noise: Noise
    samples: dict
    spacing: dict


def realise(noise: Noise, t_end: float) -> Realisation:
    """Draw each process of `noise` (rms > 0) from its own stream of the seed (PROCESSES' order, so
    that adding one noise leaves the other's draws as they were) on a grid covering [0, t_end]."""
    streams = np.random.SeedSequence(noise.seed).spawn(len(PROCESSES))
    samples, spacing = {}, {}
    for (name, process), stream in zip(((n, getattr(noise, n)) for n in PROCESSES), streams):
        if process is None or process.rms == 0:
            continue
        dt = process.spacing
        cells = math.ceil(t_end / dt) + 1  # one more than needed: the end of the run lies inside a cell
        if cells > MAX_CELLS:
            raise ParameterError(
                f"noise.{name}.grid",
                f"noise.{name}: {cells:.3g} grid cells over {t_end:g} s exceed {MAX_CELLS:g}; take a coarser grid "
                "(a longer tau) or a shorter run",
            )
        xi = np.random.Generator(np.random.PCG64(stream)).standard_normal(cells + 1)
        samples[name] = ou_samples(xi, process.rms, process.tau, dt)
        spacing[name] = dt
    return Realisation(noise, samples, spacing)


def ou_samples(xi: np.ndarray, rms: float, tau: float, dt: float) -> np.ndarray:
    """The exact OU update driven by standard normals xi, started from the stationary law."""
    a = math.exp(-dt / tau)
    drive = rms * math.sqrt(-math.expm1(-2.0 * dt / tau)) * xi  # sqrt(1 - a^2) without cancellation
    drive[0] = rms * xi[0]
    return lfilter([1.0], [1.0, -a], drive)


def splines(samples: np.ndarray, dt: float) -> BSpline:
    """The spline of :data:`RULE` through samples at t_k = k dt."""
    return make_interp_spline(np.arange(samples.size) * dt, samples, k=SPLINE_DEGREE, bc_type=SPLINE_ENDS)


def cell_coefficients(spline: BSpline, integrate: bool = False) -> np.ndarray:
    """(cells, degree + 1) coefficients of `spline` (with `integrate`: of its antiderivative from the
    first knot) on each grid cell, lowest power of s = t - t_i first."""
    pp = PPoly.from_spline(spline)  # (not of a BSpline's antiderivative: SciPy 1.17 crashes on degree 8)
    wide = np.diff(pp.x) > 0  # the end knots repeat: their cells have no width
    pp = PPoly(pp.c[:, wide], np.append(pp.x[:-1][wide], pp.x[-1]))
    if integrate:
        pp = pp.antiderivative()
    return np.ascontiguousarray(pp.c[::-1].T)


def pack(p: np.ndarray, realisation: Realisation) -> np.ndarray:
    """The parameter array p with the realisation behind it (layout: impactosc.model.noise_kernel)."""
    header = np.zeros(NZ_HEADER)
    blocks = []
    for name, slots, degree in (
        ("motor", (NZ_MOTOR_CELLS, NZ_MOTOR_DT), MOTOR_DEGREE),
        ("force", (NZ_FORCE_CELLS, NZ_FORCE_DT), FORCE_DEGREE),
    ):
        if name not in realisation.samples:
            header[slots[1]] = 1.0
            continue
        y = splines(realisation.samples[name], realisation.spacing[name])
        c = cell_coefficients(y, integrate=name == "motor")
        assert c.shape[1] == degree + 1
        header[slots[0]], header[slots[1]] = c.shape[0], realisation.spacing[name]
        blocks.append(c.ravel())
    return np.concatenate([p, header, *blocks])


def realisation_datasets(realisation: Realisation) -> tuple[dict, dict]:
    """(datasets, attributes) that write a realisation into a run file: group ``noise`` with one
    dataset of samples per process, and the rule that turns them into the forcing."""
    datasets = {PROCESSES[name][1]: y for name, y in realisation.samples.items()}
    return {"noise": datasets}, {"noise_rule": RULE}
