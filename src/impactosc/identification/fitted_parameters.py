"""The parameters identification fits: the model per unit mass, with its contact law's constants.

Why per unit mass: a displacement record sees only x'' = F / m, so every force constant enters
as its ratio to m and m itself is not identifiable; it is given (model BC's mass unless the
user says otherwise) and the fitted ratios are multiplied by it to give a ModelParams.  eps (the
friction regularisation) and the contact exponents n1, n2 are fixed: eps is a numerical
device far below any measurable velocity, and the exponents are the contact law's choice.

The fitted vector theta is ordered as QUANTITIES, one vector for every contact law: model BC's
eight (NAMES), then the contact laws' own numbers (a restitution law's e, a viscous damping
cI/m, ...: :data:`impactosc.model.contact_laws.OWN_PARAMETERS`).  Which entries are
free is a boolean mask, so a nested law (b = 0), a model without dry friction (T = 0) or a law
without b and n3 (:func:`law_quantities`) is the same vector with entries fixed.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactosc.model.contact_laws import LAWS, OWN_PARAMETERS, law_at
from impactosc.model.parameters import (
    OWN_SLOTS,
    P_B,
    P_C,
    P_K,
    P_KI,
    P_M0E,
    P_N3,
    P_T,
    P_XI,
    ModelParams,
    place_law,
    unit_of,
)

__all__ = [
    "NAMES",
    "QUANTITIES",
    "FIELDS",
    "UNITS",
    "LOWER",
    "UPPER",
    "law_quantities",
    "quantity_unit",
    "theta_of",
    "params_of",
    "fill_array",
]

_OWN = tuple(OWN_PARAMETERS.values())
#: Fitted quantities, in the order of theta: model BC's eight, then the laws' own (e, cI/m, ...).
QUANTITIES = ("k/m", "c/m", "T/m", "m0e/m", "kI/m", "b", "n3", "xI", *(prm.quantity for prm in _OWN))
#: Model BC's quantities: the first eight of theta.
NAMES = QUANTITIES[:8]
#: The ModelParams field behind each quantity (per unit mass ones are multiplied by m).
ALL_FIELDS = ("k", "c", "T", "m0e", "kI", "b", "n3", "xI", *(prm.name for prm in _OWN))
FIELDS = ALL_FIELDS[:8]
PER_MASS = (True, True, True, True, True, False, False, False, *(prm.per_mass for prm in _OWN))
#: Units of the quantities, kI/m's for n1 = 1.5 (:func:`quantity_unit` for another n1).
UNITS = ("1/s^2", "1/s", "m/s^2", "m", "1/(m^0.5 s^2)", "(s/m)^n3", "1", "m")
#: Where the core's p array holds each field.
_INDEX = (P_K, P_C, P_T, P_M0E, P_KI, P_B, P_N3, P_XI, *(OWN_SLOTS[prm.name] for prm in _OWN))
#: Physical bounds of theta (the Levenberg-Marquardt steps are projected onto them), the laws'
#: own from their definitions (e above 0.02: below, Flores' and Gonthier's chi ask for a damping
#: 40 times the elastic force at v0).
LOWER = np.array([1.0, 0.0, 0.0, 1e-6, 1e3, 0.0, 0.02, -np.inf, *(prm.fit_low for prm in _OWN)])
UPPER = np.array([np.inf, np.inf, np.inf, np.inf, np.inf, 20.0, 2.0, np.inf, *(prm.fit_high for prm in _OWN)])
_COMMON = ("k/m", "c/m", "T/m", "m0e/m", "kI/m", "xI")


def law_quantities(law: str) -> tuple[str, ...]:
    """The quantities of theta the contact law `law` has (in theta's order): the six every law
    has, then the law's own (its component's: model BC's b and n3, a restitution law's e, ...)."""
    own = LAWS[law].quantities
    return tuple(nm for nm in QUANTITIES if nm in _COMMON or nm in own)


def quantity_unit(name: str, n1: float = 1.5) -> str:
    """The unit of quantity `name`: the field's unit, per kg for a ratio to m (a stiffness's,
    kI/m's, follows the elastic exponent n1: 1/s^2 for a linear law)."""
    i = QUANTITIES.index(name)
    if i < len(UNITS) and name != "kI/m":
        return UNITS[i]
    unit = unit_of(ALL_FIELDS[i], n1)
    if not PER_MASS[i]:
        return "1" if unit == "-" else unit
    if unit.startswith("N/m"):  # N/m^n / kg = 1/(m^(n-1) s^2)
        power = 1.0 if unit == "N/m" else float(unit[4:])
        return "1/s^2" if power == 1 else f"1/(m^{power - 1:g} s^2)"
    return {"N s/m": "1/s", "N": "m/s^2", "kg m": "m"}.get(unit, f"{unit}/kg")


def field_unit(name: str, n1: float = 1.5) -> str:
    """The unit of the ModelParams field behind quantity `name`."""
    return unit_of(ALL_FIELDS[QUANTITIES.index(name)], n1)


def _names(theta, law: str) -> tuple[str, ...]:
    """The quantities theta holds: every entry of QUANTITIES, or the law's own (by its length)."""
    own = law_quantities(law)
    if len(theta) not in (len(QUANTITIES), len(own)):
        raise ValueError(f"theta of {len(theta)} entries: the {law} law has {len(own)} ({', '.join(own)})")
    return QUANTITIES if len(theta) == len(QUANTITIES) else own


def theta_of(params: ModelParams, full: bool = False) -> np.ndarray:
    """theta of a ModelParams: its law's quantities (:func:`law_quantities`, what an
    identification reports), or with ``full`` every entry of QUANTITIES (the vector it fits)."""
    names = QUANTITIES if full else law_quantities(params.law)
    return np.array(
        [getattr(params, ALL_FIELDS[i]) / (params.m if PER_MASS[i] else 1.0) for i in map(QUANTITIES.index, names)],
        dtype=float,
    )


def params_of(theta, base: ModelParams) -> ModelParams:
    """ModelParams with the fitted fields from theta (either length of :func:`theta_of`), the
    rest (m, eps, n1, n2, law) from base."""
    values = {}
    for nm, v in zip(_names(theta, base.law), theta):
        i = QUANTITIES.index(nm)
        values[ALL_FIELDS[i]] = float(v) * (base.m if PER_MASS[i] else 1.0)
    return dataclasses.replace(base, **values)


def fill_array(p: np.ndarray, theta, m: float) -> None:
    """Write theta (either length of :func:`theta_of`) into the core's parameter array p, in the
    place of p's contact law (in place; no ModelParams, no warnings)."""
    for nm, v in zip(_names(theta, law_at(p).name), theta):
        i = QUANTITIES.index(nm)
        p[_INDEX[i]] = v * (m if PER_MASS[i] else 1.0)
    place_law(p)
