"""Two stops one behind the other: F = kI h^n1, and past h = h1 also k2 (h - h1)^n1.

A compliant first stop (a rubber pad, a spring-loaded plate) backed by a stiffer second one at
the depth h1: the force is C^1 but no smoother at h = h1, a switching surface inside the contact
that the core locates and splits at, as it does at the onset. No damping: the contact is elastic.
"""

from __future__ import annotations

from impactosc.model.contact_laws.component import ContactLaw, LawParameter, Surface
from impactosc.model.slots import P_B, P_H1, P_K2

H1 = LawParameter(
    "h1", "m", "the depth of the second stop behind the first", 5.0e-5, low_open=True, unpinned=1.0, step=1e-7
)
K2 = LawParameter("k2", "N/m^n1", "the second stop's stiffness", 2.0e9, per_mass=True, unpinned=0.5)


class TwoStage(ContactLaw):
    name = "two-stage"
    force = "kI h^n1 + k2 (h - h1)^n1 for h > h1, else kI h^n1"
    parameters = (H1, K2)
    surfaces = (Surface("second stop", "h - h1", "h = h1 upwards engages k2, downwards releases it"),)

    def _place(self, p, own):
        p[P_B] = 0.0
        p[P_H1], p[P_K2] = own["h1"], own["k2"]

    def start(self, contact, theta):
        # the first stop's stiffness from the contact fit is that of both stops at once: the
        # second stop, its depth and stiffness, start at the stated model's values
        return {}


LAW = TwoStage()
