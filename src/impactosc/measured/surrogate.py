"""Surrogate rig data: the model sampled like the rig, with sensor noise and parameter mismatch.

Why: until a user supplies measured records, the paper's experimental panels are drawn
from this stand-in, which goes through exactly the record path (CSV/HDF5 record ->
:mod:`impactosc.measured.extract` -> statistics).  It is always labelled
``"surrogate (model + noise)"`` and carries its settings as metadata, never called
experimental.

* sampling at ``rate`` Hz (a data-acquisition card's 1-5 kHz),
* additive white Gaussian sensor noise of std ``noise`` (m), seeded,
* a small parameter mismatch: relative changes of ModelParams fields, e.g. {"c": 0.02},
* optional sensor realism (each off by default; :class:`SurrogateOptions`): a causal
  Butterworth anti-aliasing filter, a slow zero drift, sample-clock jitter and ADC quantisation.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..analysis.chaotic import analyse_train
from ..analysis.impact_train import ImpactTrain
from ..integration.model import ModelParams
from ..integration.simulate import Window, simulate
from .extract import ExtractOptions, estimate_noise, estimate_x_impact, extract_events
from .records import Record

__all__ = [
    "LABEL",
    "panel_hooked",
    "noise_study",
    "SurrogateOptions",
    "butterworth_delay",
    "mismatched_params",
    "surrogate_record",
    "surrogate_sweep",
    "surrogate_driven",
    "ramp_omegas",
    "surrogate_ramp",
]

LABEL = "surrogate (model + noise)"


@dataclasses.dataclass(frozen=True)
class SurrogateOptions:
    """How the model is turned into a record; every realism option is off (0) by default.

    rate : sample rate, Hz.
    noise : std of the white sensor noise, m (added after the filter, at the samples).
    mismatch : model parameter -> relative change.
    seed : seed of every random draw (noise first, then drift, then jitter: with the realism
        options off the noise is the same as without them).
    lowpass_hz, lowpass_order : causal Butterworth anti-aliasing filter (cutoff, Hz, below
        rate / 2; order) applied to the motion before sampling.  Simulated on an 8 times finer
        grid (an analog filter, not its sampled copy) and then sampled.  It delays the signal by
        its group delay, ``butterworth_delay`` (0.83 ms for order 4 at 500 Hz), which the record
        declares in its metadata as ``sensor_delay`` (s); extraction subtracts it.
    drift, drift_time : slow zero drift of the sensor, an Ornstein-Uhlenbeck process of std
        ``drift`` (m) and correlation time ``drift_time`` (s) (a random walk pulled back to zero
        over drift_time), added to every sample.
    clock_jitter : std of the sample-time errors, s: sample k is the signal at t_k + e_k (e_k
        white Gaussian) but is stamped t_k.
    quantum : ADC step, m: every sample is rounded to a multiple of it, last (e.g. a 16-bit
        card over a 20 mm range: 20e-3 / 2**16 = 0.31 um).
    """

    rate: float = 2000.0
    noise: float = 5e-6
    mismatch: dict = dataclasses.field(default_factory=dict)
    seed: int = 0
    lowpass_hz: float = 0.0
    lowpass_order: int = 4
    drift: float = 0.0
    drift_time: float = 10.0
    clock_jitter: float = 0.0
    quantum: float = 0.0

    def __post_init__(self):
        if not math.isfinite(self.rate) or self.rate <= 0:
            raise ValueError(f"rate must be > 0 Hz, got {self.rate}")
        if not math.isfinite(self.noise) or self.noise < 0:
            raise ValueError(f"noise must be >= 0 m, got {self.noise}")
        for name, unit in (("lowpass_hz", "Hz"), ("drift", "m"), ("clock_jitter", "s"), ("quantum", "m")):
            v = getattr(self, name)
            if not math.isfinite(v) or v < 0:
                raise ValueError(f"{name} must be >= 0 {unit} (0: off), got {v}")
        if self.lowpass_hz >= self.rate / 2:
            raise ValueError(
                f"lowpass_hz must be below half the sample rate ({self.rate / 2:g} Hz), got {self.lowpass_hz}"
            )
        if not (isinstance(self.lowpass_order, int) and 1 <= self.lowpass_order <= 10):
            raise ValueError(f"lowpass_order must be an integer 1-10, got {self.lowpass_order!r}")
        if not math.isfinite(self.drift_time) or self.drift_time <= 0:
            raise ValueError(f"drift_time must be > 0 s, got {self.drift_time}")
        if self.clock_jitter >= 0.5 / self.rate:
            raise ValueError(f"clock_jitter must be well below the sample interval, got {self.clock_jitter} s")
        object.__setattr__(self, "mismatch", dict(self.mismatch or {}))

    @property
    def oversample(self) -> int:
        """Simulation grid per sample interval: 8 with the anti-aliasing filter, else 1."""
        return 8 if self.lowpass_hz > 0 else 1

    @property
    def sensor_delay(self) -> float:
        """Group delay of the anti-aliasing filter at low frequency, s (0 without it)."""
        if self.lowpass_hz <= 0:
            return 0.0
        return butterworth_delay(self.lowpass_order, self.lowpass_hz, self.rate * self.oversample)


def butterworth_delay(order: int, cutoff_hz: float, fs: float) -> float:
    """Low-frequency group delay (s) of the causal Butterworth low-pass (order, cutoff) at fs.

    A slowly varying signal comes out of the filter delayed by this (the first moment of the
    impulse response); for the analog filter it is sum_k sin((2k - 1) pi / (2 order)) / (2 pi
    cutoff) over the poles, e.g. 2.613 / (2 pi cutoff) for order 4.
    """
    from scipy.signal import butter, group_delay

    b, a = butter(order, cutoff_hz, fs=fs)
    _, gd = group_delay((b, a), w=[1e-4 * cutoff_hz], fs=fs)
    return float(gd[0]) / fs


def mismatched_params(params: ModelParams | None, mismatch: dict) -> ModelParams:
    """ModelParams with each named field scaled by (1 + relative change)."""
    params = params or ModelParams()
    names = {f.name for f in dataclasses.fields(params)}
    unknown = set(mismatch) - names
    if unknown:
        raise ValueError(f"unknown model parameter(s) {sorted(unknown)} in mismatch; known: {sorted(names)}")
    for k, r in mismatch.items():
        if not math.isfinite(r) or abs(r) >= 0.5:
            raise ValueError(f"mismatch of {k} must be a small relative change (|r| < 0.5), got {r}")
    return dataclasses.replace(params, **{k: getattr(params, k) * (1 + r) for k, r in mismatch.items()})


def _meta(o: SurrogateOptions, params: ModelParams, extra=None) -> dict:
    meta = {
        "label": LABEL,
        "source": "surrogate",
        "surrogate_rate_hz": o.rate,
        "surrogate_noise_m": o.noise,
        "surrogate_seed": o.seed,
        "surrogate_mismatch": ", ".join(f"{k}{r:+g}" for k, r in sorted(o.mismatch.items())) or "none",
        "x_impact": params.xI,
    }
    # realism options only when on (records without them keep their metadata)
    if o.lowpass_hz > 0:
        meta.update(
            surrogate_lowpass_hz=o.lowpass_hz, surrogate_lowpass_order=o.lowpass_order, sensor_delay=o.sensor_delay
        )
    if o.drift > 0:
        meta.update(surrogate_drift_m=o.drift, surrogate_drift_time_s=o.drift_time)
    if o.clock_jitter > 0:
        meta["surrogate_clock_jitter_s"] = o.clock_jitter
    if o.quantum > 0:
        meta["surrogate_quantum_m"] = o.quantum
    meta.update(extra or {})
    return meta


def _noisy(traj, o: SurrogateOptions, rng):
    """The recorded samples of a trajectory (t, x, v on a grid of 1 / (rate * k), k >= 1).

    Order of the sensor chain: anti-aliasing filter on the fine grid -> sampling every k-th
    point at the jittered instants -> + zero drift -> + white noise -> ADC rounding.  With
    every realism option off this is x + noise, drawn exactly as before they existed.
    """
    t, x = traj["t"], traj["x"]
    k = max(1, int(round(1.0 / (o.rate * float(t[1] - t[0]))))) if t.size > 1 else 1
    v = traj.get("v")
    if o.lowpass_hz > 0:
        from scipy.signal import butter, sosfilt, sosfilt_zi

        sos = butter(o.lowpass_order, o.lowpass_hz, fs=o.rate * k, output="sos")
        zi = sosfilt_zi(sos)
        # started in steady state at the first value (no switch-on transient); the filter is
        # linear, so the filtered velocity is the velocity of the filtered signal
        x = sosfilt(sos, x, zi=zi * x[0])[0]
        v = sosfilt(sos, v, zi=zi * v[0])[0] if v is not None else None
    x = x[::k]
    n = x.size
    out = x + (rng.normal(0.0, o.noise, n) if o.noise > 0 else 0.0)
    if o.drift > 0:
        from scipy.signal import lfilter

        rho = math.exp(-1.0 / (o.rate * o.drift_time))
        e = rng.normal(0.0, o.drift, n + 1)
        # stationary Ornstein-Uhlenbeck: d_0 ~ N(0, drift^2), d_j = rho d_j-1 + sqrt(1 - rho^2) e_j
        d = lfilter([math.sqrt(1 - rho * rho)], [1.0, -rho], e[1:], zi=[rho * e[0]])[0]
        out = out + d
    if o.clock_jitter > 0:
        vv = v[::k] if v is not None else np.gradient(x, 1.0 / o.rate)
        # the signal at t_k + e_k: x + v e (the neglected x'' e^2 / 2 is below 1e-10 m for e <= 10 us)
        out = out + vv * rng.normal(0.0, o.clock_jitter, n)
    if o.quantum > 0:
        out = o.quantum * np.round(out / o.quantum)
    return out


def surrogate_record(
    omega,
    transient,
    duration,
    options: SurrogateOptions | None = None,
    *,
    params: ModelParams | None = None,
    x0=0.0,
    v0=0.0,
    rtol=1e-10,
    atol=1e-12,
):
    """A record of the model at ``omega`` sampled on [transient, transient + duration].

    Returns (record, truth) where truth is the simulation's exact event dict (for tests
    and the noise study).  x_impact is stored in the metadata (the rig's obstacle position
    would be measured too).
    """
    o = options or SurrogateOptions()
    p = mismatched_params(params, o.mismatch)
    win = Window(float(transient), float(transient) + float(duration), 1.0 / (o.rate * o.oversample))
    res = simulate(
        omega,
        transient,
        duration,
        x0=x0,
        v0=v0,
        params=p,
        rtol=rtol,
        atol=atol,
        window=win,
        record=("impacts", "penetrations", "poincare"),
    )
    rng = np.random.default_rng(o.seed)
    t = res.trajectory["t"][:: o.oversample]
    rec = Record(t, _noisy(res.trajectory, o, rng), float(omega), _meta(o, p), "<surrogate>")
    return rec, res.events


def surrogate_sweep(
    omegas,
    n_transient,
    n_record,
    options: SurrogateOptions | None = None,
    *,
    params: ModelParams | None = None,
    n_initial=None,
    x0=0.0,
    v0=0.0,
    rtol=1e-10,
    atol=1e-12,
) -> list[Record]:
    """Per-w records of a slow sweep (the rig's bifurcation experiment), in the given w order.

    Each w runs a whole number of forcing periods (n_transient discarded, n_record
    sampled), so the end state is at phase 0 and seeds the next w (continuation, like
    turning the rig's speed knob).  The first w discards ``n_initial`` periods.
    """
    o = options or SurrogateOptions()
    p = mismatched_params(params, o.mismatch)
    rng = np.random.default_rng(o.seed)
    out = []
    for k, w in enumerate(np.asarray(omegas, dtype=float)):
        period = 2 * math.pi / w
        ntr = n_initial if (k == 0 and n_initial is not None) else n_transient
        tr, du = ntr * period, n_record * period
        win = Window(tr, tr + du, 1.0 / o.rate)
        res = simulate(w, tr, du, x0=x0, v0=v0, params=p, rtol=rtol, atol=atol, window=win, record=("impacts",))
        x0, v0 = float(res.final_state[1]), float(res.final_state[2])
        out.append(
            Record(res.trajectory["t"], _noisy(res.trajectory, o, rng), float(w), _meta(o, p), f"<surrogate w={w:g}>")
        )
    return out


def surrogate_driven(
    omegas,
    options: SurrogateOptions | None = None,
    *,
    params: ModelParams | None = None,
    n_initial: int = 0,
    encoder_counts: int | None = None,
    x0=0.0,
    v0=0.0,
    rtol=1e-10,
    atol=1e-12,
):
    """A record of the model whose forcing frequency changes from one forcing period to the
    next (period k at ``omegas[k]``), with the forcing phase as an encoder would measure it.

    Why chained runs: the core takes w as a constant of the run (``sin(w t)`` in absolute
    time), so a varying motor speed is built from one run per forcing period, each started at
    its own phase 0 from the previous run's end state (x, v): state and forcing phase are
    continuous, w is a staircase with one step per period (for a slow ramp, steps of
    ``dw/dt`` times a period, e.g. 0.002 rad/s).  The forcing amplitude follows w^2, as an
    unbalance's does (the small term of the motor's angular acceleration is left out).  A run
    restarted during a sticking phase re-enters it only if v is exactly 0 (as in
    :func:`surrogate_sweep`).

    ``n_initial`` periods at ``omegas[0]`` are discarded first (started from x0, v0).  The
    samples lie on one uniform grid ``t0 + j / rate``, t0 the end of that transient (at
    constant w the samples equal :func:`surrogate_record`'s).  The phase
    is exact, or with ``encoder_counts`` = N read as an encoder counter does: whole counts
    (floor of N phase / 2 pi), reported as the centre of the count (count + 1/2) in rad.

    Returns (record, truth): the record (x with sensor noise, ``phase``, nominal omega =
    the mean of ``omegas``; meta as :func:`surrogate_record`'s plus the speed profile) and the
    exact truth: ``poincare`` t, x, v, omega (the state at the start of every period, where
    the true phase is 2 pi i), ``impacts`` t, v, and ``phase`` at the samples.
    """
    o = options or SurrogateOptions()
    p = mismatched_params(params, o.mismatch)
    omegas = np.asarray(omegas, dtype=float)
    if omegas.ndim != 1 or omegas.size < 1 or not np.all(np.isfinite(omegas) & (omegas > 0)):
        raise ValueError("omegas must be a non-empty list of forcing frequencies > 0 rad/s, one per period")
    if encoder_counts is not None and not encoder_counts >= 4:
        raise ValueError(f"encoder_counts must be >= 4 counts per revolution, got {encoder_counts}")
    k_over = o.oversample
    dt = 1.0 / (o.rate * k_over)  # the simulation grid (finer than the samples under the filter)
    solver = dict(params=p, rtol=rtol, atol=atol)
    T = 0.0
    if n_initial > 0:
        P0 = 2 * math.pi / omegas[0]
        res = simulate(omegas[0], 0.0, n_initial * P0, x0=x0, v0=v0, record=(), **solver)
        x0, v0, T = float(res.final_state[1]), float(res.final_state[2]), n_initial * P0

    t_first = T

    def first_sample(t):  # index of the first grid sample t_first + j dt at or after t
        return math.ceil((t - t_first) / dt - 1e-9)

    xs, vs, pt, px, pv, it, iv, lens = [], [], [], [], [], [], [], []
    for w in omegas.tolist():
        P = 2 * math.pi / w
        js, je = first_sample(T), first_sample(T + P)
        win = None
        if je > js:
            s0 = max(t_first + js * dt - T, 0.0)
            win = Window(s0, min(s0 + (je - js - 0.5) * dt, P), dt)
        res = simulate(w, 0.0, P, x0=x0, v0=v0, window=win, record=("impacts",), **solver)
        pt.append(T), px.append(x0), pv.append(v0)
        if win is not None:
            xs.append(res.trajectory["x"][: je - js])
            vs.append(res.trajectory["v"][: je - js])
            lens.append(je - js)
        it.append(T + res.events["impacts"]["t"]), iv.append(res.events["impacts"]["v"])
        x0, v0 = float(res.final_state[1]), float(res.final_state[2])
        T += P
    fine = {"x": np.concatenate(xs), "v": np.concatenate(vs)}
    fine["t"] = t_first + np.arange(fine["x"].size) * dt
    x = _noisy(fine, o, np.random.default_rng(o.seed))  # the samples, every k_over-th grid point
    t = fine["t"][::k_over]
    # exact forcing phase at the samples: 2 pi (n_initial + k) + w_k (t - T_k) in period k
    k = np.repeat(np.arange(len(lens)), lens)[::k_over]
    starts = np.asarray(pt)
    true_phase = 2 * math.pi * (n_initial + k) + omegas[k] * (t - starts[k])
    phase = true_phase
    if encoder_counts is not None:
        c = encoder_counts / (2 * math.pi)
        phase = (np.floor(true_phase * c) + 0.5) / c
    extra = {
        "surrogate_omega_first": float(omegas[0]),
        "surrogate_omega_last": float(omegas[-1]),
        "surrogate_n_periods": int(omegas.size),
        "surrogate_encoder_counts": int(encoder_counts) if encoder_counts is not None else "exact",
    }
    rec = Record(t, x, float(np.mean(omegas)), _meta(o, p, extra), "<surrogate driven>", phase)
    truth = {
        "poincare": {"t": starts, "x": np.asarray(px), "v": np.asarray(pv), "omega": omegas.copy()},
        "impacts": {"t": np.concatenate(it), "v": np.concatenate(iv)},
        "phase": true_phase,
    }
    return rec, truth


def ramp_omegas(start, stop, duration):
    """Forcing frequency of each period of a linear ramp from ``start`` to ``stop`` rad/s over
    ``duration`` s: period k runs at w(T_k), T_k its start time (a staircase of one step per
    period, which :func:`surrogate_driven` integrates)."""
    start, stop, duration = float(start), float(stop), float(duration)
    if not (start > 0 and stop > 0 and duration > 0):
        raise ValueError(f"ramp needs start, stop > 0 rad/s and duration > 0 s, got {start}, {stop}, {duration}")
    out, T = [], 0.0
    while duration > T:
        w = start + (stop - start) * T / duration
        out.append(w)
        T += 2 * math.pi / w
    return np.asarray(out)


def surrogate_ramp(start, stop, duration, options: SurrogateOptions | None = None, *, n_initial=1000, **kwargs):
    """A slow sweep in one record: w ramped linearly from ``start`` to ``stop`` over
    ``duration`` s (the rig's experimental bifurcation diagram, as its motor produces it),
    with an encoder phase; ``n_initial`` periods at ``start`` discarded first.  Slow enough to
    be quasi-stationary when dw/dt times the relaxation time (0.9 s measured) moves the
    attractor by little: at 0.01 rad/s^2 (25 rad/s in 2500 s) the lag is below 6 um on the
    flat parts of the period-1 branch, 45 um on its steep part (:mod:`impactosc.measured.sweep`).
    Keywords as :func:`surrogate_driven`; returns (record, truth)."""
    rec, truth = surrogate_driven(ramp_omegas(start, stop, duration), options, n_initial=n_initial, **kwargs)
    meta = dict(rec.meta, surrogate_ramp=f"{float(start):g} -> {float(stop):g} rad/s in {float(duration):g} s")
    return dataclasses.replace(rec, meta=meta, path="<surrogate ramp>"), truth


def _match(true_t, found_t):
    """Nearest-neighbour one-to-one matching of found to true impact times."""
    if found_t.size == 0 or true_t.size == 0:
        return np.empty(0, int), np.empty(0, int)
    j = np.clip(np.searchsorted(true_t, found_t), 1, true_t.size - 1)
    near = np.where(np.abs(true_t[j] - found_t) < np.abs(true_t[j - 1] - found_t), j, j - 1)
    half = np.minimum(np.diff(true_t, prepend=-np.inf), np.diff(true_t, append=np.inf))[near] / 2
    ok = np.abs(found_t - true_t[near]) < half
    found, true = np.flatnonzero(ok), near[ok]
    _, first = np.unique(true, return_index=True)  # a true impact claimed twice counts once
    return found[first], true[first]


def _train_numbers(times, t0, t1, omega, analysis):
    """Scalars of the noise study from :func:`impactosc.analysis.chaotic.analyse_train`."""
    a = analyse_train(ImpactTrain(times, t0, t1, omega=omega), analysis, ("variability", "isi_density", "acf"))
    d = a["isi_density"]
    g, dens, mx = np.asarray(d["kde_grid"]), np.asarray(d["kde_density"]), np.asarray(d["maxima"])
    valley = float("nan")
    if mx.size >= 2:
        # depth of the bimodality: density minimum between the outer maxima / lower maximum
        inside = (g > mx[0]) & (g < mx[-1])
        valley = float(dens[inside].min() / min(np.interp(mx[0], g, dens), np.interp(mx[-1], g, dens)))
    return {
        "cv2_paper": a["variability"]["cv2_paper"],
        "cv2": a["variability"]["cv2"],
        "isi_n_modes": int(d["n_modes"]),
        "isi_maxima": " ".join(f"{m:.4f}" for m in mx),
        "isi_valley_ratio": valley,
        "acf_n_significant": int(a["acf"]["n_significant"]),
        "kde_grid": g,
        "kde_density": dens,
    }


def _extraction_row(rec, x_impact, truth, opts: ExtractOptions) -> tuple[dict, np.ndarray]:
    """Extract the events of rec with the known x_impact and score them against the truth.

    Returns (columns, extracted impact times).  Timing: rms error, largest |error| / stated
    sigma_t, the median |error| against the median Cramer-Rao bound of the matched impacts and
    ``timing_crb_ratio`` = median(|error| / bound) / 0.6745 (1 when every impact is timed with
    the bound's precision: |error| / bound is then half-normal, median 0.6745).  Penetration:
    median error and median |error| of the depths of the matched impacts.
    """
    T, Ht = truth["impacts"]["t"], truth["penetrations"]["h"]
    ev, at = extract_events(rec, x_impact, opts)
    E, s, crb = ev["impacts"]["t"], ev["impacts"]["sigma_t"], ev["impacts"]["crb_t"]
    fi, ti = _match(T, E)
    err = E[fi] - T[ti]
    nan = float("nan")
    row = {
        "n_true": T.size,
        "n_found": E.size,
        "missed": T.size - ti.size,
        "extra": E.size - fi.size,
        "timing_rms_s": float(np.sqrt(np.mean(err**2))) if err.size else nan,
        "timing_bias_s": float(np.median(err)) if err.size else nan,
        "timing_max_z": float(np.max(np.abs(err) / s[fi])) if err.size else nan,
        "frac_beyond_5sigma": float(np.mean(np.abs(err) > 5 * s[fi])) if err.size else nan,
        "sigma_t_median_s": at["timing_sigma_median"],
        "noise_estimate_m": at["noise_sigma"],
    }
    c = crb[fi]
    ok = np.isfinite(c) & (c > 0)
    if ok.any():
        row.update(
            timing_err_median_s=float(np.median(np.abs(err[ok]))),
            timing_crb_median_s=float(np.median(c[ok])),
            timing_crb_ratio=float(np.median(np.abs(err[ok]) / c[ok]) / 0.6745),
        )
    if Ht.size == T.size and ti.size:
        dh = ev["penetrations"]["h"][fi] - Ht[ti]
        row.update(penetration_bias_m=float(np.median(dh)), penetration_err_median_m=float(np.median(np.abs(dh))))
    return row, E


def _x_impact_columns(rec, span, x_true) -> dict:
    """Error and stated sigma of estimate_x_impact on the first ``span`` s of rec (nothing if span is 0)."""
    if not span:
        return {}
    n = int(np.searchsorted(rec.t, rec.t[0] + span, side="right"))
    part = Record(rec.t[:n], rec.x[:n], rec.omega, {}, rec.path)
    try:
        est, det = estimate_x_impact(part)
    except ValueError as exc:
        return {"x_impact_note": str(exc)}
    return {"x_impact_err_m": est - x_true, "x_impact_sigma_m": det["sigma"]}


def _realism_name(case: dict) -> str:
    """Method label of a realism row, e.g. 'realism: low-pass 500 Hz order 4, delay corrected'."""
    parts = []
    if case.get("quantum"):
        parts.append(f"ADC step {case['quantum'] * 1e6:g} um")
    if case.get("lowpass_hz"):
        how = "delay corrected" if case.get("declare_delay", True) else "delay not declared"
        parts.append(f"low-pass {case['lowpass_hz']:g} Hz order {case.get('lowpass_order', 4)}, {how}")
    if case.get("drift"):
        parts.append(f"zero drift {case['drift'] * 1e6:g} um over {case.get('drift_time', 10.0):g} s")
    if case.get("clock_jitter"):
        parts.append(f"clock jitter {case['clock_jitter'] * 1e6:g} us")
    return "realism: " + ("; ".join(parts) or "none")


def noise_study(
    omega,
    transient,
    duration,
    rates,
    noises,
    *,
    analysis=None,
    mismatch=None,
    seed=0,
    params=None,
    rtol=1e-10,
    atol=1e-12,
    x_impact_span=0.0,
    x_impact_noise=(),
    realism=None,
    realism_noise=5e-6,
    realism_rate=None,
):
    """How sampling rate, sensor noise and sensor imperfections change the extracted train.

    For each rate one simulation is sampled; for each noise level white noise is added,
    events are extracted twice (with hysteresis, and naive threshold crossing for
    comparison) and matched to the exact events.  Returns a list of row dicts (one per
    rate x noise x method, plus the exact train per rate) with the counts (true, found,
    missed, extra), the timing error (rms, median = bias, max |error| / stated sigma_t), the
    median stated sigma_t, the timing error against the Cramer-Rao bound
    (:func:`_extraction_row`), the penetration-depth error, and C_V^2 (paper and
    dimensionless), ISI modes / valley depth and significant ACF-spectrum peaks; the ISI
    kernel densities are returned under ``kde`` per row.

    x_impact_span : s; when > 0, the hysteresis row of every rate x noise also gets the error
        and stated sigma of :func:`estimate_x_impact` on the first x_impact_span s of the record
        (only at the noise levels in ``x_impact_noise`` when it is not empty).
    realism : list of dicts of :class:`SurrogateOptions` realism fields (lowpass_hz,
        lowpass_order, drift, drift_time, clock_jitter, quantum), one extra row each at
        ``realism_noise`` and ``realism_rate`` (default: the first rate), method
        ``"realism: ..."``, plus a ``"realism: none"`` row with the same noise draws.  A case
        with ``declare_delay: false`` drops the filter's sensor_delay from the record's metadata
        (the delay is then not corrected: its timing bias shows).
    """
    stray = sorted(set(x_impact_noise) - set(noises))
    if stray:
        raise ValueError(f"x_impact_noise {stray} not among the study's noise levels {list(noises)}")
    out = []
    for rate in rates:
        base = SurrogateOptions(rate=float(rate), noise=0.0, mismatch=mismatch or {}, seed=seed)
        rec0, truth = surrogate_record(omega, transient, duration, base, params=params, rtol=rtol, atol=atol)
        T = truth["impacts"]["t"]
        x_true = rec0.meta["x_impact"]
        t0, t1 = float(rec0.t[0]), float(rec0.t[-1])
        exact = _train_numbers(T, t0, t1, omega, analysis)
        out.append(
            {
                "rate_hz": rate,
                "noise_m": 0.0,
                "method": "exact events",
                "n_true": T.size,
                "n_found": T.size,
                "missed": 0,
                "extra": 0,
                **exact,
            }
        )
        rng = np.random.default_rng(seed)
        for noise in noises:
            # no omega: the study needs the impacts, not the Poincare points (the costliest
            # part of extraction left); the noise is estimated once for both methods
            x = rec0.x + (rng.normal(0, noise, rec0.x.size) if noise > 0 else 0.0)
            rec = Record(rec0.t, x, None, rec0.meta, rec0.path)
            sigma = estimate_noise(x)
            for method, opts in (
                ("hysteresis", ExtractOptions(noise=sigma)),
                ("naive threshold", ExtractOptions(noise=sigma, hysteresis=0.0, confirm_sigmas=0.0)),
            ):
                cols, E = _extraction_row(rec, x_true, truth, opts)
                row = {"rate_hz": rate, "noise_m": noise, "method": method, **cols}
                if method == "hysteresis" and (not x_impact_noise or noise in x_impact_noise):
                    row.update(_x_impact_columns(Record(rec0.t, x, omega, {}, rec0.path), x_impact_span, x_true))
                try:
                    row.update(_train_numbers(E, t0, t1, omega, analysis))
                except ValueError as exc:  # e.g. too few impacts left: say so in the table
                    row["note"] = str(exc)
                out.append(row)
    if realism:
        out.extend(
            _realism_rows(
                omega,
                transient,
                duration,
                float(realism_rate or rates[0]),
                realism_noise,
                realism,
                mismatch=mismatch,
                seed=seed,
                params=params,
                rtol=rtol,
                atol=atol,
                x_impact_span=x_impact_span,
            )
        )
    return out


_REALISM_FIELDS = ("lowpass_hz", "lowpass_order", "drift", "drift_time", "clock_jitter", "quantum")


def _realism_rows(omega, transient, duration, rate, noise, cases, *, mismatch, seed, params, rtol, atol, x_impact_span):
    """Rows of :func:`noise_study` for the sensor-realism cases (one simulation on the fine grid)."""
    for case in cases:
        unknown = set(case) - set(_REALISM_FIELDS) - {"declare_delay"}
        if unknown:
            raise ValueError(f"unknown realism option(s) {sorted(unknown)}; known: {list(_REALISM_FIELDS)}")
    p = mismatched_params(params, mismatch or {})
    # the fine grid of the anti-aliasing filter when a case has one
    k = SurrogateOptions(rate=rate, lowpass_hz=0.25 * rate).oversample if any(c.get("lowpass_hz") for c in cases) else 1
    win = Window(float(transient), float(transient) + float(duration), 1.0 / (rate * k))
    res = simulate(
        omega, transient, duration, params=p, rtol=rtol, atol=atol, window=win, record=("impacts", "penetrations")
    )
    truth, traj = res.events, res.trajectory
    coarse = {name: traj[name][::k] for name in ("t", "x", "v")}
    t = coarse["t"]
    out = []
    for case in [{}, *cases]:
        fields = {f: case[f] for f in _REALISM_FIELDS if f in case}
        o = SurrogateOptions(rate=rate, noise=noise, mismatch=mismatch or {}, seed=seed, **fields)
        x = _noisy(traj if o.oversample > 1 else coarse, o, np.random.default_rng(seed))
        meta = _meta(o, p)
        if not case.get("declare_delay", True):
            meta.pop("sensor_delay", None)
        rec = Record(t, x, None, meta, "<surrogate>")
        cols, _ = _extraction_row(rec, p.xI, truth, ExtractOptions(noise=estimate_noise(x)))
        row = {"rate_hz": rate, "noise_m": noise, "method": _realism_name(case), **cols}
        if o.lowpass_hz > 0:  # the filter's delay, corrected or not (see the method)
            row["sensor_delay_s"] = o.sensor_delay
        xrec = Record(t - meta.get("sensor_delay", 0.0), x, omega, {}, "<surrogate>")
        row.update(_x_impact_columns(xrec, x_impact_span, p.xI))
        out.append(row)
    return out


def panel_hooked(name: str, entry: dict | None, path_key: str, path: str, is_surrogate: bool) -> bool:
    """Whether a figure panel (config ``name``) is drawn from ``path``; checks its label.

    Why: the surrogate must never be called experimental, and a real record must not keep
    the surrogate's label.  Raises ValueError naming the config key when the label
    contradicts the data source.
    """
    if not entry or entry[path_key] != path:
        return False
    says = "surrogate" in entry["label"].lower()
    if is_surrogate and not says:
        raise ValueError(
            f"config {name}.label is {entry['label']!r} but the panel shows the surrogate "
            f"(no measured record configured): label it {LABEL!r}"
        )
    if not is_surrogate and says:
        raise ValueError(
            f"config {name}.label says surrogate but a measured record is configured; name the record instead"
        )
    return True
