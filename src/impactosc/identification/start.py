"""Start values of the identification: the contact fit and a linear fit of the free flight.

Why these: both are cheap and need no trajectory.  The obstacle's contact fit
(:func:`impactosc.records.obstacle_estimate.estimate_x_impact`, method "contact") already estimates xI,
kI/m, b and n3 from the samples around the turning points; the free flight is linear in k/m,
c/m, T/m and m0e/m once the acceleration is estimated from the samples (as
:func:`impactosc.records.obstacle.free_flight_law` does for one record: a = (m0e/m) w^2 sin(phi)
- (k/m) x - (c/m) v - (T/m) sgn(v) + a0, least squares over every sample well below the obstacle,
here over all records at once).
Multiple shooting then starts within a few per cent of its answer.

What the records cannot pin is said here, not discovered as noise later: with fewer than
``MIN_TURNING_POINTS`` turning points near the obstacle the contact fit has nothing to fit, and
kI/m, b, n3 (and xI when the records never come near the obstacle) keep the stated values.

The contact fit is model BC's law (Hertz stiffness, damping b |v|^n3); another law starts from it
through :func:`for_law`, as the law's component says (the same damping at a typical impact,
``V_TYPICAL``, for a restitution law; the same deepest penetration and restitution for a linear one).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from impactosc.identification.fitted_parameters import NAMES, QUANTITIES, law_quantities, theta_of
from impactosc.model.contact_laws import LAWS
from impactosc.model.contact_laws.component import V_TYPICAL

__all__ = ["StartValues", "start_values", "for_law", "V_TYPICAL"]

CONTACT_NAMES = ("kI/m", "b", "n3")


class StartValues(dict):
    """theta0 (``theta``), the names the records cannot pin (``unpinned``: name -> reason) and
    the details of the two fits (``contact``, ``free_flight``)."""


def _contact(records, sigma):
    """The contact fit on each record that has one; (weighted xI, sigma, K, b, n3) or reason."""
    from impactosc.records.obstacle_estimate import estimate_x_impact

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
        return None, reasons[0] + (f" (and {len(reasons) - 1} more records alike)" if len(reasons) > 1 else "")
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


def _free_flight(records, level, half_t=10e-3):
    """k/m, c/m, T/m, m0e/m from one regression over every record's free flight, or None.

    Why one regression over all records (the obstacle module fits one record at a time): at a
    single w a steady motion is nearly a sinusoid, and x, sin(w t), cos(w t) are then nearly
    collinear, so k/m and m0e/m trade off; the forcing's amplitude grows like w^2, the spring's
    does not, so records at several w separate them.  Columns: w^2 sin(phi), w^2 cos(phi)
    (shared: m0e/m and the phase's error), x, v, sgn(v) (shared), one offset per record.
    """
    from scipy.ndimage import maximum_filter1d
    from scipy.signal import savgol_filter

    rows, rhs = [], []
    for r, rec in enumerate(records):
        dt = float(np.median(np.diff(rec.t)))
        hw = max(3, int(round(half_t / dt)))
        if rec.x.size < 2 * hw + 2:
            continue
        a = savgol_filter(rec.x, 2 * hw + 1, 4, deriv=2, delta=dt)
        v = savgol_filter(rec.x, 2 * hw + 1, 4, deriv=1, delta=dt)
        ok = maximum_filter1d(rec.x, 2 * hw + 1, mode="nearest") < level
        ok[:hw] = ok[rec.x.size - hw :] = False
        if ok.sum() < 200:
            continue
        phi = rec.phase if rec.phase is not None else rec.omega * rec.t
        w = rec.omega if rec.phase is None else float(np.polyfit(rec.t, rec.phase, 1)[0])
        offsets = np.zeros((int(ok.sum()), len(records)))
        offsets[:, r] = 1.0
        cols = [w * w * np.sin(phi[ok]), w * w * np.cos(phi[ok]), rec.x[ok], v[ok], np.sign(v[ok])]
        rows.append(np.column_stack([*cols, offsets]))
        rhs.append(a[ok])
    if not rows:
        return None
    coef = np.linalg.lstsq(np.vstack(rows), np.concatenate(rhs), rcond=None)[0]
    F, G, cx, cv, cs = coef[:5]
    return np.array([-cx, -cv, -cs, math.hypot(F, G)])


def start_values(records, base, *, sigma) -> StartValues:
    """theta0 for the records, the base model's value wherever the records say nothing."""
    from impactosc.model.parameters import ModelParams

    base = base or ModelParams()
    theta = theta_of(base, full=True)
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
    return for_law(out, base.law)


def for_law(start: StartValues, law: str) -> StartValues:
    """The start values for the contact law `law` from those of the contact fit (model BC's law):
    the law's own (:meth:`impactosc.model.contact_laws.ContactLaw.start`: a restitution law's e
    whose damping at a typical impact matches the fit's, a linear law's stiffness with the same
    deepest penetration and its damping with the same restitution, ...). Names the law does not
    have leave ``unpinned``; without a contact fit the law's own quantities are unpinned too."""
    theta = start["theta"].copy()
    own = law_quantities(law)
    unpinned = {nm: why for nm, why in start["unpinned"].items() if nm in own}
    contact = start.get("contact")
    component = LAWS[law]
    if contact is not None:
        for nm, value in component.start(contact, dict(zip(QUANTITIES, theta))).items():
            theta[QUANTITIES.index(nm)] = value
    else:
        why = next((w for nm, w in start["unpinned"].items() if nm in CONTACT_NAMES), "no contacts to fit")
        unpinned.update({nm: why for nm in component.quantities if nm in own and nm not in CONTACT_NAMES})
    return StartValues(start, theta=theta, unpinned=unpinned)
