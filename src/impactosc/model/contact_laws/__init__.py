"""The contact laws: model BC's and the named laws of impact mechanics, each one definition.

Why one family: every law here is model BC's contact force

    F = kI (h^n1 + b h^n2 sgn(v) |v|^n3),   0 where the bracket is negative   (h = x - xI > 0)

with its own exponents and damping factor b, so the core evaluates one force, its partial
derivatives and its singular points (the onset h^n1, the cut where the bracket turns negative)
for all of them. A law is then two things: how it fills (b, n2, n3) and whether b is set anew
at each contact from the velocity v0 of its onset:

==========================  =================================================================
law                         contact force, and its place in the family
==========================  =================================================================
``bc`` (the paper's)        the family itself: b, n2, n3 as given
``hertz``                   kI h^n1: b = 0
``hunt-crossley``           kI h^n1 max(0, 1 + chi v), chi = 3 (1 - e) / (2 v0)
``lankarani-nikravesh``     the same with chi = 3 (1 - e^2) / (4 v0)
``flores``                  the same with chi = 8 (1 - e) / (5 e v0)
``gonthier``                the same with chi = (1 - e^2) / (e v0)
``kelvin-voigt``            max(0, kI h + cI v), n1 = 1: b = cI / kI, n2 = 0, n3 = 1
==========================  =================================================================

A restitution law (chi) is the family with n2 = n1, n3 = 1 and b = chi, set at each contact's
onset from its v0: e is the coefficient of restitution the law is built for (how closely a
free impact delivers it: the restitution table). Adding a law is one row of :data:`LAWS` (and
its chi in :func:`impactosc.model.equations.restitution_damping`, compiled into the core,
when it has one), its tests, and nothing else. This module is plain Python: the workflow's
config check reads it without numba.
"""

from __future__ import annotations

import dataclasses

from impactosc.io.names import shown

__all__ = [
    "LAWS",
    "LAW_CODES",
    "ContactLaw",
    "RESTITUTION_FIRST",
    "law_of",
]

# --- codes in the parameter array (p[P_LAW]); the restitution laws are the codes from RESTITUTION_FIRST up
BC, HERTZ, KELVIN_VOIGT, HUNT_CROSSLEY, LANKARANI_NIKRAVESH, FLORES, GONTHIER = range(7)
RESTITUTION_FIRST = HUNT_CROSSLEY


@dataclasses.dataclass(frozen=True)
class ContactLaw:
    """One law: its code in the core, what it is, and which of e (restitution) and cI
    (Kelvin-Voigt damping, N s/m) it takes."""

    name: str
    code: int
    force: str
    uses_e: bool = False
    uses_cI: bool = False

    @property
    def family(self) -> tuple[str, ...]:
        """The contact parameters of model BC's family this law reads (b, n2, n3 only model BC;
        the others take them from e or cI)."""
        return ("kI", "b", "n1", "n2", "n3") if self.code == BC else ("kI", "n1")

    @property
    def own(self) -> tuple[str, ...]:
        """The law's own numbers beside the family's (e, cI)."""
        return ("e",) * self.uses_e + ("cI",) * self.uses_cI


LAWS = {
    law.name: law
    for law in (
        ContactLaw("bc", BC, "kI (h^n1 + b h^n2 sgn(v) |v|^n3), 0 where the bracket is negative"),
        ContactLaw("hertz", HERTZ, "kI h^n1"),
        ContactLaw("kelvin-voigt", KELVIN_VOIGT, "max(0, kI h + cI v), n1 = 1", uses_cI=True),
        ContactLaw("hunt-crossley", HUNT_CROSSLEY, "kI h^n1 max(0, 1 + chi v), chi = 3 (1 - e) / (2 v0)", True),
        ContactLaw(
            "lankarani-nikravesh", LANKARANI_NIKRAVESH, "kI h^n1 max(0, 1 + chi v), chi = 3 (1 - e^2) / (4 v0)", True
        ),
        ContactLaw("flores", FLORES, "kI h^n1 max(0, 1 + chi v), chi = 8 (1 - e) / (5 e v0)", True),
        ContactLaw("gonthier", GONTHIER, "kI h^n1 max(0, 1 + chi v), chi = (1 - e^2) / (e v0)", True),
    )
}
LAW_CODES = {law.code: law.name for law in LAWS.values()}


def law_of(name: str) -> ContactLaw:
    """The law named `name`; a ValueError naming the laws when there is none of that name."""
    try:
        return LAWS[name]
    except (KeyError, TypeError):
        raise ValueError(f"contact law {shown(name)} is not one of {', '.join(LAWS)}") from None
