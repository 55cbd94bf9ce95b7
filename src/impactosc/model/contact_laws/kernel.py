"""The contact laws' force compiled for the core: F_I(h, v) of model BC's family.

    F_I = kI (h^n1 + b h^n2 sgn(v) |v|^n3)   for h = x - xI > 0 and the bracket >= 0, else 0

Every law of :mod:`impactosc.model.contact_laws` is a member of this family; the functions read
its numbers from the parameter array ``p`` (indices in :mod:`impactosc.model.slots`).
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.model.contact_laws import FLORES, HUNT_CROSSLEY, LANKARANI_NIKRAVESH
from impactosc.model.slots import P_B, P_KI, P_N1, P_N2, P_N3, P_XI


@njit(cache=True)
def _pow(h, n):
    # h**1.5 is the common case; h*sqrt(h) is faster and exact to rounding.
    if n == 1.5:
        return h * math.sqrt(h)
    return h**n


# The right-hand-side pieces are inlined into the steppers (numba inline="always"): 6-16 % off
# the chaotic scene's wall time in two A/B rounds, events bit-identical; compile +5-10 s.
@njit(cache=True, inline="always")
def contact_force(p, x, v):
    """Hunt-Crossley force kI*max(bracket, 0) for penetration x - xI > 0, else 0."""
    if x - p[P_XI] <= 0.0:  # no contact: no power to take
        return 0.0
    return contact_force_vn(p, x, v, abs(v) ** p[P_N3])


@njit(cache=True, inline="always")
def contact_force_vn(p, x, v, vn):
    """contact_force with vn = |v|^n3 given (a piece in the variable |v|^n3 has it: one pow less)."""
    h = x - p[P_XI]
    if h <= 0.0:
        return 0.0
    damp = 0.0
    if v != 0.0:
        damp = p[P_B] * _pow(h, p[P_N2]) * vn
        if v < 0.0:
            damp = -damp
    bracket = _pow(h, p[P_N1]) + damp
    if bracket <= 0.0:
        return 0.0
    return p[P_KI] * bracket


@njit(cache=True)
def restitution_damping(code, e, v0):
    """chi of the restitution law `code` for a contact whose onset velocity is v0 > 0 (b of the
    family for this contact); 0 for a contact without approach speed (a touch at v0 = 0)."""
    if v0 <= 0.0:
        return 0.0
    if code == HUNT_CROSSLEY:
        return 3.0 * (1.0 - e) / (2.0 * v0)
    if code == LANKARANI_NIKRAVESH:
        return 3.0 * (1.0 - e * e) / (4.0 * v0)
    if code == FLORES:
        return 8.0 * (1.0 - e) / (5.0 * e * v0)
    return (1.0 - e * e) / (e * v0)  # GONTHIER
