"""Periodic orbits of model BC by shooting, and their Floquet multipliers.

Why: the brute-force diagrams see only stable orbits and locate a bifurcation to the sweep's
grid step. A period-N orbit is a fixed point of the N-th iterate of the stroboscopic map
P: (x, v) at phase w t = 2 pi i  ->  (x, v) one forcing period later. Newton on
F(y) = P^N(y) - y finds it, stable or not, to the solver's tolerance; the eigenvalues of the
Jacobian M = dP^N/dy (the monodromy matrix) are its Floquet multipliers, which say whether it
is stable (all |mu| < 1) and how it loses stability (mu = -1 period doubling, +1 fold, a
complex pair on the unit circle Neimark-Sacker).

M comes from fourth-order central differences of P^N, each evaluation a run of the core at a
tight tolerance (rtol 1e-12). The map is smooth where the orbit's impacts are transversal: the
contact force is continuous at the obstacle (it grows like (x - xI)^1.5), so no saltation
matrix is needed; the differences must stay inside one such smooth region: DEFAULT_STEP, 1e-4
of the state's scale (0.1 um, 10 um/s), is far below the micrometre penetrations and far above
the level where the solver's error shows. Measured on model BC's period-1 orbits at w = 25 and
30: M agrees to 2e-8 for steps 1e-3 and 1e-5 of the scale, drifts by 2e-7 at 1e-6 and 1e-6 at
1e-7 (the solver's error divided by the step); the period doubling at w = 37.28 located with
steps 1e-3 and 1e-4 agrees to 4e-10 rad/s. On the linear oscillator, where M is known in
closed form, the multipliers agree to 1e-7 (tests/test_shooting.py).

A restitution law's contact remembers its onset velocity v0 (its damping chi(e, v0) is set at the
onset), so a section point inside such a contact is (x, v, v0), and so is every state the map
carries (``as_state``). Newton then runs in three dimensions: v0 at the section is a function of
the trajectory one period back, and the fixed point must reproduce it too. The three-dimensional
M has rank 2 (the contact at the section ends within the period and its v0 is forgotten at the
exit: every later state depends on the start through the exit state alone), so its third
multiplier is 0 and the other two are those of the map restricted to the surface of states the
flow reaches, {(x, v, phi(x, v))}. The orbit reports that map's 2 x 2 Jacobian (``reduced``), whose
multipliers equal those of a section in free flight (the two maps are conjugate); measured on
Flores' law against an independent SciPy integration (tests/test_shooting_contact.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from impactosc.core.simulation import end_state, simulate, start_of
from impactosc.model.contact_laws import law_of
from impactosc.model.parameters import ModelParams

__all__ = [
    "PeriodicOrbit",
    "ShootingError",
    "as_state",
    "monodromy",
    "monodromy_columns",
    "reduced",
    "require_free_section",
    "shoot",
    "stroboscopic_map",
]

RTOL = 1e-12  # the core's tolerances for every map evaluation of the shooting
ATOL = 1e-14
SCALE = np.array([1e-3, 1e-1])  # m, m/s: the sizes of x and v on model BC's orbits
SCALE_V0 = 1e-1  # m/s: the size of a contact's onset velocity, the third component inside a contact
DEFAULT_STEP = 1e-4  # finite-difference step, relative to SCALE


class ShootingError(RuntimeError):
    """Newton did not converge; the message says where it stopped."""


@dataclass(frozen=True)
class PeriodicOrbit:
    """A fixed point y = (x, v) of P^N at phase 0 (t = 0 mod 2 pi / w), its monodromy matrix
    and Floquet multipliers (largest modulus first); inside a restitution law's contact also the
    contact's onset velocity (nan elsewhere)."""

    omega: float  # rad/s
    n_periods: int  # N: forcing periods per orbit
    x0: float  # m
    v0: float  # m/s
    monodromy: np.ndarray  # dP^N/dy at the fixed point, 2 x 2 (inside a contact: `reduced`)
    multipliers: np.ndarray  # eigenvalues of monodromy, complex, by decreasing modulus
    residual: float  # |P^N(y) - y| / SCALE at the returned point (max over components)
    newton_steps: int
    contact_v0: float = math.nan  # m/s: onset velocity of the contact the section point lies in

    @property
    def stable(self) -> bool:
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    @property
    def state(self) -> np.ndarray:
        """The section point as the maps take it: (x, v), or (x, v, v0) inside a contact."""
        if math.isnan(self.contact_v0):
            return np.array([self.x0, self.v0])
        return np.array([self.x0, self.v0, self.contact_v0])


