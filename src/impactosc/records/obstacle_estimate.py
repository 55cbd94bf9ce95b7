"""The obstacle position x_impact estimated from a record that does not state it.

Why a module: a rig's record gives the motion but not where the obstacle is, and event
extraction needs it; the estimate (the contact law fitted to the turning points near the
obstacle, :mod:`impactosc.records.obstacle`, started from the curvature of those turning
points) is also what the coverage study (:mod:`impactosc_study.coverage`) and the
identification's start check.
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.records.record import Record
from impactosc.records.sample_fits import estimate_noise, quadratic_fits

__all__ = ["estimate_x_impact"]


def _local_maxima(x, half):
    """Indices of samples that are the largest within +-half samples."""
    from scipy.ndimage import maximum_filter1d

    m = maximum_filter1d(x, size=2 * half + 1, mode="nearest")
    return np.flatnonzero((x == m) & (np.arange(x.size) >= half) & (np.arange(x.size) < x.size - half))


def estimate_x_impact(
    record: Record,
    *,
    method: str = "contact",
    window: float | None = None,
    noise: float | None = None,
    n3: float | None = None,
    exponent: float | None = 1.5,
) -> tuple[float, dict]:
    """Estimate the obstacle position x_impact (m) from a record, with its uncertainty.

    ``method="contact"`` (default): the contact law fitted to the samples around every turning
    point near the obstacle, the free-flight acceleration (forcing, spring, damping, friction)
    measured on the rest of the record (:func:`impactosc.records.obstacle.fit_contact_law`,
    whose docstring gives the method).  The curvature estimate below is its starting point.
    On the model's chaotic attractor (w = 40.86, 2 kHz, c + 1 %; 6 segments of 60 s x 5 noise
    seeds, :mod:`impactosc_study.coverage`, target measured_x_impact_coverage) the error is
    -0.03 +- 0.12 um at 5 um noise and +0.08 +- 0.22 um at 10 um (mean +- its standard error; sd
    0.63 and 1.22 um against a median stated sigma of 0.65 and 1.26 um); the stated sigma, from
    the fit covariance, holds the truth within 1 sigma in 22/30 and 20/30 draws, within 2 sigma
    in 30/30 and 30/30.  The curvature estimate: -8.7 to -10.7 um.  About 1 s per 60 s of record
    at 2 kHz (docs/measured.md, tests/test_obstacle.py).

    ``method="curvature"``: the earlier estimate.  At a turning point in free flight the
    curvature |x''| is the spring and forcing acceleration (a few m/s^2 here); at a turning point
    in contact it grows with the penetration, like kI/m (x_max - x_impact)^1.5 (tens of m/s^2).
    Each turning point (maximum within +-5 ms) gets a height and curvature from a quadratic fit
    over +-``window`` s (default 2.5 ms); turning points with curvature above a quarter of the
    median and above 5 times the fit's noise are taken as contacts; a robust (Theil-Sen)
    straight line of curvature^(2/3) against height then crosses zero at x_impact.  Measured
    8-16 um too low on the chaotic attractor at <= 5 um noise (the quadratic misses the sharp,
    lopsided peak of the contact acceleration by 9-25 %, growing with depth; module
    impactosc.records.obstacle); no uncertainty.

    noise : sensor-noise std (m); None estimates it (:func:`estimate_noise`).
    n3 : contact method only: fix the damping exponent (None fits it).
    exponent : contact method only: the contact-force exponent (1.5, Hertz: model BC's law), or
        None to fit it too.  Why offer it: with the exponent fixed, a rig whose law differs is
        estimated precisely but off (an emulated exponent of about 1.9 moved the estimate by +3.7
        and +5.7 um on 30 s at 5 um noise, beyond 2 sigma); fitted, the exponent trades off
        against x_impact and the stated sigma grows to 7-9 um on 30 s, covering the truth there;
        over 30 draws of 60 s it is unbiased but its sigma is 4-12 % smaller than the spread
        (docs/measured.md: a lower bound).

    Returns (estimate, details): details hold ``method``, ``sigma`` (1-sigma uncertainty, m;
    nan for the curvature method), n_maxima, n_contacts, noise and the method's own numbers.
    """
    if method not in ("contact", "curvature"):
        raise ValueError(f"method must be 'contact' or 'curvature', got {method!r}")
    curv, det = _curvature_estimate(record, window=2.5e-3 if (window is None or method == "contact") else window)
    if noise is not None:
        det["noise"] = float(noise)
    det["method"] = "curvature"
    det["sigma"] = float("nan")
    if method == "curvature":
        return curv, det
    from impactosc.records.obstacle import fit_contact_law

    fit = fit_contact_law(
        record.t,
        record.x,
        curv,
        det["noise"],
        omega=record.omega,
        K0=det["slope"] ** 1.5,
        window=window if window is not None else 2.5e-3,
        n3=n3,
        exponent=exponent,
    )
    ff = fit.pop("free_flight")
    return fit["x_impact"], {
        "method": "contact",
        "sigma": fit["sigma"],
        "curvature_estimate": curv,
        "n_maxima": det["n_maxima"],
        "noise": det["noise"],
        **fit,
        "omega": ff["omega"],
        "omega_estimated": ff["omega_estimated"],
        "free_flight_samples": ff["n"],
        "free_flight_rms": ff["rms"],
    }


def _curvature_estimate(record: Record, *, window: float) -> tuple[float, dict]:
    """The curvature estimate of :func:`estimate_x_impact` (``method="curvature"``)."""
    from scipy import stats

    sigma = estimate_noise(record.x)
    t, x, dt = record.t, record.x, record.dt
    hf = max(2, int(round(window / dt)))
    idx = _local_maxima(x, max(1, int(round(5e-3 / dt))))
    idx = idx[(idx >= hf) & (idx < x.size - hf)]
    if idx.size < 5:
        raise ValueError(f"{record.path}: only {idx.size} turning points; cannot estimate x_impact, pass it")
    c, _ = quadratic_fits(t, x, idx - hf, idx + hf + 1, t[idx])
    s = np.zeros(idx.size)
    top = c[:, 2] < 0
    s[top] = -c[top, 1] / (2 * c[top, 2])
    curv, height = -2 * c[:, 2], c[:, 0] + c[:, 1] * s + c[:, 2] * s * s
    _, cov = quadratic_fits(t, x, np.array([0]), np.array([2 * hf + 1]), t[[hf]])
    curv_noise = 2 * sigma * math.sqrt(cov[0, 2, 2])
    contact = curv > max(0.25 * np.median(curv), 5 * curv_noise)
    if contact.sum() < 3:
        raise ValueError(
            f"{record.path}: only {int(contact.sum())} turning points look like contacts; "
            "cannot estimate x_impact, pass it"
        )
    slope, intercept, _, _ = stats.theilslopes(curv[contact] ** (2 / 3), height[contact])
    if not slope > 0:
        raise ValueError(
            f"{record.path}: contact curvature does not grow with height; cannot estimate x_impact, pass it"
        )
    return float(-intercept / slope), {
        "n_maxima": int(idx.size),
        "n_contacts": int(contact.sum()),
        "noise": sigma,
        "curvature_noise": curv_noise,
        "slope": float(slope),
    }
