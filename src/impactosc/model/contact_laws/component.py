"""What a contact law is: one component that every consumer asks, never a name it tests.

A law owns its name and force; its own parameters (:class:`LawParameter`: unit, range, default,
how identification fits it); how it fills model BC's family, the one force the core evaluates
(:meth:`ContactLaw.place`, into the parameter array ``p``: b, n2, n3, a damping set per contact,
a second stop); its switching surfaces (:class:`Surface`); the state it keeps per contact; its
exponents at the singular points; the quantities identification fits for it and their start
values; the fields the explorer shows. This module is plain Python (the workflow's config
check and the plotting jobs read it without numba); the family's compiled force, residuals and
per-contact state are in :mod:`impactosc.model.contact_laws.kernel`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from impactosc.model.slots import P_B, P_CHI, P_CHI_PER, P_H1, P_K2, P_N1, P_N2, P_N3

__all__ = ["ContactLaw", "LawParameter", "RestitutionLaw", "Surface", "FAMILY", "DAMPING", "V_TYPICAL"]

#: The parameters of model BC's family every law reads (its own may replace b, n2, n3: DAMPING).
FAMILY = ("m", "m0e", "k", "c", "T", "eps", "kI", "b", "n1", "n2", "n3", "xI")
#: Model BC's damping: read by the laws that take the family as it is, set by the others.
DAMPING = ("b", "n2", "n3")
#: A typical impact speed of model BC's motions, m/s: where another law's start damping matches
#: the contact fit's b |v|^n3 (identification's start values).
V_TYPICAL = 0.2


@dataclasses.dataclass(frozen=True)
class LawParameter:
    """A number of a law's own, beside model BC's family.

    unit: SI, as a model file writes it ("^n1" follows the elastic exponent, as kI's unit);
    low, high and the open flags: its range (checked whenever a model is built); default: the
    value a model holds when its law does not read it (and a new model of the law starts from);
    quantity: its name in identification (per_mass: fitted as its ratio to m, ``name/m``), with
    the bounds of the fit, the standard error beyond which the records do not pin it (relative to
    the value for a per-mass quantity) and the absolute difference step of its sensitivities."""

    name: str
    unit: str
    meaning: str
    default: float
    low: float = 0.0
    high: float = math.inf
    low_open: bool = False
    high_open: bool = True
    per_mass: bool = False
    fit_low: float = 0.0
    fit_high: float = math.inf
    unpinned: float = 1.0
    step: float | None = None

    @property
    def quantity(self) -> str:
        return f"{self.name}/m" if self.per_mass else self.name

    @property
    def range_text(self) -> str:
        return f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"

    def problem(self, value: float) -> str | None:
        """Why `value` is outside the range, or None."""
        low_ok = value > self.low if self.low_open else value >= self.low
        high_ok = value < self.high if self.high_open else value <= self.high
        if low_ok and high_ok:
            return None
        if self.high == math.inf:
            rule = f"{'>' if self.low_open else '>='} {self.low:g}"
        else:
            rule = f"in {self.range_text}"
        return f"model parameter {self.name} must be {rule} ({self.meaning}), got {value}"


@dataclasses.dataclass(frozen=True)
class Surface:
    """A switching surface of the law: its residual g(h, v) (h = x - xI), where the motion
    crosses it and what changes there; the core locates its root on the dense output."""

    name: str
    residual: str
    crossing: str


OBSTACLE = Surface("onset / exit", "h", "h = 0 upwards starts the contact, downwards ends it")


def unit_for(unit: str, n1: float) -> str:
    """A unit with "^n1" written for the elastic exponent n1 (N/m^n1: N/m^1.5, or N/m when n1 = 1)."""
    if "^n1" not in unit:
        return unit
    return unit.replace("^n1", "" if n1 == 1 else f"^{n1:g}")


class ContactLaw:
    """A contact law of model BC's family. Subclasses set the class attributes and override
    :meth:`_place` (and :meth:`start`) where they differ from the family itself.

    name, force (how its force reads), parameters (its own, LawParameter each), reads_damping (it reads
    model BC's b, n2, n3 as given), n1 (an elastic exponent it fixes, else None), surfaces (its
    switching surfaces beyond onset and exit), contact_state (what it keeps per contact, '' none)."""

    name: str = ""
    force: str = ""
    parameters: tuple[LawParameter, ...] = ()
    reads_damping: bool = False
    n1: float | None = None
    surfaces: tuple[Surface, ...] = ()
    contact_state: str = ""

    # ------------------------------------------------------------------ parameters
    @property
    def own(self) -> tuple[str, ...]:
        """The names of the law's own numbers beside the family's (e, cI, ...)."""
        return tuple(prm.name for prm in self.parameters)

    @property
    def family(self) -> tuple[str, ...]:
        """The parameters of model BC's family this law reads (b, n2, n3 only when it reads the
        damping as given; the others set them from their own numbers)."""
        return tuple(name for name in FAMILY if self.reads_damping or name not in DAMPING)

    @property
    def fields(self) -> tuple[str, ...]:
        """Every parameter a model of this law is given by: the family's it reads, then its own
        (what a model file writes and the explorer shows)."""
        return self.family + self.own

    def problems(self, params) -> list[tuple[str, str]]:
        """(parameter, why) for each value of `params` the law refuses (beyond the family's
        checks, which :class:`impactosc.model.parameters.ModelParams` makes)."""
        if self.n1 is not None and params.n1 != self.n1:
            shape = "linear" if self.n1 == 1 else f"of the power {self.n1:g}"
            return [("n1", f"the {self.name} law is {shape} in the penetration: n1 = {self.n1:g}, got {params.n1}")]
        return []

    # ------------------------------------------------------------------ the core's numbers
    def place(self, p: np.ndarray, own: dict) -> None:
        """Fill the law's place in model BC's family in the parameter array p, in place, from
        p's family numbers and the law's own values `own` (name -> value): b, n2, n3, the damping
        set per contact (P_CHI), the second stop (P_H1, P_K2)."""
        p[P_CHI], p[P_CHI_PER], p[P_H1], p[P_K2] = 0.0, 1.0, math.inf, 0.0
        self._place(p, own)

    def _place(self, p: np.ndarray, own: dict) -> None:
        """The law's own part of :meth:`place` (model BC's family: nothing to set)."""

    @property
    def keeps_contact_state(self) -> bool:
        """Whether a contact of this law remembers something of its onset (a run that starts
        inside one needs it: simulate's contact_v0)."""
        return bool(self.contact_state)

    def exponents(self, params) -> tuple[float, float]:
        """The exponents at the contact's singular points: the onset's (F ~ h^n1) and the turn's
        (F ~ |v|^n3 at v = 0 when the law damps with n3 < 1; 1: smooth there)."""
        p = params.as_array(1.0)
        turn = p[P_N3] if p[P_B] > 0 and 0 < p[P_N3] < 1 else 1.0
        return float(p[P_N1]), float(turn)

    # ------------------------------------------------------------------ identification
    @property
    def quantities(self) -> tuple[str, ...]:
        """What identification fits for this law beside the six every law has (k/m, c/m, T/m,
        m0e/m, kI/m, xI): model BC's b and n3, or the law's own numbers."""
        return ("b", "n3") if self.reads_damping else tuple(prm.quantity for prm in self.parameters)

    def start(self, contact: dict, theta: dict) -> dict:
        """Start values of the law's quantities (name -> value, entries of `theta` it changes)
        from the contact fit `contact` (model BC's law: kI/m, b, n3 of the records); `theta` holds
        every quantity's current start (the stated model's, or the fit's). Default: the stated
        model's values, unchanged."""
        return {}


def penetration_at(k_over_m: float, v0: float, n1: float = 1.5) -> float:
    """The deepest penetration of a free undamped impact at v0 against kI/m h^n1 (energy:
    (kI/m) h^(n1+1) / (n1+1) = v0^2 / 2)."""
    return ((n1 + 1.0) * v0**2 / (2.0 * k_over_m)) ** (1.0 / (n1 + 1.0))


class RestitutionLaw(ContactLaw):
    """kI h^n1 max(0, 1 + chi v) with chi = g(e) / v0: a law built for a coefficient of
    restitution e, its damping set at each contact's onset from that contact's velocity v0.
    Subclasses give g(e) as the fraction it is published as (:meth:`fraction`, numerator and
    denominator: the core divides once, chi = numerator / (denominator v0)), decreasing to 0 at e = 1."""

    contact_state = "the onset velocity v0 (chi = g(e) / v0)"
    parameters = (
        LawParameter(
            "e",
            "-",
            "a coefficient of restitution",
            1.0,
            low=0.0,
            high=1.0,
            low_open=True,
            high_open=False,
            fit_low=0.02,  # below 0.02 Flores' and Gonthier's chi ask for 40 times the elastic force at v0
            fit_high=1.0,
            unpinned=0.5,
        ),
    )
    surfaces = (Surface("cut", "1 + chi v", "v = -1/chi: the force turns to 0 (past it the obstacle lets go)"),)

    def fraction(self, e: float) -> tuple[float, float]:  # pragma: no cover - every restitution law defines it
        raise NotImplementedError

    def g(self, e: float) -> float:
        """chi v0 of the law at e."""
        num, den = self.fraction(e)
        return num / den

    def _place(self, p, own):
        p[P_B], p[P_N2], p[P_N3] = 0.0, p[P_N1], 1.0
        p[P_CHI], p[P_CHI_PER] = self.fraction(float(own["e"]))

    def e_for(self, chi_v0: float) -> float:
        """The e whose g(e) equals chi_v0 (= chi v0), within identification's range of e: its
        lower end when g never gets that large, 1 when chi_v0 <= 0."""
        from scipy.optimize import brentq

        prm = self.parameters[0]
        if self.g(1.0) >= chi_v0:
            return 1.0
        if self.g(prm.fit_low) <= chi_v0:
            return float(prm.fit_low)
        return float(brentq(lambda e: self.g(e) - chi_v0, prm.fit_low, 1.0, xtol=1e-12))

    def start(self, contact, theta):
        # the damping force at a typical impact matches the contact fit's b |v|^n3
        chi = contact["b"] * V_TYPICAL ** (contact["n3"] - 1.0)
        return {"e": self.e_for(chi * V_TYPICAL)}


def linear_damping_start(contact: dict, n1: float) -> tuple[float, float]:
    """(kI/m, cI/m) of kI h^n1 + cI v that matches the contact fit (model BC's law, h^1.5) at a
    typical impact: the same deepest penetration, and the viscous damping whose linear oscillator
    loses what the fit's damping loses at V_TYPICAL (the restitution Hunt-Crossley's chi gives)."""
    k15 = contact["kI/m"]
    h = penetration_at(k15, V_TYPICAL)
    k = k15 * h ** (1.5 - n1) * (n1 + 1.0) / 2.5  # (kI/m) h^(n1+1) / (n1+1) alike
    chi = contact["b"] * V_TYPICAL ** (contact["n3"] - 1.0)
    e = min(max(1.0 - 2.0 * chi * V_TYPICAL / 3.0, 0.02), 1.0)  # Hunt-Crossley: chi v0 = 3 (1 - e) / 2
    zeta = -math.log(e) / math.hypot(math.pi, math.log(e))
    k_lin = k * h ** (n1 - 1.0)  # the stiffness of the linear oscillator at that depth
    return k, 2.0 * zeta * math.sqrt(k_lin)
