"""Impact events from a sampled, noisy displacement record (the rig's path to the statistics).

Why: the model's events are located exactly on the integrator's dense output; a measured
record only has samples (1-50 kHz) with sensor noise.  This module turns a
:class:`impactosc.records.record.Record`, or a record file read in chunks
(:class:`impactosc.records.streams.RecordStream`), into the same event datasets as ``impactosc simulate``
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

Records of any length: the noise level, the timing windows and the x_impact estimate come from
the record's first :data:`LEADING_SAMPLES`; then each chunk is searched with the samples before
it that its events need carried over (the longest fit window, a few forcing periods for the
Poincare points, the hysteresis state and the previous contact's end), and an event is taken
from the buffer in which it is complete.  So memory is bounded by the chunk, and the events do
not depend on where the chunks are cut.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from impactosc.model.parameters import ParameterError
from impactosc.records.contacts import _peaks, _segment_argmax, hysteresis_contacts
from impactosc.records.impact_times import derivative_scales, time_impacts, window_samples
from impactosc.records.obstacle_estimate import estimate_x_impact
from impactosc.records.poincare import poincare_attrs, poincare_between, poincare_margin
from impactosc.records.record import Record, check_motion
from impactosc.records.sample_fits import estimate_noise
from impactosc.records.streams import RecordStream

__all__ = [
    "ExtractOptions",
    "extract_events",
]

#: Samples read per chunk by default (8 MB of float64 per array).
CHUNK_SAMPLES = 1 << 20
#: Samples at a record's start on which the noise, the timing fits' derivative scales and (when
#: needed) x_impact are measured: 17 min at 2 kHz, 42 s at 50 kHz.
LEADING_SAMPLES = 1 << 21

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
        if self.delay is not None:
            _check_delay(self.delay, "the sensor delay")
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
                raise ParameterError(name, f"{name} must be >= 0 m, got {v}")
        for name in ("hysteresis_sigmas", "confirm_sigmas"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")


#: Longest sensor delay, s. Why: an anti-aliasing filter delays by about its order / (2 pi
#: cutoff), 1 s being order 10 at a 1.6 Hz cutoff, far below any band that resolves impacts; a
#: larger value is a unit mistake (ms given as s), and 1e300 s overflows the sample times.
MAX_SENSOR_DELAY = 1.0


def _check_delay(delay, name):
    if not (math.isfinite(delay) and 0 <= delay <= MAX_SENSOR_DELAY):
        raise ParameterError("delay", f"{name} must be in [0, {MAX_SENSOR_DELAY:g}] s, got {delay}")
    return delay


def _delay(meta, given, path):
    """The sensor delay (s) and where it came from (given, record metadata)."""
    if given is not None:
        return given, "given"
    try:
        delay = float(meta.get("sensor_delay", 0.0))
    except ValueError:
        raise ValueError(f"{path}: sensor_delay {meta['sensor_delay']!r} is not a number (seconds)") from None
    return _check_delay(delay, f"{path}: sensor_delay"), "record metadata"


def _x_impact(head: Record, x_impact, sigma, o: ExtractOptions, attrs: dict, estimating=None) -> float:
    """x_impact given, from the record's metadata, or estimated from the leading samples ``head``
    (``estimating(head)`` called first)."""
    if x_impact is not None:
        how = "given"
    elif "x_impact" in head.meta:
        x_impact, how = float(head.meta["x_impact"]), "record metadata"
    else:
        if estimating is not None:
            estimating(head)
        x_impact, det = estimate_x_impact(head, method=o.x_impact_method, noise=sigma, exponent=o.contact_exponent)
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
    attrs.update(x_impact=float(x_impact), x_impact_source=how)
    return float(x_impact)


@dataclass
class _Scan:
    """What carries from one buffer of samples to the next."""

    start: int = 0  # absolute index of the buffer's first sample
    emitted: int = 0  # events with onset (absolute) before this index are out
    armed: bool = False  # hysteresis state before the buffer's first sample
    last_end: int = 0  # absolute end of the last confirmed contact
    n_unconfirmed: int = 0
    last_time: float = -math.inf  # time of the last impact out


def _settings(head: Record, sigma, x_impact, hyst, o: ExtractOptions):
    """The record-level constants every buffer uses: the fit windows (from the derivative
    scales on the leading samples) and the lookback they and the Poincare points need."""
    t, x = head.t, head.x
    onsets, ends, _ = hysteresis_contacts(x, x_impact, hyst)
    keep = _confirmed(x, onsets, ends, x_impact + o.confirm_sigmas * sigma)
    floors = np.concatenate([[0], ends[keep][:-1]]).astype(np.int64)
    scales = derivative_scales(t, x, onsets[keep], floors, x_impact, sigma)
    rate = 1.0 / head.dt
    windows = window_samples(sigma, rate, scales, o.timing_window)
    lookback = max(windows) + o.fit_points + 2
    margin = lookback + o.peak_half_width + 2
    return scales, windows, lookback, max(margin, poincare_margin(head))


def _confirmed(x, onsets, ends, level):
    """Indices of the contacts whose largest sample reaches level (the rest are near misses
    lifted by noise, or contacts shallower than the noise: not resolvable from the record)."""
    j = _segment_argmax(x, onsets + 1, ends)
    return np.flatnonzero(x[j] >= level) if j.size else np.empty(0, int)


def _buffer_events(t, x, phase, scan: _Scan, final, c: dict, head: Record):
    """The events of one buffer of samples that are complete in it, and the scan moved on.

    Events whose onset lies in [scan.emitted, e1) are emitted, e1 being ``margin`` samples
    before the buffer's end (its end when ``final``) or the first onset whose contact (and
    penetration fit) does not end in the buffer.  Returns (impacts, penetrations, Poincare
    points, the start of the next buffer (absolute)).
    """
    n, b0 = x.size, scan.start
    onsets, ends, _ = hysteresis_contacts(x, c["xi"], c["hyst"], scan.armed)
    done = scan.emitted - b0  # events before this index (in the buffer) are out
    e1 = n
    if not final:
        e1 = max(n - c["margin"], done)
        late = (onsets >= done) & (ends + c["half"] + 1 >= n)  # a contact or its peak fit runs on
        if late.any():
            e1 = min(e1, int(onsets[np.argmax(late)]))
    take = (onsets >= done) & (onsets < e1) & (onsets >= 0)
    onsets, ends = onsets[take], ends[take]
    keep = _confirmed(x, onsets, ends, c["xi"] + c["confirm"])
    scan.n_unconfirmed += int(onsets.size - keep.size)
    on, en = onsets[keep], ends[keep]
    prev_end = np.concatenate([[scan.last_end - b0], en[:-1]])
    floors = np.maximum(np.maximum(prev_end, on - c["lookback"]), 0).astype(np.int64)
    j = _segment_argmax(x, on + 1, en)
    impacts = time_impacts(
        t,
        x,
        on,
        floors,
        c["xi"],
        c["sigma"],
        windows=c["windows"],
        peaks=j,
        ends=en,
        short_points=c["fit_points"],
        after=scan.last_time,
    )
    if impacts["t"].size:
        scan.last_time = float(impacts["t"][-1])
    pen_t, pen_x = _peaks(t, x, j, c["half"])
    penetrations = {"t": pen_t, "h": np.maximum(pen_x - c["xi"], 0.0)}
    poincare = None
    if c["poincare"]:
        lo = t[done] if scan.emitted > 0 else -math.inf
        hi = math.inf if final else t[e1] if e1 < n else t[-1] + 1.0
        poincare = poincare_between(dataclasses.replace(head, t=t, x=x, phase=phase), lo, hi)
    if en.size:
        scan.last_end = int(en[-1]) + b0
    # the next buffer starts a lookback before e1, in the hysteresis state there
    nxt = max(e1 - c["margin"], 0)
    before = x[:nxt]
    armed = before < c["xi"] - c["hyst"] if c["hyst"] > 0 else before < c["xi"]
    marked = np.flatnonzero(armed | (before >= c["xi"]))
    if marked.size:
        scan.armed = bool(armed[marked[-1]])
    scan.emitted = e1 + b0
    scan.start = nxt + b0
    return impacts, penetrations, poincare, nxt


def _joined(parts):
    """One dict of arrays from the dicts of each buffer."""
    parts = [p for p in parts if p is not None]
    if not parts:
        return None
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def extract_events(
    record: Record | RecordStream,
    x_impact: float | None = None,
    options: ExtractOptions | None = None,
    *,
    chunk_samples: int = CHUNK_SAMPLES,
    progress=None,
    estimating=None,
) -> tuple[dict, dict]:
    """Events of a record in the run-file contract, and the attributes describing them.

    ``record``: a :class:`Record` in memory or a :class:`impactosc.records.streams.RecordStream`
    (a file read in chunks of ``chunk_samples``: memory bounded whatever the record's length).
    The noise level, the derivative scales of the timing fits and, when it is neither given
    nor in the metadata, x_impact are measured on the record's first :data:`LEADING_SAMPLES`
    samples; every event is then found in the chunk that holds it, with the samples before it
    carried over, so the events do not depend on where the chunks are cut.  ``progress``:
    called with the share of the record done after each chunk; ``estimating``: called with the
    leading samples (a :class:`Record`) before x_impact is estimated from them.

    Returns ``(events, attrs)`` for :func:`impactosc.io.files.write_run`.  attrs hold x_impact
    (and how it was obtained), the noise level, hysteresis, sample interval, the timing
    uncertainty (median and maximum of the per-impact sigma_t), t_start/t_stop (the
    record's span) and omega when known; with Poincare points, ``poincare_phase_source``
    ("encoder" or "nominal omega") and, from the encoder, the measured w's median and range.
    """
    o = options or ExtractOptions()
    stream = RecordStream.from_record(record) if isinstance(record, Record) else record
    if chunk_samples < 1:
        raise ValueError(f"chunk_samples must be >= 1, got {chunk_samples}")
    delay, delay_source = _delay(stream.meta, o.delay, stream.path)
    lead = stream.read(0, LEADING_SAMPLES)
    if lead.x.size and (lead.x.size < LEADING_SAMPLES or stream.n_samples == lead.x.size):  # the whole record
        check_motion(stream.path, float(lead.x.min()), float(lead.x.max()), "extract")
    # every time of the motion is the sample time minus the sensor's delay
    head = Record(lead.t - delay, lead.x, stream.omega, stream.meta, stream.path, lead.phase)
    sigma = o.noise if o.noise is not None else estimate_noise(head.x)
    attrs = {
        "source": "record",
        "record": str(stream.path),
        "label": stream.label,
        "sample_interval": head.dt,
        "noise_sigma": sigma,
        "noise_source": "given" if o.noise is not None else "estimated (MAD of 2nd difference)",
    }
    if delay:
        attrs.update(sensor_delay=delay, sensor_delay_source=delay_source)
    xi = _x_impact(head, x_impact, sigma, o, attrs, estimating)
    hyst = o.hysteresis if o.hysteresis is not None else max(o.hysteresis_sigmas * sigma, 1e-7)
    attrs["hysteresis"] = hyst
    if stream.omega is not None:
        attrs["omega"] = stream.omega
    scales, windows, lookback, margin = _settings(head, sigma, xi, hyst, o)
    attrs.update(timing_jerk_scale=scales[0], timing_snap_scale=scales[1])
    c = {
        "xi": xi,
        "hyst": hyst,
        "sigma": sigma,
        "confirm": o.confirm_sigmas * sigma,
        "half": o.peak_half_width,
        "fit_points": o.fit_points,
        "windows": windows,
        "lookback": lookback,
        "margin": margin,
        "poincare": stream.omega is not None or stream.has_phase,
    }
    scan, parts, carry = _Scan(), [], None
    first = last = None
    x_min, x_max = math.inf, -math.inf
    chunks = stream.chunks(max(int(chunk_samples), 1))
    chunk = next(chunks, None)
    while chunk is not None:
        following = next(chunks, None)
        t, x, phase = chunk.t - delay, chunk.x, chunk.phase
        first = t[0] if first is None and t.size else first
        last = t[-1] if t.size else last
        if x.size:
            x_min, x_max = min(x_min, float(x.min())), max(x_max, float(x.max()))
        if carry is not None:
            t, x = np.concatenate([carry[0], t]), np.concatenate([carry[1], x])
            phase = None if phase is None else np.concatenate([carry[2], phase])
        parts.append(_buffer_events(t, x, phase, scan, following is None, c, head))
        k = parts[-1][3]
        carry = (t[k:], x[k:], None if phase is None else phase[k:])
        if progress is not None and stream.n_samples:
            progress(min((chunk.start + chunk.x.size) / stream.n_samples, 1.0))
        chunk = following
    if first is None:
        raise ValueError(f"{stream.path}: the record has no samples")
    check_motion(stream.path, x_min, x_max, "extract")
    attrs.update(t_start=float(first), t_stop=float(last))
    attrs["n_unconfirmed"] = scan.n_unconfirmed
    attrs["confirm_level"] = c["confirm"]
    events = {"impacts": _joined(p[0] for p in parts), "penetrations": _joined(p[1] for p in parts)}
    if c["poincare"]:
        events["poincare"] = _joined(p[2] for p in parts)
        attrs.update(poincare_attrs(head, events["poincare"]))
    s = events["impacts"]["sigma_t"]
    attrs["n_impacts"] = int(s.size)
    attrs["timing_sigma_median"] = float(np.median(s)) if s.size else float("nan")
    attrs["timing_sigma_max"] = float(np.max(s)) if s.size else float("nan")
    crb = events["impacts"]["crb_t"]
    attrs["timing_crb_median"] = float(np.nanmedian(crb)) if np.isfinite(crb).any() else float("nan")
    return events, attrs
