"""Model BC's parameters (paper eq. 1): their names, units and meanings (:data:`PARAMETERS`),
their values (the defaults of :class:`ModelParams`, written nowhere else), the ranges the
tests cover, and their indices in the parameter array the numba core reads.

The parameters travel into the numba core as one float64 array ``p`` (indices P_*, in the
order of :data:`PARAMETERS`, then the forcing frequency), so compiled functions never close
over Python objects and stay cacheable on disk.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass, fields

import numpy as np

from impactosc.io.names import shown
from impactosc.model.contact_laws import DEFAULT_LAW, INDEX, OWN_PARAMETERS, law_at, law_of, unit_for
from impactosc.model.slots import (  # noqa: F401  (the indices of p, re-exported where they were defined)
    P_B,
    P_C,
    P_CHI,
    P_CHI_PER,
    P_EPS,
    P_H1,
    P_K,
    P_K2,
    P_KI,
    P_LAW,
    P_M,
    P_M0E,
    P_N1,
    P_N2,
    P_N3,
    P_OMEGA,
    P_OWN,
    P_T,
    P_XI,
)

#: Every parameter of the model, in the order of the ModelParams fields and of the array p:
#: (name, SI unit as a model file writes it, "-" when dimensionless; meaning).
PARAMETERS = (
    ("m", "kg", "moving mass"),
    ("m0e", "kg m", "unbalance m0 e"),
    ("k", "N/m", "spring stiffness"),
    ("c", "N s/m", "viscous damping"),
    ("T", "N", "dry-friction level"),
    ("eps", "m/s", "friction regularisation velocity"),
    ("kI", "N/m^1.5", "contact stiffness"),
    ("b", "(s/m)^n3", "Hunt-Crossley damping factor"),
    ("n1", "-", "elastic exponent"),
    ("n2", "-", "damping penetration exponent"),
    ("n3", "-", "damping velocity exponent"),
    ("xI", "m", "obstacle position (contact when x >= xI)"),
)
#: The contact laws' own numbers beside PARAMETERS, (name, unit for n1 = 1.5, meaning), from the
#: laws (:data:`impactosc.model.contact_laws.OWN_PARAMETERS`): a model file gives them in its
#: ``contact`` block with the law's name; only the laws that name them read them.
LAW_PARAMETERS = tuple((prm.name, unit_for(prm.unit, 1.5), prm.meaning) for prm in OWN_PARAMETERS.values())
#: Unit of every parameter (from PARAMETERS and LAW_PARAMETERS), for n1 = 1.5 (:func:`unit_of`).
PARAM_UNITS = {name: unit for name, unit, _ in PARAMETERS + LAW_PARAMETERS}
#: Units that follow the elastic exponent n1, as a stiffness of h^n1 does.
_UNIT_TEMPLATES = {"kI": "N/m^n1", **{prm.name: prm.unit for prm in OWN_PARAMETERS.values() if "^n1" in prm.unit}}
#: Where each law's own number sits in the parameter array p.
OWN_SLOTS = {name: P_OWN + i for i, name in enumerate(OWN_PARAMETERS)}
N_PARAMS = P_OWN + len(OWN_PARAMETERS)


def unit_of(name: str, n1: float = 1.5) -> str:
    """The SI unit of parameter `name`; a stiffness's (kI, a second stop's k2) follows the elastic
    exponent n1 (N/m^1.5 for Hertz's 1.5, N/m for a linear law)."""
    if name in _UNIT_TEMPLATES:
        return unit_for(_UNIT_TEMPLATES[name], n1)
    return PARAM_UNITS[name]


# Parameter ranges whose events have been checked against an independent SciPy reference:
# the randomized differential tests draw from these (benchmarks/random_scenes.BOX, with T
# from 0 to the forcing amplitude m0e w^2 and w from 10 to 60 rad/s), and the hard cases
# extend eps down to 1e-9 m/s and kI up to 100 x model BC. The obstacle xI was drawn within
# 5 mm of rest (a far obstacle is plain free flight). Outside these ranges the core still
# cannot hang (its watchdog bounds the work) but no test has looked at its events.
TESTED_RANGES = {
    "m": (2.0, 20.0),
    "m0e": (0.005, 0.05),
    "k": (500.0, 5000.0),
    "c": (0.0, 20.0),
    "eps": (1e-9, 1e-5),
    "kI": (1e7, 2.4e10),
    "b": (0.0, 2.0),
    "n1": (1.5, 1.5),
    "n2": (1.5, 1.5),
    "n3": (0.05, 1.0),
}


#: Largest magnitude of a parameter (and smallest of a nonzero one) the model evaluates. Why
#: 1e100: the force and the step-size control form products and squares of a few parameters and
#: the state, which must stay inside double precision (1e-308 .. 1.8e308); measured, eps of 1e-180
#: or 1e160 already divides by zero in the core (eps^2 underflows or overflows).
MAGNITUDE_LIMIT = 1e100
#: Largest exponent of the contact law (n1, n2, n3). Why 10: a penetration or velocity up to 1e30
#: (far beyond any state the core meets before its watchdog stops it) raised to it stays at 1e300,
#: inside double precision; a rig's contact laws have exponents from 1 to 2.5.
MAX_EXPONENT = 10.0


def place_law(p: np.ndarray) -> None:
    """Fill the law's place in model BC's family (b, n2, n3, a damping per contact, a second stop)
    from its own numbers in p, in place: one definition for a ModelParams' array and for an
    identification's, which writes fitted values into an array directly."""
    law_at(p).place(p, {name: float(p[OWN_SLOTS[name]]) for name in law_at(p).own})


class ParameterError(ValueError):
    """A value outside what the model or the core can take; ``name`` is the parameter (or the
    argument) it was given as, so that the command line can name its option."""

    def __init__(self, name: str, message: str):
        super().__init__(message)
        self.name = name


class UntestedParameterWarning(UserWarning):
    """A model parameter lies outside the ranges the randomized tests cover."""


class ModelParams:
    """Physical parameters of the model (SI units; units and meanings in :data:`PARAMETERS`),
    its contact law, and each law's own numbers (LAW_PARAMETERS: a law reads its own).

    The defaults are model BC, the paper's values: the one place they are written. The laws'
    own numbers are fields too, added after ``law`` from the laws' definitions (below the class),
    so that a law's new parameter needs no edit here."""

    m: float = 8.735
    m0e: float = 0.01805
    k: float = 1418.9
    c: float = 6.6511
    T: float = 0.63133
    eps: float = 1e-6
    kI: float = 2.3983e8
    b: float = 0.8485
    n1: float = 1.5
    n2: float = 1.5
    n3: float = 0.18667
    xI: float = -2.086e-3
    #: the contact law (impactosc.model.contact_laws.LAWS); b, n2 and n3 are model BC's own
    law: str = DEFAULT_LAW

    def __post_init__(self):
        law = law_of(self.law)
        for f in fields(self):
            if f.name == "law":
                continue
            value = getattr(self, f.name)
            if not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ParameterError(f.name, f"model parameter {f.name} must be a finite number, got {shown(value)}")
            if value != 0 and not 1 / MAGNITUDE_LIMIT <= abs(value) <= MAGNITUDE_LIMIT:
                raise ParameterError(
                    f.name,
                    f"model parameter {f.name} = {value:g} is beyond what the model evaluates "
                    f"(|{f.name}| from {1 / MAGNITUDE_LIMIT:g} to {MAGNITUDE_LIMIT:g}, or 0 where allowed)",
                )
        for name in ("m", "k", "eps", "kI", "n1", "n2"):
            if getattr(self, name) <= 0:
                raise ParameterError(name, f"model parameter {name} must be > 0, got {getattr(self, name)}")
        for prm in OWN_PARAMETERS.values():
            problem = prm.problem(getattr(self, prm.name))
            if problem:
                raise ParameterError(prm.name, problem)
        for name, problem in law.problems(self):
            raise ParameterError(name, problem)
        for name in ("m0e", "c", "T", "b", "n3"):
            if getattr(self, name) < 0:
                raise ParameterError(name, f"model parameter {name} must be >= 0, got {getattr(self, name)}")
        for name in ("n1", "n2", "n3"):
            if getattr(self, name) > MAX_EXPONENT:
                raise ParameterError(
                    name,
                    f"model parameter {name} = {getattr(self, name):g} exceeds {MAX_EXPONENT:g}, the largest "
                    "contact-law exponent the force evaluates without overflow",
                )
        for name, (lo, hi) in TESTED_RANGES.items():
            value = getattr(self, name)
            if not lo <= value <= hi:
                where = f"= {lo:g}" if lo == hi else f"in [{lo:g}, {hi:g}]"
                warnings.warn(
                    f"model parameter {name} = {value:g} is outside the tested range ({name} {where}); "
                    "the core runs, but its events there are not covered by the randomized tests",
                    UntestedParameterWarning,
                    stacklevel=3,
                )

    def as_array(self, omega: float) -> np.ndarray:
        """Pack the parameters and the forcing frequency for the numba core."""
        p = np.empty(N_PARAMS)
        p[P_M], p[P_M0E], p[P_K], p[P_C], p[P_T], p[P_EPS] = self.m, self.m0e, self.k, self.c, self.T, self.eps
        p[P_KI], p[P_B], p[P_N1], p[P_N2], p[P_N3], p[P_XI] = self.kI, self.b, self.n1, self.n2, self.n3, self.xI
        p[P_LAW] = INDEX[self.law]
        for name, slot in OWN_SLOTS.items():
            p[slot] = getattr(self, name)
        place_law(p)
        p[P_OMEGA] = omega
        return p

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_attrs(cls, attrs, prefix: str = "param_") -> ModelParams:
        """The parameters a file's attributes state as ``<prefix><name>`` (the law by its name,
        the rest numbers; a file written before laws had names is model BC's)."""
        values = {k[len(prefix) :]: v for k, v in attrs.items() if k.startswith(prefix)}
        return cls(
            **{
                k: (v.decode() if isinstance(v, bytes) else str(v)) if k == "law" else float(v)
                for k, v in values.items()
            }
        )

    @property
    def cut_velocity(self) -> float:
        """|v| beyond which the bracket turns negative (F_I = 0) where the law's cut is the line
        v = -b^(-1/n3) (its n2 = n1, b fixed); inf for a law without it, whose cut is another
        curve (:func:`impactosc.model.contact_laws.kernel.cut_residual`) or set per contact."""
        return cut_velocity(self.as_array(1.0))


for _prm in OWN_PARAMETERS.values():  # the laws' own numbers, after law, in the laws' order
    ModelParams.__annotations__[_prm.name] = "float"
    setattr(ModelParams, _prm.name, _prm.default)
ModelParams = dataclass(frozen=True)(ModelParams)


def cut_is_line(p: np.ndarray) -> bool:
    """Is the law's cut the line v = -b^(-1/n3) with b fixed (its bracket h^n1 (1 + b sgn(v) |v|^n3),
    n2 = n1, no damping set per contact)? Else the core finds it from the bracket itself."""
    return p[P_CHI] == 0 and p[P_N2] == p[P_N1]


def new_contact_state(p: np.ndarray) -> None:
    """Forget the contact state a law keeps in p (a damping set at the last onset), in place: a
    run that starts outside a contact, as each identification window does."""
    if p[P_CHI] > 0:
        p[P_B] = 0.0


def cut_velocity(p: np.ndarray) -> float:
    """The cut velocity a run with the parameter array p starts with (ModelParams.cut_velocity):
    b^(-1/n3) where the cut is that line (:func:`cut_is_line`), else inf."""
    b, n3 = float(p[P_B]), float(p[P_N3])
    if not cut_is_line(p) or b == 0 or n3 == 0:
        return math.inf
    try:
        return b ** (-1.0 / n3)
    except OverflowError:  # b < 1 and a tiny n3: the bracket never turns negative
        return math.inf


def model_bc_summary(names=("m", "k", "xI")) -> str:
    """Model BC's values of `names` with their units, e.g. "m=8.735 kg, k=1418.9 N/m" (for help texts)."""
    bc = ModelParams()
    return ", ".join(
        f"{name}={getattr(bc, name):g}" + ("" if PARAM_UNITS[name] == "-" else f" {PARAM_UNITS[name]}")
        for name in names
    )
