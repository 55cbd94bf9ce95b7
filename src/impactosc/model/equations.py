"""Model BC's right-hand side (paper eq. 1), compiled with numba for the core.

    m x'' + k x + c x' + T x'/sqrt(x'^2 + eps^2) + F_I(x, x') = m0e w^2 sin(w t)
    F_I = kI ((x - xI)^n1 + b (x - xI)^n2 sgn(x') |x'|^n3)   if x >= xI and the bracket >= 0

The functions read the parameters from the array ``p`` (indices P_* in
:mod:`impactosc.model.parameters`). The smooth vector field they evaluate is one of three
kinds (FREE, CONTACT, CUT): a trajectory switches between them at contact onset, exit and
the Hunt-Crossley cut.
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.model.contact_laws.kernel import _pow, contact_force, contact_force_vn
from impactosc.model.parameters import (
    P_B,
    P_C,
    P_EPS,
    P_K,
    P_KI,
    P_M,
    P_M0E,
    P_N1,
    P_N2,
    P_N3,
    P_OMEGA,
    P_T,
    P_XI,
)

# --- which smooth vector field is active on a piece -------------------------------------
FREE, CONTACT, CUT = 0, 1, 2  # free flight; contact; contact past the Hunt-Crossley cut (F_I = 0)
FIELD_NAMES = ("free flight", "contact", "contact past the Hunt-Crossley cut")


@njit(cache=True, inline="always")
def external_force(p, t, x, v):
    """Everything but the contact: forcing - spring - viscous - regularised dry friction."""
    w = p[P_OMEGA]
    friction = p[P_T] * v / math.sqrt(v * v + p[P_EPS] * p[P_EPS])
    return p[P_M0E] * w * w * math.sin(w * t) - p[P_K] * x - p[P_C] * v - friction


@njit(cache=True, inline="always")
def accel(p, field, t, x, v):
    """x'' on the smooth piece `field` (FREE and CUT have no contact force)."""
    f = external_force(p, t, x, v)
    if field == CONTACT:
        f -= contact_force(p, x, v)
    return f / p[P_M]


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
    w = p[P_OMEGA]
    f = p[P_M0E] * w * w * math.sin(w * t) - p[P_K] * x
    if field == CONTACT:
        f -= contact_force(p, x, 0.0)
    return f


@njit(cache=True)
def jacobian(p, field, t, x, v, chord):
    """Partial derivatives (da/dx, da/dv) for the implicit stick-phase solver.

    With ``chord`` the slope of sgn(v)|v|^n3 is replaced by its chord through v = 0,
    |v|^(n3 - 1) (larger than the tangent n3 |v|^(n3 - 1)): Newton then contracts towards
    the root instead of overshooting across v = 0 (radau.radau_step falls back to it).
    """
    eps = p[P_EPS]
    s = v * v + eps * eps
    dfdx = -p[P_K]
    dfdv = -p[P_C] - p[P_T] * eps * eps / (s * math.sqrt(s))
    if field == CONTACT:
        h = x - p[P_XI]
        if h > 0.0:
            av = max(abs(v), 1e-30)
            sg = 1.0 if v >= 0.0 else -1.0
            vn = av ** p[P_N3]
            bracket = _pow(h, p[P_N1]) + p[P_B] * _pow(h, p[P_N2]) * sg * vn
            if bracket > 0.0:
                dfdx -= p[P_KI] * (p[P_N1] * h ** (p[P_N1] - 1.0) + p[P_B] * p[P_N2] * h ** (p[P_N2] - 1.0) * sg * vn)
                if chord:
                    dfdv -= p[P_KI] * p[P_B] * _pow(h, p[P_N2]) * max(av, 1e-30) ** (p[P_N3] - 1.0)
                else:
                    # |v|^n3 has an infinite slope at v = 0; capping |v| keeps Newton finite.
                    dfdv -= p[P_KI] * p[P_B] * _pow(h, p[P_N2]) * p[P_N3] * vn / max(av, 1e-12)
    return dfdx / p[P_M], dfdv / p[P_M]


@njit(cache=True)
def damping_rate(p, field, x, v):
    """-da/dv: viscous + friction slope + Hunt-Crossley slope (inf at v = 0 in contact).

    Unlike jacobian (which caps |v| to keep Newton finite) this is the true slope:
    at a creep of 1e-18 m/s the cap would hide a factor 1e5 of stiffness.
    """
    eps = p[P_EPS]
    s2 = v * v + eps * eps
    rate = p[P_C] + p[P_T] * eps * eps / (s2 * math.sqrt(s2))
    h = x - p[P_XI]
    if field == CONTACT and h > 0.0 and p[P_B] > 0.0 and 0.0 < p[P_N3] < 1.0:
        av = abs(v)
        if av == 0.0:
            return math.inf
        rate += p[P_KI] * p[P_B] * h ** p[P_N2] * p[P_N3] * av ** (p[P_N3] - 1.0)
    return rate / p[P_M]
