"""Model BC's right-hand side (paper eq. 1), compiled with numba for the core.

    m x'' + k x + c x' + T x'/sqrt(x'^2 + eps^2) + F_I(x, x') = m0e w^2 sin(w t)   (:func:`forcing`)
    F_I = kI ((x - xI)^n1 + b (x - xI)^n2 sgn(x') |x'|^n3)   if x >= xI and the bracket >= 0

The functions read the parameters from the array ``p`` (indices P_* in
:mod:`impactosc.model.parameters`). The smooth vector field they evaluate is one of three
kinds (FREE, CONTACT, CUT, STOP): a trajectory switches between them at contact onset, exit,
the contact law's cut and a second stop inside the contact (a law's surfaces: contact_laws.kernel).
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.model.contact_laws.kernel import (
    contact_damping_rate,
    contact_force,
    contact_force_vn,
    contact_slopes,
    stop_force,
    stop_slope,
)
from impactosc.model.noise_kernel import harmonic_forcing, noisy_forcing
from impactosc.model.parameters import (
    P_C,
    P_EPS,
    P_K,
    P_M,
    P_M0E,
    P_OMEGA,
    P_T,
)

# --- which smooth vector field is active on a piece -------------------------------------
FREE, CONTACT, CUT, STOP = 0, 1, 2, 3  # free flight; contact; past the cut (F_I = 0); behind a second stop
FIELD_NAMES = ("free flight", "contact", "contact past the cut", "contact behind the second stop")


@njit(cache=True, inline="always")
def in_contact(field):
    """Is the field one of the contact (in front of or behind a second stop, not past the cut)?"""
    return (field == CONTACT) | (field == STOP)


@njit(cache=True, inline="always")
def forcing(p, t):
    """The unbalance's force m0e w^2 sin(w t); with noise in the dynamics (p longer than the model's
    parameters) the jittering motor's and the random force (noise_kernel), else today's arithmetic."""
    if harmonic_forcing(p):
        w = p[P_OMEGA]
        return p[P_M0E] * w * w * math.sin(w * t)
    return noisy_forcing(p, t)


@njit(cache=True, inline="always")
def external_force(p, t, x, v):
    """Everything but the contact: forcing - spring - viscous - regularised dry friction."""
    friction = p[P_T] * v / math.sqrt(v * v + p[P_EPS] * p[P_EPS])
    return forcing(p, t) - p[P_K] * x - p[P_C] * v - friction


@njit(cache=True, inline="always")
def accel(p, field, t, x, v):
    """x'' on the smooth piece `field` (FREE and CUT have no contact force)."""
    f = external_force(p, t, x, v)
    if field == CONTACT:
        f -= contact_force(p, x, v)
    return f / p[P_M]


@njit(cache=True)
def accel_any(p, field, t, x, v):
    """accel on any field, behind a second stop (STOP) too. Apart from accel on purpose: a test of
    STOP in accel, inlined into every stage of every stepper, cost model BC's chaotic scene 7-9 %
    (benchmark core_speed against the revision before); the steppers reach this through
    layout.STOP_TIME, the implicit solver always."""
    if field == STOP:
        return (external_force(p, t, x, v) - stop_force(p, x, v)) / p[P_M]
    return accel(p, field, t, x, v)


@njit(cache=True, inline="always")
def accel_vn(p, field, t, x, v, vn):
    """accel with vn = |v|^n3 given."""
    f = external_force(p, t, x, v)
    if field == CONTACT:
        f -= contact_force_vn(p, x, v, vn)
    return f / p[P_M]


@njit(cache=True)
def stick_force(p, field, t, x):
    """Net force other than dry friction at v = 0; |.| < T means the cart sticks."""
    f = forcing(p, t) - p[P_K] * x
    if field == CONTACT:
        f -= contact_force(p, x, 0.0)
    elif field == STOP:
        f -= stop_force(p, x, 0.0)
    return f


@njit(cache=True)
def jacobian(p, field, t, x, v, chord):
    """Partial derivatives (da/dx, da/dv) for the implicit stick-phase solver; with ``chord``
    the contact damping's slope is its chord through v = 0 (contact_laws.kernel.contact_slopes)."""
    eps = p[P_EPS]
    s = v * v + eps * eps
    dfdx = -p[P_K]
    dfdv = -p[P_C] - p[P_T] * eps * eps / (s * math.sqrt(s))
    if in_contact(field):
        dx, dv = contact_slopes(p, x, v, chord)
        dfdx -= dx
        dfdv -= dv
        if field == STOP:
            dfdx -= stop_slope(p, x)
    return dfdx / p[P_M], dfdv / p[P_M]


@njit(cache=True)
def damping_rate(p, field, x, v):
    """-da/dv: viscous + friction slope + the contact damping's (inf at v = 0 in contact).

    Unlike jacobian (which caps |v| to keep Newton finite) this is the true slope:
    at a creep of 1e-18 m/s the cap would hide a factor 1e5 of stiffness.
    """
    eps = p[P_EPS]
    s2 = v * v + eps * eps
    rate = p[P_C] + p[P_T] * eps * eps / (s2 * math.sqrt(s2))
    if in_contact(field):
        rate += contact_damping_rate(p, x, v)
    return rate / p[P_M]
