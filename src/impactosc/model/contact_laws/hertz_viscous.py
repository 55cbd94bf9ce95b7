"""Hertz's stiffness with a linear viscous damper: F = max(0, kI h^n1 + cI v), cI in N s/m.

In model BC's family: b = cI / kI, n2 = 0, n3 = 1 (n1 as the model gives it, Hertz's 1.5). The
damper pulls as the cart leaves: the force turns to 0 where kI h^n1 + cI v = 0, a curve in
(h, v) (its cut), and the cart leaves the obstacle's force before it leaves the obstacle.
"""

from __future__ import annotations

from impactosc.model.contact_laws.component import ContactLaw, Surface, linear_damping_start
from impactosc.model.contact_laws.kelvin_voigt import CI  # the same viscous damping, one definition
from impactosc.model.slots import P_B, P_KI, P_N2, P_N3


class HertzViscous(ContactLaw):
    name = "hertz-viscous"
    force = "max(0, kI h^n1 + cI v)"
    parameters = (CI,)
    surfaces = (Surface("cut", "kI h^n1 + cI v", "the force turns to 0: a curve in (h, v)"),)

    def _place(self, p, own):
        p[P_B], p[P_N2], p[P_N3] = own["cI"] / p[P_KI], 0.0, 1.0

    def start(self, contact, theta):
        # Hertz's stiffness as the contact fit has it; the damper that loses what its damping does
        _, c = linear_damping_start(contact, 1.5)
        return {"kI/m": contact["kI/m"], "cI/m": c}


LAW = HertzViscous()
