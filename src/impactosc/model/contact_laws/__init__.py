"""The contact laws: model BC's and the named laws of impact mechanics, each one component.

Why one family: every law here is a member of model BC's contact force

    F = kI (h^n1 + b h^n2 sgn(v) |v|^n3),   0 where the bracket is negative   (h = x - xI > 0)

with its own exponents and damping factor b (set anew at each contact from the velocity v0 of
its onset for a restitution law), plus a second stop k2 (h - h1)^n1 behind a surface h = h1 inside
the contact for a law that has one. So the core evaluates one force, its partial derivatives and
the residuals of its switching surfaces for all of them (:mod:`.kernel`), and a law is one
component (:class:`~.component.ContactLaw`) that says how it fills the family and owns everything
else about itself: its parameters with their units and ranges, its surfaces, the state it keeps
per contact, its exponents, what identification fits for it and from which start, the fields
the explorer shows. Every consumer asks the component; none tests a law by its name.

Adding a law is a module of this package with its component, one entry in :data:`LAWS` below,
its tests and its docs (docs/development.md). This package is plain Python but for :mod:`.kernel`:
the workflow's config check reads it without numba.
"""

from __future__ import annotations

from impactosc.io.names import shown
from impactosc.model.contact_laws import bc, hertz, hertz_viscous, kelvin_voigt, restitution, two_stage
from impactosc.model.contact_laws.component import ContactLaw, LawParameter, RestitutionLaw, unit_for

__all__ = [
    "DEFAULT_LAW",
    "INDEX",
    "LAWS",
    "OWN_PARAMETERS",
    "ContactLaw",
    "LawParameter",
    "RestitutionLaw",
    "law_of",
    "law_at",
    "unit_for",
]

#: Every law by its name, in the order of the menus and tables (and of their own parameters in
#: OWN_PARAMETERS: e, cI, ...).
LAWS: dict[str, ContactLaw] = {
    law.name: law
    for law in (
        bc.LAW,
        hertz.LAW,
        *restitution.LAWS,
        kelvin_voigt.LAW,
        hertz_viscous.LAW,
        two_stage.LAW,
    )
}


#: The law of a model that names none (model BC's: a model file without a ``contact`` block).
DEFAULT_LAW = bc.LAW.name


def _own_parameters() -> dict[str, LawParameter]:
    """The laws' own parameters by name, each once: two laws that share a name (cI) share its
    unit and range, checked here."""
    out: dict[str, LawParameter] = {}
    for law in LAWS.values():
        for prm in law.parameters:
            first = out.setdefault(prm.name, prm)
            if (first.unit, first.low, first.high, first.default) != (prm.unit, prm.low, prm.high, prm.default):
                raise TypeError(f"the laws {law.name} and another define {prm.name} differently")
    return out


#: The laws' own parameters beside model BC's family, by name (a model holds each: a law reads its own).
OWN_PARAMETERS = _own_parameters()
#: Each law's index, the number the parameter array carries (p[P_LAW]) for Python code that holds
#: only an array (identification's windows); the core never reads it.
INDEX = {name: i for i, name in enumerate(LAWS)}


def law_of(name: str) -> ContactLaw:
    """The law named `name`; a ValueError naming the laws when there is none of that name."""
    try:
        return LAWS[name]
    except (KeyError, TypeError):
        raise ValueError(f"contact law {shown(name)} is not one of {', '.join(LAWS)}") from None


def law_at(p) -> ContactLaw:
    """The law of a parameter array p (ModelParams.as_array)."""
    from impactosc.model.slots import P_LAW

    return list(LAWS.values())[int(p[P_LAW])]
