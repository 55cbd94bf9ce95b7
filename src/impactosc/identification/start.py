"""Start values of the identification: the contact fit and a linear fit of the free flight.

Why these: both are cheap and need no trajectory.  The obstacle's contact fit
(:func:`impactosc.measured.extract.estimate_x_impact`, method "contact") already estimates xI,
kI/m, b and n3 from the samples around the turning points; the free flight is linear in k/m,
c/m, T/m and m0e/m once the acceleration is estimated from the samples
(:func:`impactosc.measured.obstacle.free_flight_law`: a = F sin(phi) + G cos(phi) - (k/m) x
- (c/m) v - (T/m) sgn(v) + a0, least squares over every sample well below the obstacle).
Multiple shooting then starts within a few per cent of its answer.

What the records cannot pin is said here, not discovered as noise later: with fewer than
``MIN_TURNING_POINTS`` turning points near the obstacle the contact fit has nothing to fit, and
kI/m, b, n3 (and xI when the records never come near the obstacle) keep the stated values.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from ..measured.records import Record
from .parameters import NAMES, theta_of

__all__ = ["StartValues", "start_values", "model_time"]

CONTACT_NAMES = ("kI/m", "b", "n3")


class StartValues(dict):
    """theta0 (``theta``), the names the records cannot pin (``unpinned``: name -> reason) and
    the details of the two fits (``contact``, ``free_flight``)."""


def model_time(rec: Record) -> np.ndarray:
    """The record's time as the forcing sees it: phase / w with an encoder, else t."""
    if rec.phase is None:
        return rec.t
    w = float(np.polyfit(rec.t, rec.phase, 1)[0])
    return rec.phase / w


def _contact(records, sigma):
    """The contact fit on each record that has one; (weighted xI, sigma, K, b, n3) or reason."""
    from ..measured.extract import estimate_x_impact

    fits, reasons = [], []
    for rec in records:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                xi, det = estimate_x_impact(rec, method="contact", noise=sigma)
        except ValueError as exc:
            reasons.append(f"{rec.label}: {exc}")
            continue
        fits.append((xi, det))
    if not fits:
        return None, "; ".join(reasons)
    wts = np.array([1.0 / max(d["sigma"], 1e-9) ** 2 for _, d in fits])
    xi = float(np.sum(wts * [f[0] for f in fits]) / wts.sum())
    best = max(fits, key=lambda f: f[1]["n_contacts"])[1]
    return {
        "xI": xi,
        "xI_sigma": float(1.0 / math.sqrt(wts.sum())),
        "kI/m": best["K"],
        "b": best["b"],
        "n3": best["n3"],
        "n_contacts": int(sum(d["n_contacts"] for _, d in fits)),
    }, ""


def _free_flight(records, level):
    from ..measured.obstacle import free_flight_law

    rows, weights = [], []
    for rec in records:
        t = model_time(rec)
        w = rec.omega if rec.phase is None else float(np.polyfit(rec.t, rec.phase, 1)[0])
        try:
            ff = free_flight_law(t, rec.x, level, w)
        except ValueError:
            continue
        _, F, G, cx, cv, cs = ff["coef"]
        rows.append([-cx, -cv, -cs, math.hypot(F, G) / w**2])
        weights.append(ff["n"])
    if not rows:
        return None
    return np.average(np.array(rows), axis=0, weights=weights)


def start_values(records, base, *, sigma) -> StartValues:
    """theta0 for the records, the base model's value wherever the records say nothing."""
    from ..integration.model import ModelParams

    base = base or ModelParams()
    theta = theta_of(base)
    out = StartValues(unpinned={})
    contact, why = _contact(records, sigma)
    if contact is None:
        for nm in CONTACT_NAMES:
            out["unpinned"][nm] = f"no contacts to fit ({why})"
        top = max(float(np.max(r.x)) for r in records)
        level = min(base.xI, top) - 50e-6
        if top < base.xI - 20 * sigma:
            out["unpinned"]["xI"] = (
                f"the records stay below the obstacle (highest sample {top:.6g} m, stated xI {base.xI:.6g} m)"
            )
    else:
        for nm in ("xI", *CONTACT_NAMES):
            theta[NAMES.index(nm)] = contact[nm]
        level = contact["xI"] - 30e-6 - 5 * sigma
    ff = _free_flight(records, level)
    if ff is None:
        for nm in ("k/m", "c/m", "T/m", "m0e/m"):
            out["unpinned"][nm] = "too few free-flight samples"
    else:
        lo = np.array([1.0, 0.0, 0.0, 1e-6])
        theta[:4] = np.maximum(ff, lo)
    out["theta"] = theta
    out["contact"] = contact
    out["free_flight"] = None if ff is None else dict(zip(NAMES[:4], map(float, ff)))
    return out
