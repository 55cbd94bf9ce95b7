"""The restitution laws: kI h^n1 max(0, 1 + chi v), chi = g(e) / v0 set at each contact's onset.

They differ only in g(e), how the damping is written in the coefficient of restitution e it is
built for; how closely a free impact delivers e is the restitution table's question
(:mod:`impactosc.dynamics.restitution`).
"""

from __future__ import annotations

from impactosc.model.contact_laws.component import RestitutionLaw


class HuntCrossley(RestitutionLaw):
    name = "hunt-crossley"
    force = "kI h^n1 max(0, 1 + chi v), chi = 3 (1 - e) / (2 v0)"

    def fraction(self, e):
        return 3.0 * (1.0 - e), 2.0


class LankaraniNikravesh(RestitutionLaw):
    name = "lankarani-nikravesh"
    force = "kI h^n1 max(0, 1 + chi v), chi = 3 (1 - e^2) / (4 v0)"

    def fraction(self, e):
        return 3.0 * (1.0 - e * e), 4.0


class Flores(RestitutionLaw):
    name = "flores"
    force = "kI h^n1 max(0, 1 + chi v), chi = 8 (1 - e) / (5 e v0)"

    def fraction(self, e):
        return 8.0 * (1.0 - e), 5.0 * e


class Gonthier(RestitutionLaw):
    name = "gonthier"
    force = "kI h^n1 max(0, 1 + chi v), chi = (1 - e^2) / (e v0)"

    def fraction(self, e):
        return 1.0 - e * e, e


LAWS = (HuntCrossley(), LankaraniNikravesh(), Flores(), Gonthier())