def carries_v0(params: ModelParams | None) -> bool:
    """Whether the law's state inside a contact includes the contact's onset velocity."""
    return params is not None and law_of(params.law).keeps_contact_state


def as_state(y, params: ModelParams | None = None) -> np.ndarray:
    """y as the maps carry it: (x, v) for a law without memory, (x, v, v0) for a restitution law
    (v0 nan outside a contact); a finite third component is kept (a contact's v0)."""
    y = np.asarray(y, float)
    if len(y) > 2 and math.isfinite(y[2]):
        return y[:3].copy()
    if carries_v0(params):
        return np.array([y[0], y[1], math.nan])
    return y[:2].copy()


def require_free_section(x0: float, params: ModelParams | None, what: str) -> None:
    """Refuse, for `what` (a construction written in (x, v) alone), a section point inside a
    restitution law's contact, where the map's state includes the contact's v0."""
    if carries_v0(params) and x0 > params.xI:
        raise ValueError(
            f"{what} is written for a section point (x, v) in free flight; this one lies inside a {params.law} "
            "contact, whose onset velocity it does not carry"
        )


def _active(y) -> int:
    """Components of y the map depends on: 3 inside a restitution contact, else 2."""
    return 3 if len(y) > 2 and math.isfinite(y[2]) else 2


def _scale(k: int) -> np.ndarray:
    return np.append(SCALE, SCALE_V0)[:k]


def monodromy_columns(y, image) -> tuple[np.ndarray, np.ndarray]:
    """The scales of dP/dy's columns (the components y depends on: v0 too inside a contact) and
    of its rows (those of the image)."""
    return _scale(_active(y)), _scale(_active(image))


def stroboscopic_map(y, omega: float, n_periods: int = 1, params: ModelParams | None = None, *, rtol=RTOL, atol=ATOL):
    """P^N(y): the state after `n_periods` forcing periods from y at phase 0, in y's form:
    (x, v), or (x, v, v0) with the onset velocity of the contact it lies in (nan outside one)."""
    if int(n_periods) < 1:
        raise ValueError(f"n_periods must be >= 1, got {n_periods}")
    res = simulate(
        omega, 0.0, n_periods * 2 * math.pi / omega, **start_of(y), params=params, rtol=rtol, atol=atol, record=()
    )
    return end_state(res)[: len(y)]


def monodromy(y, omega: float, n_periods: int = 1, params: ModelParams | None = None, *, step=DEFAULT_STEP, **tol):
    """(P^N(y), M): the map and its Jacobian by fourth-order central differences (steps h and
    2h, h = `step` x SCALE per component: truncation error O(h^4), so the curvature of the
    map does not show and h can stay well above the solver's noise). M's columns are the
    components y depends on (v0 too inside a contact), its rows those of the image."""
    y = np.asarray(y, float)
    image = stroboscopic_map(y, omega, n_periods, params, **tol)
    scale, rows = monodromy_columns(y, image)
    M = np.empty((len(rows), len(scale)))
    for j in range(len(scale)):
        unit = np.zeros(len(y))
        unit[j] = 1.0
        M[:, j] = central_difference(
            lambda s, unit=unit: stroboscopic_map(y + s * unit, omega, n_periods, params, **tol)[: len(M)],
            step * scale[j],
        )
    return image, M


