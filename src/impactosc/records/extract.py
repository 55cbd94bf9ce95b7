"""Impact events from a sampled, noisy displacement record (the rig's path to the statistics).

Why: the model's events are located exactly on the integrator's dense output; a measured
record only has samples (1-5 kHz) with sensor noise.  This module turns a
:class:`impactosc.records.record.Record` into the same event datasets as ``impactosc simulate``
(``impacts/t, v``; ``penetrations/t, h``; ``poincare/t, x, v`` when omega is known), so
every downstream rule treats a record and a simulation alike.

Method
------
* Noise level sigma: robust (MAD) scale of the second difference of the samples divided
  by sqrt(6) (white noise of std sigma gives a second difference of std sigma sqrt(6); the
  smooth motion contributes a |x''| dt^2 that is small at kHz rates;
  :func:`impactosc.records.sample_fits.estimate_noise`).
* Impact onset = upward crossing of x_impact with hysteresis: a crossing counts only when
  the signal has been below ``x_impact - hysteresis`` since the previous one
  (default hysteresis 5 sigma), so sensor noise around the obstacle level cannot produce
  chatter of false impacts; and a crossing is confirmed only when the contact then rises
  ``confirm_sigmas`` (default 3) noise std above x_impact (a near miss lifted by noise is
  not an impact).
* Sub-sample time: a polynomial fit over the free-flight approach before each crossing, in a
  window chosen from the sample rate, the noise and the record's own motion, so that the
  timing error falls with the rate toward its Cramer-Rao bound; sigma_t is the fit's std at
  the crossing (:mod:`impactosc.records.impact_times`).
* Penetration H_j: vertex of a quadratic fit through the samples around the largest sample
  of each contact (not the raw maximum sample, which is biased up by noise and down by
  sampling).
* Poincare points: x and v from a local quadratic fit (Savitzky-Golay) at the section
  times: where the measured forcing phase (an encoder on the unbalance, ``Record.phase``)
  crosses 2 pi i, timed by a straight-line fit of the phase through the samples around the
  crossing; else at t_i = 2 pi i / omega (the nominal w).  The rig's motor speed is not
  exactly nominal: an error dw slides the nominal section by dw t_i / w of a period after
  t_i, so after a few hundred periods the nominal points are no longer on the section.  The
  encoder also gives w(t): 4 pi over the time between the neighbouring crossings
  (:mod:`impactosc.records.poincare`).

When x_impact is not known, :func:`impactosc.records.obstacle_estimate.estimate_x_impact`
estimates it from the record.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from impactosc.records.contacts import _peaks, _segment_argmax
from impactosc.records.impact_times import derivative_scales, time_impacts
from impactosc.records.obstacle_estimate import estimate_x_impact
from impactosc.records.poincare import poincare_attrs, poincare_points
from impactosc.records.record import Record
from impactosc.records.sample_fits import estimate_noise

__all__ = [
    "ExtractOptions",
    "extract_events",
]

#: Contact-force exponents the obstacle fit allows, given or fitted (soft to stiff contacts).
CONTACT_EXPONENT_RANGE = (1.0, 2.5)


@dataclass(frozen=True)
class ExtractOptions:
    """Settings of :func:`extract_events`.

    noise : float or None
        Sensor noise std (m); None estimates it from the record.
    hysteresis : float or None
        Re-arming distance below x_impact (m); None = ``hysteresis_sigmas`` * noise, at
        least 1e-7 m.  0 (with confirm_sigmas = 0) gives the naive threshold crossing, for
        comparison only.
    hysteresis_sigmas : float
    fit_points : int
        Free-flight samples of the short crossing fit (>= 3), used where an impact's approach is
        too short for the windowed fit (:mod:`impactosc.records.impact_times`).
    peak_half_width : int
        Samples either side of a contact's largest sample in the penetration fit (>= 1).
    confirm_sigmas : float
        A crossing counts only if the contact's largest sample exceeds x_impact by this
        many noise std (penetrations shallower than the noise are not resolvable; this
        keeps near misses lifted above the obstacle by noise out).
    x_impact_method : str
        How :func:`impactosc.records.obstacle_estimate.estimate_x_impact` estimates x_impact when it is neither given nor in the
        record's metadata: "contact" (fit of the contact law, default) or "curvature" (the
        earlier, 8-16 um low estimate).
    contact_exponent : float or None
        Exponent of the contact force in that fit: 1.5 (Hertz, model BC's; default) or None to
        fit it as well (a rig whose contact law is not known; a wider, honest sigma).
    delay : float or None
        Delay of the sensor chain (s; an anti-aliasing filter's group delay), subtracted from
        every sample time before extraction, so that impact, penetration and Poincare times
        are those of the motion.  None: the record's metadata ``sensor_delay`` (the surrogate
        declares its filter's), else 0.
    timing_window : float or None
        Longest window (s) of the impact-time fits; None chooses it from the sample rate, the
        noise and the record's own motion (:func:`impactosc.records.impact_times.window_lengths`).
    """

    noise: float | None = None
    hysteresis: float | None = None
    hysteresis_sigmas: float = 5.0
    fit_points: int = 5
    peak_half_width: int = 2
    confirm_sigmas: float = 3.0
    x_impact_method: str = "contact"
    contact_exponent: float | None = 1.5
    delay: float | None = None
    timing_window: float | None = None

    def __post_init__(self):
        if self.timing_window is not None and not (math.isfinite(self.timing_window) and self.timing_window > 0):
            raise ValueError(f"timing_window must be > 0 s, got {self.timing_window}")
        if self.delay is not None and not (math.isfinite(self.delay) and self.delay >= 0):
            raise ValueError(f"delay must be >= 0 s, got {self.delay}")
        if self.x_impact_method not in ("contact", "curvature"):
            raise ValueError(f"x_impact_method must be 'contact' or 'curvature', got {self.x_impact_method!r}")
        lo, hi = CONTACT_EXPONENT_RANGE
        if self.contact_exponent is not None and not lo <= self.contact_exponent <= hi:
            raise ValueError(
                f"contact_exponent must be in [{lo:g}, {hi:g}] or None (fitted), got {self.contact_exponent}"
            )
        if self.fit_points < 3:
            raise ValueError(f"fit_points must be >= 3, got {self.fit_points}")
        if self.peak_half_width < 1:
            raise ValueError(f"peak_half_width must be >= 1, got {self.peak_half_width}")
        for name in ("noise", "hysteresis"):
            v = getattr(self, name)
            if v is not None and (not math.isfinite(v) or v < 0):
                raise ValueError(f"{name} must be >= 0 m, got {v}")
        for name in ("hysteresis_sigmas", "confirm_sigmas"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")


def extract_events(
    record: Record, x_impact: float | None = None, options: ExtractOptions | None = None
) -> tuple[dict, dict]:
    """Events of a record in the run-file contract, and the attributes describing them.

    Returns ``(events, attrs)`` for :func:`impactosc.io.files.write_run`.  attrs hold x_impact
    (and how it was obtained), the noise level, hysteresis, sample interval, the timing
    uncertainty (median and maximum of the per-impact sigma_t), t_start/t_stop (the
    record's span) and omega when known; with Poincare points, ``poincare_phase_source``
    ("encoder" or "nominal omega") and, from the encoder, the measured w's median and range.
    """
    o = options or ExtractOptions()
    delay, delay_source = o.delay, "given"
    if delay is None:
        try:
            delay, delay_source = float(record.meta.get("sensor_delay", 0.0)), "record metadata"
        except ValueError:
            raise ValueError(
                f"{record.path}: sensor_delay {record.meta['sensor_delay']!r} is not a number (seconds)"
            ) from None
    if delay:
        # every time of the motion is the sample time minus the sensor's delay
        record = dataclasses.replace(record, t=record.t - delay)
    t, x = record.t, record.x
    dt = record.dt
    sigma = o.noise if o.noise is not None else estimate_noise(x)
    attrs = {
        "source": "record",
        "record": str(record.path),
        "label": record.label,
        "t_start": float(t[0]),
        "t_stop": float(t[-1]),
        "sample_interval": dt,
        "noise_sigma": sigma,
        "noise_source": "given" if o.noise is not None else "estimated (MAD of 2nd difference)",
    }
    if delay:
        attrs.update(sensor_delay=delay, sensor_delay_source=delay_source)
    if x_impact is None and "x_impact" in record.meta:
        x_impact, how = float(record.meta["x_impact"]), "record metadata"
    elif x_impact is None:
        x_impact, det = estimate_x_impact(record, method=o.x_impact_method, noise=sigma, exponent=o.contact_exponent)
        if det["method"] == "contact":
            how = (
                f"estimated by fitting the contact law to {det['n_windows']} turning points "
                f"({det['n_contacts']} in contact; impactosc.records.extract.estimate_x_impact, "
                f"+- {det['sigma'] * 1e6:.2g} um"
                + (f"; contact exponent fitted: {det['exponent']:.3f}" if det["exponent_fitted"] else "")
                + ")"
            )
        else:
            how = (
                f"estimated from the curvature of {det['n_contacts']} contact turning points "
                f"(of {det['n_maxima']}; impactosc.records.extract.estimate_x_impact)"
            )
        attrs.update(x_impact_method=det["method"], x_impact_sigma=det["sigma"])
        if det.get("exponent_fitted"):
            attrs.update(contact_exponent=det["exponent"], contact_exponent_sigma=det["exponent_sigma"])
    else:
        how = "given"
    x_impact = float(x_impact)
    attrs.update(x_impact=x_impact, x_impact_source=how)
    hyst = o.hysteresis if o.hysteresis is not None else max(o.hysteresis_sigmas * sigma, 1e-7)
    attrs["hysteresis"] = hyst
    if record.omega is not None:
        attrs["omega"] = record.omega

    above = x >= x_impact
    armed_level = x < x_impact - hyst if hyst > 0 else ~above
    # hysteresis state machine (after each onset, wait for the next arming sample, then for
    # the next sample at/above x_impact), in closed form: an onset is a sample at/above
    # x_impact whose nearest earlier armed-or-above sample is an armed one
    n = x.size
    arm_idx = np.flatnonzero(armed_level)
    marked = np.flatnonzero(armed_level | above)
    is_up = above[marked]
    onsets = marked[1:][is_up[1:] & ~is_up[:-1]] - 1
    # each contact runs from its onset to the next re-arming sample (or the record's end);
    # a contact that never rose clearly above the obstacle (a near miss lifted by noise, or
    # a contact shallower than the noise) is not resolvable from this record
    k = np.searchsorted(arm_idx, onsets + 1)
    stop = np.append(arm_idx, n)[k]
    j = _segment_argmax(x, onsets + 1, stop)
    confirm = o.confirm_sigmas * sigma
    keep = np.flatnonzero(x[j] >= x_impact + confirm)
    # each fit starts after the previous (confirmed) contact; the record's derivative scales
    # set the windows (impactosc.records.impact_times)
    floors = np.concatenate([[0], stop[keep][:-1]]).astype(np.int64)
    scales = derivative_scales(t, x, onsets[keep], floors, x_impact, sigma)
    impacts = time_impacts(
        t, x, onsets[keep], floors, x_impact, sigma, scales=scales, window=o.timing_window, short_points=o.fit_points
    )
    attrs.update(timing_jerk_scale=scales[0], timing_snap_scale=scales[1])
    pen_t, pen_x = _peaks(t, x, j[keep], o.peak_half_width)
    pen_h = np.maximum(pen_x - x_impact, 0.0)
    attrs["n_unconfirmed"] = int(len(onsets) - keep.size)
    attrs["confirm_level"] = confirm
    events = {
        "impacts": impacts,
        "penetrations": {"t": pen_t, "h": pen_h},
    }
    if record.omega is not None or record.phase is not None:
        events["poincare"] = poincare_points(record)
        attrs.update(poincare_attrs(record, events["poincare"]))
    s = events["impacts"]["sigma_t"]
    attrs["n_impacts"] = int(s.size)
    attrs["timing_sigma_median"] = float(np.median(s)) if s.size else float("nan")
    attrs["timing_sigma_max"] = float(np.max(s)) if s.size else float("nan")
    crb = events["impacts"]["crb_t"]
    attrs["timing_crb_median"] = float(np.nanmedian(crb)) if np.isfinite(crb).any() else float("nan")
    return events, attrs
