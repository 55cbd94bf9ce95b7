"""Kelvin-Voigt's linear spring and dashpot: max(0, kI h + cI v), n1 = 1 (the force jumps at onset).

In the family: b = cI / kI, n2 = 0, n3 = 1; its cut kI h + cI v = 0 is a line in (h, v).
"""

from __future__ import annotations

from impactosc.model.contact_laws.component import ContactLaw, LawParameter, Surface, linear_damping_start
from impactosc.model.slots import P_B, P_KI, P_N2, P_N3

CI = LawParameter("cI", "N s/m", "a viscous contact damping", 0.0, per_mass=True, unpinned=1.0, step=1e-6)


class KelvinVoigt(ContactLaw):
    name = "kelvin-voigt"
    force = "max(0, kI h + cI v), n1 = 1"
    parameters = (CI,)
    n1 = 1.0
    surfaces = (Surface("cut", "kI h + cI v", "the force turns to 0: the cart leaves the obstacle inside it"),)

    def _place(self, p, own):
        p[P_B], p[P_N2], p[P_N3] = own["cI"] / p[P_KI], 0.0, 1.0

    def start(self, contact, theta):
        k, c = linear_damping_start(contact, 1.0)
        return {"kI/m": k, "cI/m": c}


LAW = KelvinVoigt()
