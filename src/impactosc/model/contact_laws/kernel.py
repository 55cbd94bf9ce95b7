"""The contact laws' force compiled for the core: model BC's family, with what each law placed.

    F_I = kI max(0, h^n1 + b h^n2 sgn(v) |v|^n3) [+ k2 (h - h1)^n1 behind h = h1]   (h = x - xI > 0)

Every law of :mod:`impactosc.model.contact_laws` is a member of this family: it places its numbers
in the parameter array ``p`` (:meth:`~impactosc.model.contact_laws.component.ContactLaw.place`),
and the functions here read only numbers, never a law's name or code: the force and its partial
derivatives, the residual of each switching surface (:func:`surface_residual`: the obstacle,
the cut where the bracket reaches zero, a surface inside the contact) and the state a contact
keeps (:func:`contact_onset`: a damping set from the onset velocity).
"""

from __future__ import annotations

import math

from numba import njit

from impactosc.model.slots import P_B, P_CHI, P_CHI_PER, P_H1, P_K2, P_KI, P_N1, P_N2, P_N3, P_XI

# --- the switching surfaces of a contact law (the core locates the roots of their residuals)
SURFACE_OBSTACLE, SURFACE_CUT, SURFACE_STOP = 0, 1, 2


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
    """The contact force: kI max(bracket, 0) (and a second stop's) for penetration x - xI > 0, else 0."""
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
    br = _pow(h, p[P_N1]) + damp
    if br <= 0.0:
        return 0.0
    return p[P_KI] * br


@njit(cache=True)  # a call, not inlined: only a law with a second stop, behind it, pays for it
def stop_force(p, x, v):
    """The contact force behind a second stop: the family's and k2 (h - h1)^n1. (The vector field
    behind it is a field of its own, STOP, so model BC's contact force carries no test of it:
    a test of a stage in contact_force cost 6 % of the chaotic scene's time.)"""
    h = x - p[P_XI]
    return contact_force(p, x, v) + p[P_K2] * _pow(max(h - p[P_H1], 0.0), p[P_N1])


@njit(cache=True, inline="always")
def bracket(p, x, v):
    """The family's bracket h^n1 + b h^n2 sgn(v) |v|^n3 (F = kI max(0, bracket)), h = max(x - xI, 0)."""
    h = max(x - p[P_XI], 0.0)
    damp = 0.0
    if v != 0.0:
        damp = p[P_B] * _pow(h, p[P_N2]) * abs(v) ** p[P_N3]
        if v < 0.0:
            damp = -damp
    return _pow(h, p[P_N1]) + damp


@njit(cache=True)
def contact_slopes(p, x, v, chord):
    """(dF/dx, dF/dv) of the contact force at penetration x - xI > 0 (0, 0 elsewhere), for the
    implicit solver's Jacobian.

    With ``chord`` the slope of sgn(v)|v|^n3 is replaced by its chord through v = 0,
    |v|^(n3 - 1) (larger than the tangent n3 |v|^(n3 - 1)): Newton then contracts towards
    the root instead of overshooting across v = 0 (radau.radau_step falls back to it).
    """
    h = x - p[P_XI]
    dfdx = 0.0
    dfdv = 0.0
    if h > 0.0:
        av = max(abs(v), 1e-30)
        sg = 1.0 if v >= 0.0 else -1.0
        vn = av ** p[P_N3]
        br = _pow(h, p[P_N1]) + p[P_B] * _pow(h, p[P_N2]) * sg * vn
        if br > 0.0:
            dfdx = p[P_KI] * (p[P_N1] * h ** (p[P_N1] - 1.0) + p[P_B] * p[P_N2] * h ** (p[P_N2] - 1.0) * sg * vn)
            if chord:
                dfdv = p[P_KI] * p[P_B] * _pow(h, p[P_N2]) * max(av, 1e-30) ** (p[P_N3] - 1.0)
            else:
                # |v|^n3 has an infinite slope at v = 0; capping |v| keeps Newton finite.
                dfdv = p[P_KI] * p[P_B] * _pow(h, p[P_N2]) * p[P_N3] * vn / max(av, 1e-12)
    return dfdx, dfdv


@njit(cache=True)
def stop_slope(p, x):
    """dF/dx of a second stop's force k2 (h - h1)^n1 (0 in front of it)."""
    h = x - p[P_XI] - p[P_H1]
    return p[P_K2] * p[P_N1] * h ** (p[P_N1] - 1.0) if h > 0.0 else 0.0


@njit(cache=True)
def contact_damping_rate(p, x, v):
    """-dF/dv of the contact force where its damping ~ |v|^n3 (0 < n3 < 1) is stiff: the true
    slope, inf at v = 0 (0 where the law does not damp so)."""
    h = x - p[P_XI]
    if h > 0.0 and p[P_B] > 0.0 and 0.0 < p[P_N3] < 1.0:
        av = abs(v)
        if av == 0.0:
            return math.inf
        return p[P_KI] * p[P_B] * h ** p[P_N2] * p[P_N3] * av ** (p[P_N3] - 1.0)
    return 0.0


@njit(cache=True, inline="always")
def surface_residual(p, vcut, surface, x, v):
    """The residual g(x, v) of a switching surface, its root the surface: the obstacle x - xI;
    the cut, the law's bracket (v + v_cut where the bracket is h^n1 (1 + b sgn(v) |v|^n3), n2 = n1:
    the same sign, on a line the state is put onto); the second stop (x - xI) - h1."""
    if surface == SURFACE_OBSTACLE:
        return x - p[P_XI]
    if surface == SURFACE_CUT:
        if p[P_N2] == p[P_N1]:
            return v + vcut
        return bracket(p, x, v)
    return x - p[P_XI] - p[P_H1]


@njit(cache=True, inline="always")
def surface_reads(p, surface):
    """(reads x, reads v): which of the state's components the surface's residual depends on."""
    if surface == SURFACE_CUT:
        return p[P_N2] != p[P_N1], True
    return True, False


@njit(cache=True, inline="always")
def past_cut(p, vcut, x, v):
    """Is (x, v), in contact, past the cut where the law's bracket turns negative (F_I = 0)?"""
    return surface_residual(p, vcut, SURFACE_CUT, x, v) <= 0.0


@njit(cache=True, inline="always")
def onto_cut(p, vcut, v):
    """The velocity put onto a located cut: -v_cut where the cut is that line, else v as located."""
    return -vcut if p[P_N2] == p[P_N1] else v


@njit(cache=True, inline="always")
def has_stop(p):
    """Does the law have a surface inside the contact (a second stop at h = h1)?"""
    return p[P_H1] < math.inf


@njit(cache=True, inline="always")
def behind_stop(p, x):
    """Is x behind the law's second stop (h > h1)? The side is the contact's state, kept as its
    vector field (equations.STOP behind, CONTACT in front)."""
    return x - p[P_XI] > p[P_H1]


@njit(cache=True)
def contact_onset(p, v0, vcut):
    """A contact starts at velocity v0: the state it keeps. A damping set per contact (P_CHI > 0)
    takes b = chi = g(e) / v0, g = P_CHI / P_CHI_PER (held in p until the next contact; 0 without
    approach speed) and its cut v = -1/chi. Returns the cut velocity."""
    if p[P_CHI] > 0.0:
        b = p[P_CHI] / (p[P_CHI_PER] * v0) if v0 > 0.0 else 0.0
        p[P_B] = b
        return 1.0 / b if b > 0.0 else math.inf
    return vcut
