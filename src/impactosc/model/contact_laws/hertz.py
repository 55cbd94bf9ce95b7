"""Hertz's elastic contact: no damping (the family with b = 0)."""

from __future__ import annotations

from impactosc.model.contact_laws.component import ContactLaw
from impactosc.model.slots import P_B


class Hertz(ContactLaw):
    name = "hertz"
    force = "kI h^n1"

    def _place(self, p, own):
        p[P_B] = 0.0


LAW = Hertz()
