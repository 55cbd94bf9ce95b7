"""The effective restitution of a contact law: e_eff = -v_exit / v0 of a free impact, by the core.

Why: a restitution law is built for a nominal e, but its damping chi(e, v0) is a closed-form
approximation (Flores et al. 2011, Multibody System Dynamics 25:357): how closely a free impact
delivers e is a property of the law, measured here. A free impact is the cart against the
obstacle with no spring, forcing or friction to speak of (their smallest values the model takes),
from just outside the obstacle at velocity v0 until it has left it.
"""

from __future__ import annotations

import dataclasses
import warnings

from scipy.optimize import brentq

from impactosc.core.layout import S_V, S_X
from impactosc.core.simulation import simulate
from impactosc.model.contact_laws import LAWS, RestitutionLaw
from impactosc.model.parameters import ModelParams, UntestedParameterWarning

__all__ = ["FREE_IMPACT", "delivers", "effective_restitution", "matched_e", "matched_models", "restitution_rows"]

#: the model without spring, forcing or friction (the smallest values it takes), obstacle at 0
FREE_IMPACT = dict(k=1e-60, c=0.0, T=0.0, m0e=1e-60, xI=0.0)
#: start this far outside the obstacle (m): the approach takes 1e-6 / v0 s of free flight
GAP = 1e-6
#: the nominal e a match searches: chi grows as 1 / e (Flores, Gonthier), so e -> 0 dissipates all
E_BRACKET = (1e-3, 1.0)
#: the match's tolerance on e: far below what a diagram resolves, far above the core's error in e_eff
E_XTOL = 1e-10


def effective_restitution(params: ModelParams, v0: float, *, rtol: float = 1e-12, atol: float = 1e-15) -> float:
    """-v_exit / v0 of one free impact at v0 > 0 (m/s) of the law and contact of `params` (its
    spring, forcing, friction and obstacle replaced by a free impact's)."""
    if not v0 > 0:
        raise ValueError(f"v0 must be > 0 m/s, got {v0}")
    with warnings.catch_warnings():  # no spring or forcing: outside the tested ranges on purpose
        warnings.simplefilter("ignore", UntestedParameterWarning)
        free = dataclasses.replace(params, **FREE_IMPACT)
    # Hertz's contact time scale (m^2 / (kI^2 v0))^(1 / (n1 + 2)), with room for a slow, damped exit
    contact = 3.0 * (free.m**2 / (free.kI**2 * v0)) ** (1.0 / (free.n1 + 2.0))
    run = simulate(10.0, 0.0, GAP / v0 + 1000.0 * contact, x0=-GAP, v0=v0, params=free, rtol=rtol, atol=atol, record=())
    x, v = run.final_state[S_X], run.final_state[S_V]
    if not (x < free.xI and v < 0):
        raise RuntimeError(f"the {free.law} impact at v0 = {v0} m/s has not left the obstacle (x = {x}, v = {v})")
    return -float(v) / v0


def matched_e(params: ModelParams, law: str, v0: float) -> float:
    """The nominal e of restitution law `law` whose free impact at v0 (m/s) dissipates what the
    model `params` dissipates at v0: effective_restitution equal at v0, by a root finder (e_eff
    rises with e, to 1 at e = 1). Why: a law compared at its nominal e alone would differ from
    model BC by its dissipation, not by the shape of its force."""
    if not isinstance(LAWS[law], RestitutionLaw):
        raise ValueError(f"the {law} law takes no e (the restitution laws: {', '.join(_restitution_laws())})")
    target = effective_restitution(params, v0)

    def gap(e):
        return effective_restitution(dataclasses.replace(params, law=law, e=float(e)), v0) - target

    lo, hi = E_BRACKET
    if not gap(lo) < 0 < gap(hi):
        raise ValueError(f"no e in {E_BRACKET} of the {law} law delivers e_eff = {target} at v0 = {v0} m/s")
    return float(brentq(gap, lo, hi, xtol=E_XTOL))


def matched_models(params: ModelParams, laws, v0: float) -> list[dict]:
    """One row per law of `laws`: the model `params` with that law (a restitution law's e
    matched at v0 by :func:`matched_e`, any other law taking params' own numbers), its nominal e
    (None without one), its e_eff at v0 and that of `params`, the reference."""
    reference = effective_restitution(params, v0)
    rows = []
    for law in laws:
        e = matched_e(params, law, v0) if isinstance(LAWS[law], RestitutionLaw) else None
        model = dataclasses.replace(params, law=law, **({"e": e} if e is not None else {}))
        rows.append(
            {"law": law, "e": e, "e_eff": effective_restitution(model, v0), "reference": reference, "params": model}
        )
    return rows


def _restitution_laws():
    return [name for name, law in LAWS.items() if isinstance(law, RestitutionLaw)]


def restitution_rows(params: ModelParams, e_values, v0_values) -> list[dict]:
    """One row per (law, e, v0) of the restitution laws: nominal e, v0, e_eff and e_eff - e."""
    rows = []
    for law in _restitution_laws():
        for e in e_values:
            for v0 in v0_values:
                eff = effective_restitution(dataclasses.replace(params, law=law, e=float(e)), float(v0))
                rows.append({"law": law, "e": float(e), "v0": float(v0), "e_eff": eff, "difference": eff - e})
    return rows


def delivers(rows, tolerance: float = 0.05) -> dict:
    """Per law: the nominal e (of the rows) whose e_eff lies within `tolerance` of it, and the
    largest |e_eff - e|."""
    out = {}
    for row in rows:
        entry = out.setdefault(row["law"], {"within": [], "worst": 0.0})
        if abs(row["difference"]) <= tolerance:
            entry["within"].append(row["e"])
        entry["worst"] = max(entry["worst"], abs(row["difference"]))
    return {law: {**v, "within": sorted(set(v["within"]))} for law, v in out.items()}