def reduced(M: np.ndarray) -> np.ndarray:
    """The 2 x 2 Jacobian of the map on the surface {(x, v, phi(x, v))} of states the flow reaches,
    from the 3 x 3 M of a section inside a contact (2 x 2 passes through). The image's v0 row is
    the surface's slope times the (x, v) rows (M has rank 2), and M acts on the surface's tangents
    (u, dphi u) as A + b dphi: the multipliers of M without its 0."""
    if M.shape == (2, 2):
        return M
    S = np.append(SCALE, SCALE_V0)
    Ms = M / S[:, None] * S[None, :]  # scaled, so that the least squares weighs x, v, v0 alike
    slope = np.linalg.lstsq(Ms[:2].T, Ms[2], rcond=None)[0]
    return (Ms[:2, :2] + np.outer(Ms[:2, 2], slope)) * SCALE[:, None] / SCALE[None, :]


def central_difference(f, h: float):
    """f'(0) to fourth order: (8 (f(h) - f(-h)) - (f(2h) - f(-2h))) / 12h."""
    return (8 * (f(h) - f(-h)) - (f(2 * h) - f(-2 * h))) / (12 * h)


def _multipliers(M: np.ndarray) -> np.ndarray:
    mu = np.linalg.eigvals(M).astype(complex)
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def shoot(
    guess,
    omega: float,
    n_periods: int = 1,
    params: ModelParams | None = None,
    *,
    tol: float = 1e-10,
    max_steps: int = 20,
    step: float = DEFAULT_STEP,
    rtol: float = RTOL,
    atol: float = ATOL,
) -> PeriodicOrbit:
    """Newton on P^N(y) - y from `guess` = (x, v) (or (x, v, v0) inside a restitution contact:
    an orbit's ``state``) until the step is below `tol` x SCALE.

    Each step solves (M - I) dy = -(P^N(y) - y) with M from :func:`monodromy`, in (x, v, v0)
    when y lies inside a restitution contact (module docstring); a step that would leave the
    region the guess came from (more than 10 x SCALE) is cut to that length.
    Raises ShootingError when `max_steps` are spent, or when M - I is singular (a multiplier
    at +1: a fold, where the orbit is not locally unique)."""
    given = np.asarray(guess, float)
    if given.shape not in ((2,), (3,)) or not np.all(np.isfinite(given[:2])):
        raise ValueError(f"guess must be a finite (x, v) or (x, v, v0), got {guess!r}")
    y = as_state(given, params)
    for k in range(1, int(max_steps) + 1):
        image, M = monodromy(y, omega, n_periods, params, step=step, rtol=rtol, atol=atol)
        n = min(M.shape)  # v0 takes part when both the point and its image lie inside a contact
        scale = _scale(n)
        try:
            dy = np.linalg.solve(M[:n, :n] - np.eye(n), -(image[:n] - y[:n]))
        except np.linalg.LinAlgError:
            raise ShootingError(f"w = {omega}: M - I is singular at {y} (a multiplier at +1)") from None
        longest = np.max(np.abs(dy) / scale)
        if longest > 10.0:
            dy *= 10.0 / longest
        y[:n] += dy
        if len(y) > 2 and n == 2:  # into or out of a contact: its v0 kept, or the image's (the nearest guess)
            inside = y[0] > (params or ModelParams()).xI
            y[2] = (y[2] if math.isfinite(y[2]) else image[2]) if inside else math.nan
        if np.max(np.abs(dy) / scale) < tol:
            image, M = monodromy(y, omega, n_periods, params, step=step, rtol=rtol, atol=atol)
            n = _active(y)
            residual = float(np.max(np.abs(image[:n] - y[:n]) / _scale(n)))
            M2 = reduced(M)
            return PeriodicOrbit(
                float(omega), int(n_periods), float(y[0]), float(y[1]), M2, _multipliers(M2), residual, k,
                float(y[2]) if n == 3 else math.nan,
            )  # fmt: skip
    raise ShootingError(
        f"w = {omega}, N = {n_periods}: no convergence in {max_steps} Newton steps "
        f"(last step {longest:.2e} of SCALE at x = {y[0]:.6e} m, v = {y[1]:.6e} m/s)"
    )
