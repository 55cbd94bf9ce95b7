"""Surrogate rig data: the model sampled like the rig, with sensor noise and parameter mismatch.

Why: until a user supplies measured records, the paper's experimental panels are drawn
from this stand-in, which goes through exactly the record path (CSV/HDF5 record ->
:mod:`impactosc.records.extract` -> statistics).  It is always labelled
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

from impactosc.core.simulation import MAX_T_END, Window, end_state, simulate, start_of
from impactosc.io.memory import shortfall
from impactosc.model.noise import Noise
from impactosc.model.parameters import ModelParams, ParameterError
from impactosc.records.record import MIN_SAMPLES, Record
from impactosc.records.surrogate_truth import LABEL, surrogate_meta

__all__ = [
    "LABEL",
    "REALISM_FIELDS",
    "SurrogateOptions",
    "butterworth_delay",
    "mismatched_params",
    "surrogate_run",
    "sample_run",
    "surrogate_record",
    "sensor_samples",
    "surrogate_sweep",
    "surrogate_driven",
    "ramp_omegas",
    "surrogate_ramp",
]

#: Bytes a surrogate record takes per point of its simulation grid, up to its file (trajectory,
#: samples, noise, the writer's text or buffers). Measured by the peak RSS of `impactosc
#: surrogate` (110 s against 10 s at 20 kHz): 31 B per sample to .h5, 47 B to .csv, 42 B per grid
#: point with the anti-aliasing filter's 8 times finer grid.
BYTES_PER_GRID_POINT = 48
#: Bytes per forcing period of a driven record (one core run each, its arrays kept until the end);
#: measured the same way (--ramp 40 40.5 at 200 Hz, 500 s against 50 s): 2.6 kB besides the samples.
BYTES_PER_PERIOD = 3000
# the sensor-realism fields of SurrogateOptions (config measured.surrogate, noise-study cases)
REALISM_FIELDS = ("lowpass_hz", "lowpass_order", "drift", "drift_time", "clock_jitter", "quantum")


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
    dynamics : noise in the dynamics the rig's model is driven with (a ``noise:`` block or a
        :class:`impactosc.model.noise.Noise`: the motor's speed jitter, a random force), None: none;
        the record's label stays the surrogate's, its metadata says which noise.
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
    dynamics: Noise | dict | None = None

    def __post_init__(self):
        if not math.isfinite(self.rate) or self.rate <= 0:
            raise ParameterError("rate", f"rate must be > 0 Hz, got {self.rate}")
        if not math.isfinite(self.noise) or self.noise < 0:
            raise ParameterError("noise", f"noise must be >= 0 m, got {self.noise}")
        for name, unit in (("lowpass_hz", "Hz"), ("drift", "m"), ("clock_jitter", "s"), ("quantum", "m")):
            v = getattr(self, name)
            if not math.isfinite(v) or v < 0:
                raise ParameterError(name, f"{name} must be >= 0 {unit} (0: off), got {v}")
        if self.lowpass_hz >= self.rate / 2:
            raise ParameterError(
                "lowpass_hz",
                f"lowpass_hz must be below half the sample rate ({self.rate / 2:g} Hz), got {self.lowpass_hz}",
            )
        if not (isinstance(self.lowpass_order, int) and 1 <= self.lowpass_order <= 10):
            raise ParameterError("lowpass_order", f"lowpass_order must be an integer 1-10, got {self.lowpass_order!r}")
        if not math.isfinite(self.drift_time) or self.drift_time <= 0:
            raise ParameterError("drift_time", f"drift_time must be > 0 s, got {self.drift_time}")
        if self.clock_jitter >= 0.5 / self.rate:
            raise ParameterError(
                "clock_jitter", f"clock_jitter must be well below the sample interval, got {self.clock_jitter} s"
            )
        if isinstance(self.seed, int) and self.seed < 0:
            raise ParameterError("seed", f"seed must be an integer >= 0, got {self.seed}")
        object.__setattr__(self, "mismatch", dict(self.mismatch or {}))
        if not isinstance(self.dynamics, Noise):
            object.__setattr__(self, "dynamics", Noise.from_dict(self.dynamics, "dynamics"))

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


def sensor_samples(traj, o: SurrogateOptions, rng, state: dict | None = None):
    """The recorded samples of a trajectory (t, x, v on a grid of 1 / (rate * k), k >= 1).

    Order of the sensor chain: anti-aliasing filter on the fine grid -> sampling every k-th
    point at the jittered instants -> + zero drift -> + white noise -> ADC rounding.  With
    every realism option off this is x + noise, drawn exactly as before they existed.

    ``state`` (a dict, empty before the first chunk) makes the trajectory one chunk of a longer
    one (:mod:`impactosc.records.long_surrogate`): the filter and drift states go on from the
    previous chunk.  With noise, filter and ADC the chunks give the whole record's samples;
    drift and jitter are then drawn chunk by chunk (same statistics, other values).
    """
    state = {} if state is None else state
    t, x = traj["t"], traj["x"]
    if "k" not in state:  # the grid's points per sample
        state["k"] = max(1, int(round(1.0 / (o.rate * float(t[1] - t[0]))))) if t.size > 1 else 1
    k = state["k"]
    v = traj.get("v")
    if o.lowpass_hz > 0:
        from scipy.signal import butter, sosfilt, sosfilt_zi

        sos = butter(o.lowpass_order, o.lowpass_hz, fs=o.rate * k, output="sos")
        zi = sosfilt_zi(sos)
        # started in steady state at the first value (no switch-on transient); the filter is
        # linear, so the filtered velocity is the velocity of the filtered signal
        x, state["zx"] = sosfilt(sos, x, zi=state.get("zx", zi * x[0]))
        if v is not None:
            v, state["zv"] = sosfilt(sos, v, zi=state.get("zv", zi * v[0]))
    x = x[::k]
    n = x.size
    out = x + (rng.normal(0.0, o.noise, n) if o.noise > 0 else 0.0)
    if o.drift > 0:
        from scipy.signal import lfilter

        rho = math.exp(-1.0 / (o.rate * o.drift_time))
        if "zd" in state:
            e = rng.normal(0.0, o.drift, n)
        else:  # stationary Ornstein-Uhlenbeck: d_0 ~ N(0, drift^2), d_j = rho d_j-1 + sqrt(1 - rho^2) e_j
            e = rng.normal(0.0, o.drift, n + 1)
            state["zd"], e = [rho * e[0]], e[1:]
        d, state["zd"] = lfilter([math.sqrt(1 - rho * rho)], [1.0, -rho], e, zi=state["zd"])
        out = out + d
    if o.clock_jitter > 0:
        vv = v[::k] if v is not None else np.gradient(x, 1.0 / o.rate)
        # the signal at t_k + e_k: x + v e (the neglected x'' e^2 / 2 is below 1e-10 m for e <= 10 us)
        out = out + vv * rng.normal(0.0, o.clock_jitter, n)
    if o.quantum > 0:
        out = o.quantum * np.round(out / o.quantum)
    return out


def _check_size(duration, o: SurrogateOptions, periods=0.0) -> None:
    """Refuse, before simulating it, a record too short to be read as one (fewer than
    MIN_SAMPLES samples) or whose arrays exceed the machine's memory (``periods``: the chained
    runs of a driven record, each with arrays of its own)."""
    points = float(duration) * o.rate * o.oversample + 1
    if points / o.oversample < MIN_SAMPLES:
        raise ParameterError(
            "rate",
            f"a record of {points / o.oversample:.3g} samples; a record needs at least {MIN_SAMPLES}: take a higher "
            "rate or a longer duration",
        )
    by_samples, by_periods = BYTES_PER_GRID_POINT * points, BYTES_PER_PERIOD * periods
    need = shortfall(by_samples + by_periods)
    if need and by_periods > by_samples:
        raise ParameterError(
            "ramp", f"a ramp of {periods:.3g} forcing periods {need}; take a slower w or a shorter duration"
        )
    if need:
        raise ParameterError(
            "rate", f"a record of {points / o.oversample:.3g} samples {need}; take a lower rate or a shorter duration"
        )


def surrogate_run(
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
    progress=None,
):
    """The simulation a surrogate record samples: the exact events from ``transient`` on and
    the trajectory on the sampling grid (finer under the anti-aliasing filter); ``progress``
    as :func:`impactosc.core.simulation.simulate`'s.

    Apart from :func:`surrogate_record` so that a workflow can simulate it once, write it as a
    run file and sample it in several jobs (:func:`sample_run`).
    """
    o = options or SurrogateOptions()
    p = mismatched_params(params, o.mismatch)
    _check_size(duration, o)
    win = Window(float(transient), float(transient) + float(duration), 1.0 / (o.rate * o.oversample))
    return simulate(
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
        progress=progress,
        noise=o.dynamics,
    )


def sample_run(trajectory, omega, options: SurrogateOptions | None = None, *, params: ModelParams | None = None):
    """The record the sensor of ``options`` takes of a :func:`surrogate_run` trajectory (noise
    drawn from its seed), with the surrogate's metadata."""
    o = options or SurrogateOptions()
    rng = np.random.default_rng(o.seed)
    t = trajectory["t"][:: o.oversample]
    meta = surrogate_meta(o, mismatched_params(params, o.mismatch))
    return Record(t, sensor_samples(trajectory, o, rng), float(omega), meta, "<surrogate>")


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
    progress=None,
):
    """A record of the model at ``omega`` sampled on [transient, transient + duration].

    Returns (record, truth) where truth is the simulation's exact event dict (for tests
    and the noise study).  x_impact is stored in the metadata (the rig's obstacle position
    would be measured too).
    """
    res = surrogate_run(
        omega, transient, duration, options, params=params, x0=x0, v0=v0, rtol=rtol, atol=atol, progress=progress
    )
    return sample_run(res.trajectory, omega, options, params=params), res.events


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
    state = np.array([x0, v0], float)  # with a restitution contact's onset velocity once inside one
    for k, w in enumerate(np.asarray(omegas, dtype=float)):
        period = 2 * math.pi / w
        ntr = n_initial if (k == 0 and n_initial is not None) else n_transient
        tr, du = ntr * period, n_record * period
        win = Window(tr, tr + du, 1.0 / o.rate)
        res = simulate(w, tr, du, **start_of(state), params=p, rtol=rtol, atol=atol, window=win, record=("impacts",))
        state = end_state(res)
        out.append(
            Record(
                res.trajectory["t"],
                sensor_samples(res.trajectory, o, rng),
                float(w),
                surrogate_meta(o, p),
                f"<surrogate w={w:g}>",
            )
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
    progress=None,
):
    """A record of the model whose forcing frequency changes from one forcing period to the
    next (period k at ``omegas[k]``), with the forcing phase as an encoder would measure it.

    Why chained runs: the core takes w as a constant of the run (``sin(w t)`` in absolute
    time), so a varying motor speed is built from one run per forcing period, each started at
    its own phase 0 from the previous run's end state (x, v, and a restitution contact's onset
    velocity): state and forcing phase are
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
    the true phase is 2 pi i), ``impacts`` t, v, and ``phase`` at the samples.  ``progress(t,
    t_end, n_impacts)`` is called after each period (t from the end of the transient).
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
    span = float(np.sum(2 * math.pi / omegas))
    _check_size(span, o, periods=omegas.size)
    solver = dict(params=p, rtol=rtol, atol=atol)
    T = 0.0
    state = np.array([x0, v0], float)  # with a restitution contact's onset velocity once inside one
    if n_initial > 0:
        P0 = 2 * math.pi / omegas[0]
        state = end_state(simulate(omegas[0], 0.0, n_initial * P0, **start_of(state), record=(), **solver))
        T = n_initial * P0

    t_first = T

    def first_sample(t):  # index of the first grid sample t_first + j dt at or after t
        return math.ceil((t - t_first) / dt - 1e-9)

    xs, vs, pt, px, pv, it, iv, lens = [], [], [], [], [], [], [], []
    n_impacts = 0
    for w in omegas.tolist():
        P = 2 * math.pi / w
        js, je = first_sample(T), first_sample(T + P)
        win = None
        if je > js:
            s0 = max(t_first + js * dt - T, 0.0)
            win = Window(s0, min(s0 + (je - js - 0.5) * dt, P), dt)
        res = simulate(w, 0.0, P, **start_of(state), window=win, record=("impacts",), **solver)
        pt.append(T), px.append(float(state[0])), pv.append(float(state[1]))
        if win is not None:
            xs.append(res.trajectory["x"][: je - js])
            vs.append(res.trajectory["v"][: je - js])
            lens.append(je - js)
        it.append(T + res.events["impacts"]["t"]), iv.append(res.events["impacts"]["v"])
        state = end_state(res)
        T += P
        n_impacts += res.events["impacts"]["t"].size
        if progress is not None:
            progress(T - t_first, span, n_impacts)
    fine = {"x": np.concatenate(xs), "v": np.concatenate(vs)}
    fine["t"] = t_first + np.arange(fine["x"].size) * dt
    x = sensor_samples(fine, o, np.random.default_rng(o.seed))  # the samples, every k_over-th grid point
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
    rec = Record(t, x, float(np.mean(omegas)), surrogate_meta(o, p, extra), "<surrogate driven>", phase)
    truth = {
        "poincare": {"t": starts, "x": np.asarray(px), "v": np.asarray(pv), "omega": omegas.copy()},
        "impacts": {"t": np.concatenate(it), "v": np.concatenate(iv)},
        "phase": true_phase,
    }
    return rec, truth


def _check_ramp(start, stop, duration) -> tuple[float, float, float]:
    start, stop, duration = float(start), float(stop), float(duration)
    if not (start > 0 and stop > 0 and duration > 0):
        raise ValueError(f"ramp needs start, stop > 0 rad/s and duration > 0 s, got {start}, {stop}, {duration}")
    if duration > MAX_T_END:
        raise ParameterError("duration", f"a ramp's duration must be <= {MAX_T_END:g} s, got {duration:g}")
    if 2 * math.pi / min(start, stop) > duration:
        raise ParameterError(
            "ramp", f"a ramp must span a forcing period of its slowest w ({2 * math.pi / min(start, stop):.3g} s)"
        )
    return start, stop, duration


def ramp_omegas(start, stop, duration):
    """Forcing frequency of each period of a linear ramp from ``start`` to ``stop`` rad/s over
    ``duration`` s: period k runs at w(T_k), T_k its start time (a staircase of one step per
    period, which :func:`surrogate_driven` integrates)."""
    start, stop, duration = _check_ramp(start, stop, duration)
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
    flat parts of the period-1 branch, 45 um on its steep part (:mod:`impactosc.records.slow_sweep`).
    Keywords as :func:`surrogate_driven`; returns (record, truth)."""
    start, stop, duration = _check_ramp(start, stop, duration)
    _check_size(duration, options or SurrogateOptions(), periods=duration * max(start, stop) / (2 * math.pi))
    rec, truth = surrogate_driven(ramp_omegas(start, stop, duration), options, n_initial=n_initial, **kwargs)
    meta = dict(rec.meta, surrogate_ramp=f"{float(start):g} -> {float(stop):g} rad/s in {float(duration):g} s")
    return dataclasses.replace(rec, meta=meta, path="<surrogate ramp>"), truth
