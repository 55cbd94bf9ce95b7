"""Parameter sweeps by continuation: follow one attractor along a grid of forcing frequencies.

Why continuation: a bifurcation diagram shows *the attractor the system is on*, and with
coexisting attractors (hysteresis) that depends on the history. As in the paper (Figs 2, 3b)
and on the rig, the state at the end of one w starts the next: every w runs ``n_transient``
forcing periods (discarded) and then ``n_record`` periods (recorded), restarting at t = 0
(phi = 0) from the previous end state. The previous run ends on a whole number of its own
forcing periods, i.e. on a Poincare time phi = 2 pi i, so the restart at phi = 0 is exact.

Chunked sweeps (one job per chunk) are in :mod:`impactosc.dynamics.sweep_chunks`.

No Snakemake here: the workflow scripts and the tests call these functions directly.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from impactosc.core.simulation import DEFAULT_ATOL, DEFAULT_RTOL, MAX_STEP_BUDGET, StallError, simulate
from impactosc.io.files import atomic_write, check_writable, stamp_h5
from impactosc.model.parameters import ModelParams, ParameterError

__all__ = [
    "SweepSettings",
    "SweepResult",
    "omega_grid",
    "regular_grid",
    "branch_grid",
    "continuation",
    "save_sweep",
    "load_sweep",
    "MAP_PARAMETERS",
    "parameter_rows",
]


@dataclass(frozen=True)
class SweepSettings:
    """Per-w lengths (in forcing periods), model, tolerances, and the start of the sweep.

    n_transient / n_record: forcing periods discarded / recorded at every w.
    n_initial: transient periods at the first w of a sweep, which starts from (x0, v0)
    rather than from an attractor, so it usually needs longer than n_transient.
    """

    n_transient: int = 150
    n_record: int = 100
    n_initial: int = 1000
    x0: float = 0.0
    v0: float = 0.0
    params: ModelParams = field(default_factory=ModelParams)
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL
    max_steps_per_period: int = 1000

    def __post_init__(self):
        for name in ("n_transient", "n_record", "n_initial", "max_steps_per_period"):
            value = getattr(self, name)
            if not isinstance(value, (int, np.integer)) or isinstance(value, bool):
                raise ValueError(f"{name} must be an integer number of forcing periods, got {value!r}")
        if self.n_transient < 0 or self.n_initial < 0:
            raise ValueError(f"n_transient and n_initial must be >= 0, got {self.n_transient}, {self.n_initial}")
        if self.n_record < 1:
            raise ValueError(f"n_record must be >= 1 forcing period, got {self.n_record}")
        if self.max_steps_per_period < 100:
            raise ValueError(f"max_steps_per_period must be >= 100, got {self.max_steps_per_period}")
        for name in ("x0", "v0"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {getattr(self, name)}")

    def to_attrs(self) -> dict:
        """Flat attributes for the HDF5 file (reproducibility)."""
        out = {
            k: getattr(self, k)
            for k in ("n_transient", "n_record", "n_initial", "x0", "v0", "rtol", "atol", "max_steps_per_period")
        }
        out.update({f"param_{k}": v for k, v in self.params.to_dict().items()})
        return out

    @classmethod
    def from_config(cls, per_w: dict, model: dict, solver: dict, **overrides) -> SweepSettings:
        """Settings from the workflow config sections (bifurcation.per_w, model, solver)."""
        kw = {
            k: per_w[k]
            for k in ("n_transient", "n_record", "n_initial", "x0", "v0", "max_steps_per_period")
            if k in per_w
        }
        kw.update(overrides)
        return cls(params=ModelParams(**model), rtol=solver["rtol"], atol=solver["atol"], **kw)

    @classmethod
    def from_attrs(cls, attrs) -> SweepSettings:
        params = ModelParams.from_attrs(attrs)
        return cls(
            n_transient=int(attrs["n_transient"]),
            n_record=int(attrs["n_record"]),
            n_initial=int(attrs["n_initial"]),
            x0=float(attrs["x0"]),
            v0=float(attrs["v0"]),
            params=params,
            rtol=float(attrs["rtol"]),
            atol=float(attrs["atol"]),
            max_steps_per_period=int(attrs["max_steps_per_period"]),
        )


# Per-w arrays of a SweepResult (all shape (n,) except the Poincare arrays (n, n_record)).
_PER_W = (
    "omega", "x_start", "v_start", "x_end", "v_end", "min_gap", "n_steps", "wall_time", "cpu_time", "status",
    "contact_v0_end",
)  # fmt: skip

# status of each w: the run finished, or it was abandoned (then its Poincare points are NaN,
# it has no impacts, and the next w continues from the state this one started from).
OK, STALLED, CORE_ERROR = 0, 1, 2
STATUS_NAMES = {OK: "ok", STALLED: "step budget exceeded", CORE_ERROR: "core error"}


class _Stalled(Exception):
    """The core used more steps than the per-w budget allows (a stuck integration)."""


@dataclass
class SweepResult:
    """Everything a bifurcation diagram needs, per w of the sweep, in sweep order.

    poincare_x, poincare_v: (n, n_record) section points at phi = 2 pi i (m, m/s).
    impact_t, impact_v: impact onsets of all w, concatenated; those of w number i are
    ``impact_t[impact_offsets[i]:impact_offsets[i+1]]``, times measured from the start of
    the recorded interval (s), so they lie in [0, n_record * 2 pi / w).
    min_gap: smallest free-flight gap xI - x at a local maximum of x (near miss) in the
    recorded interval (m); NaN if there is none. A gap -> 0 signals grazing.
    x_start, v_start: state each w started from; x_end, v_end: its end state, and
    contact_v0_end the onset velocity of a restitution contact it lies in (NaN outside one; what
    a run continuing from there passes as contact_v0).
    status: OK, or STALLED / CORE_ERROR for a w whose run was abandoned (see continuation).
    wall_time / cpu_time: seconds of wall clock / of this process's CPU per w (the CPU time
    does not grow when other processes share the core, so it measures the cost per core).
    """

    omega: np.ndarray
    poincare_x: np.ndarray
    poincare_v: np.ndarray
    impact_t: np.ndarray
    impact_v: np.ndarray
    impact_offsets: np.ndarray
    min_gap: np.ndarray
    x_start: np.ndarray
    v_start: np.ndarray
    x_end: np.ndarray
    v_end: np.ndarray
    n_steps: np.ndarray
    wall_time: np.ndarray
    cpu_time: np.ndarray
    status: np.ndarray
    settings: SweepSettings
    contact_v0_end: np.ndarray | None = None  # NaN where absent (files written before it)

    def __post_init__(self):
        if self.contact_v0_end is None:
            self.contact_v0_end = np.full(self.omega.size, np.nan)

    def __len__(self) -> int:
        return int(self.omega.size)

    def impacts(self, i: int) -> np.ndarray:
        """Impact onset times at the i-th w (s from the start of its recorded interval)."""
        return self.impact_t[self.impact_offsets[i] : self.impact_offsets[i + 1]]

    def isi(self, i: int) -> np.ndarray:
        """Inter-impact intervals S_j at the i-th w (s)."""
        return np.diff(self.impacts(i))

    def isi_points(self) -> tuple[np.ndarray, np.ndarray]:
        """(w, S) pairs of every ISI of the sweep, for the ISI diagram (Fig 3b)."""
        counts = np.maximum(np.diff(self.impact_offsets) - 1, 0)
        s = np.concatenate([self.isi(i) for i in range(len(self))]) if len(self) else np.empty(0)
        return np.repeat(self.omega, counts), s

    def poincare_points(self) -> tuple[np.ndarray, np.ndarray]:
        """(w, x) pairs of every Poincare point of the sweep, for the Poincare diagram (Fig 2)."""
        n_rec = self.poincare_x.shape[1]
        w, x = np.repeat(self.omega, n_rec), self.poincare_x.ravel()
        ok = np.isfinite(x)  # abandoned w values have no points
        return w[ok], x[ok]

    def subset(self, start: int, stop: int) -> SweepResult:
        """The w values start..stop-1 (contiguous), e.g. dropping a chunk's warm-up."""
        if not 0 <= start <= stop <= len(self):
            raise ValueError(f"subset [{start}, {stop}) outside the sweep of {len(self)} w values")
        lo, hi = self.impact_offsets[start], self.impact_offsets[stop]
        kw = {k: getattr(self, k)[start:stop].copy() for k in _PER_W}
        return SweepResult(
            poincare_x=self.poincare_x[start:stop].copy(),
            poincare_v=self.poincare_v[start:stop].copy(),
            impact_t=self.impact_t[lo:hi].copy(),
            impact_v=self.impact_v[lo:hi].copy(),
            impact_offsets=self.impact_offsets[start : stop + 1] - lo,
            settings=self.settings,
            **kw,
        )

    @property
    def steps_per_second(self) -> float:
        return float(self.n_steps.sum() / max(self.wall_time.sum(), 1e-300))


def omega_grid(start: float, stop: float, n: int) -> np.ndarray:
    """n equally spaced w from start to stop inclusive; start > stop gives a decreasing sweep."""
    if not (math.isfinite(start) and math.isfinite(stop)) or start <= 0 or stop <= 0:
        raise ValueError(f"omega start and stop must be finite and > 0 rad/s, got {start}, {stop}")
    if start == stop:
        raise ValueError(f"omega start and stop must differ, both are {start}")
    if not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"a sweep needs n >= 2 w values, got {n!r}")
    return np.linspace(float(start), float(stop), int(n))


def _check_omegas(omegas) -> np.ndarray:
    w = np.asarray(omegas, dtype=float)
    if w.ndim != 1 or w.size < 1:
        raise ValueError("omegas must be a non-empty 1-D sequence of rad/s values")
    if not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise ValueError("omegas must be finite and > 0 rad/s")
    if w.size > 1:
        d = np.diff(w)
        if not (np.all(d > 0) or np.all(d < 0)):
            raise ValueError("omegas must be strictly monotone (a continuation follows w in one direction)")
    return w


_CHUNK_STEPS = 20_000  # core steps between budget checks
_STALL_PACE = 20  # the core's watchdog: this many times the per-period budget without a period of progress


def _run_one(om: float, n_tr: int, x: float, v: float, s: SweepSettings, contact_v0=None):
    """One w: n_tr periods discarded, n_record recorded, within the step budget."""
    period = 2.0 * math.pi / om
    budget = s.max_steps_per_period * (n_tr + s.n_record)
    # Two limits: the total budget of the w (checked here between chunks), and the pace,
    # which the core's own watchdog enforces: a run that takes STALL_PACE times the
    # per-period budget (20000 steps by default) without advancing one forcing period
    # raises StallError (a stuck integration creeps ~1e-8 periods per 1e4 steps).
    state = {"calls": 0}

    def guard(t, t_end, n_imp):
        state["calls"] += 1
        if t < t_end and state["calls"] * _CHUNK_STEPS > budget:
            raise _Stalled(
                f"more than {budget} steps for {n_tr + s.n_record} periods, stuck at t = {t:.9g} s "
                f"of {t_end:.9g} s (start x0 = {x!r}, v0 = {v!r})"
            )

    # Record from half a period before the first section time so that rounding of
    # n_tr * period can never drop the Poincare point at phi = 2 pi n_tr.
    transient = max((n_tr - 0.5) * period, 0.0)
    duration = (n_tr + s.n_record) * period - transient
    return simulate(
        om,
        transient,
        duration,
        x0=x,
        v0=v,
        contact_v0=contact_v0,
        params=s.params,
        rtol=s.rtol,
        atol=s.atol,
        record=("impacts", "near_misses", "poincare"),
        chunk_steps=_CHUNK_STEPS,
        progress=guard,
        # the watchdog within the core's bounds (a huge per-period budget: the sweep's own check decides)
        step_budget=min(MAX_STEP_BUDGET, max(100.0, _STALL_PACE * s.max_steps_per_period)),
    )


def continuation(
    omegas: Sequence[float],
    settings: SweepSettings,
    *,
    x0: float | None = None,
    v0: float | None = None,
    first_transient: int | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    on_failure: Callable[[int, float, str], None] | None = None,
    contact_v0: float | None = None,
) -> SweepResult:
    """Follow the attractor along `omegas` (in the given order), one simulation per w.

    The first w starts from (x0, v0) (default: settings.x0, settings.v0; inside a restitution
    contact with its onset velocity `contact_v0`, a sweep's contact_v0_end) and discards
    `first_transient` periods (default settings.n_initial); every later w starts from the
    previous end state and discards settings.n_transient periods. Then n_record periods
    are recorded: Poincare points at the n_record section times, impacts, near misses.
    A w whose run exceeds settings.max_steps_per_period steps per forcing period on average
    or raises in the core is abandoned (status STALLED / CORE_ERROR, `on_failure(i, w,
    message)` is called) and the next w continues from the state it started from.
    `progress(i, n, w)` is called after each w.
    """
    w = _check_omegas(omegas)
    s = settings
    x = s.x0 if x0 is None else float(x0)
    v = s.v0 if v0 is None else float(v0)
    if not (math.isfinite(x) and math.isfinite(v)):
        raise ValueError(f"start state must be finite, got x0={x}, v0={v}")
    n, n_rec = w.size, s.n_record
    px = np.empty((n, n_rec))
    pv = np.empty((n, n_rec))
    per_w = {k: np.empty(n) for k in _PER_W}
    per_w["n_steps"] = np.empty(n, dtype=np.int64)
    per_w["status"] = np.empty(n, dtype=np.int64)
    imp_t, imp_v = [np.empty(0)], [np.empty(0)]
    offsets = np.zeros(n + 1, dtype=np.int64)
    n_tr = s.n_initial if first_transient is None else int(first_transient)
    # a restitution law's contact the current state lies in: its onset velocity (NaN: none)
    contact_v0 = None if contact_v0 is None or not math.isfinite(contact_v0) else float(contact_v0)
    for i, om in enumerate(w):
        period = 2.0 * math.pi / om
        t0, c0 = time.perf_counter(), time.process_time()
        try:
            res = _run_one(om, n_tr, x, v, s, contact_v0)
        except (_Stalled, RuntimeError, ParameterError) as exc:
            # A stuck integration must not stop (or hang) a 1000-point sweep: the w is
            # marked, left empty, and the continuation goes on from the last good state.
            status = STALLED if isinstance(exc, (_Stalled, StallError)) else CORE_ERROR
            per_w["status"][i] = status
            px[i] = pv[i] = np.nan
            per_w["min_gap"][i] = np.nan
            per_w["n_steps"][i] = -1
            if on_failure is not None:
                on_failure(i, float(om), f"{STATUS_NAMES[status]}: {exc}")
        else:
            per_w["status"][i] = OK
            t_rec = n_tr * period
            pt = res.events["poincare"]
            sec = np.rint(pt["t"] / period).astype(np.int64) - n_tr
            keep = (sec >= 0) & (sec < n_rec)
            x_sec, v_sec = np.full(n_rec, np.nan), np.full(n_rec, np.nan)
            x_sec[sec[keep]], v_sec[sec[keep]] = pt["x"][keep], pt["v"][keep]
            if n_tr == 0:  # the run starts on the section phi = 0: its first point is the start state
                x_sec[0], v_sec[0] = x, v
            if np.isnan(x_sec).any():  # cannot happen unless the core drops a section time
                raise RuntimeError(f"w = {om}: missing Poincare points {np.flatnonzero(np.isnan(x_sec))}")
            px[i], pv[i] = x_sec, v_sec
            it = res.events["impacts"]["t"]
            sel = it >= t_rec - 1e-9 * period
            imp_t.append(it[sel] - t_rec)
            imp_v.append(res.events["impacts"]["v"][sel])
            offsets[i + 1] = int(sel.sum())
            nm = res.events["near_misses"]
            gaps = nm["gap"][nm["t"] >= t_rec - 1e-9 * period]
            per_w["min_gap"][i] = gaps.min() if gaps.size else np.nan
            per_w["n_steps"][i] = res.attrs["n_steps"]
        per_w["omega"][i] = om
        per_w["x_start"][i], per_w["v_start"][i] = x, v
        if per_w["status"][i] == OK:
            x, v = float(res.final_state[1]), float(res.final_state[2])
            contact_v0 = res.attrs["contact_v0"] if math.isfinite(res.attrs["contact_v0"]) else None
            n_tr = s.n_transient
        per_w["x_end"][i], per_w["v_end"][i] = x, v
        per_w["contact_v0_end"][i] = math.nan if contact_v0 is None else contact_v0
        per_w["wall_time"][i] = time.perf_counter() - t0
        per_w["cpu_time"][i] = time.process_time() - c0
        if progress is not None:
            progress(i, n, float(om))
    offsets = np.cumsum(offsets)
    return SweepResult(
        poincare_x=px,
        poincare_v=pv,
        impact_t=np.concatenate(imp_t),
        impact_v=np.concatenate(imp_v),
        impact_offsets=offsets,
        settings=s,
        **per_w,
    )


# ------------------------------------------------------------------ chunking


# ------------------------------------------------------------------ files

_ARRAYS = ("poincare_x", "poincare_v", "impact_t", "impact_v", "impact_offsets", *_PER_W)


def save_sweep(path, result: SweepResult, *, sources=None, **attrs) -> Path:
    """Write a sweep to HDF5 atomically (temporary name, then rename); extra attrs are stored
    too, and the provenance of :func:`impactosc.io.files.stamp_h5` (`sources`: input files)."""
    path = check_writable(path)
    with atomic_write(path) as tmp, h5py.File(tmp, "w") as f:
        for name in _ARRAYS:
            f.create_dataset(name, data=getattr(result, name), compression="gzip", shuffle=True)
        for key, value in {**result.settings.to_attrs(), **attrs}.items():
            f.attrs[key] = value
        stamp_h5(f, sources=sources)
    return path


def load_sweep(path) -> tuple[SweepResult, dict]:
    """(result, attrs) of a file written by save_sweep."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"sweep file {path} does not exist")
    with h5py.File(path, "r") as f:
        arrays = {name: f[name][()] for name in _ARRAYS if name in f}
        attrs = dict(f.attrs)
    # files written before the per-w status existed: every w there finished
    arrays.setdefault("status", np.zeros(arrays["omega"].size, dtype=np.int64))
    arrays.setdefault("cpu_time", np.full(arrays["omega"].size, np.nan))
    attrs.setdefault("max_steps_per_period", SweepSettings.max_steps_per_period)
    return SweepResult(settings=SweepSettings.from_attrs(attrs), **arrays), attrs


# ------------------------------------------------------------------ 2-D maps

MAP_PARAMETERS = ("xI", "m0e")  # obstacle position (m), forcing amplitude m0 e (kg m)


def parameter_rows(omegas, settings: SweepSettings, parameter: str, values, progress=None):
    """One continuation in w per value of a model parameter: the rows of a 2-D map.

    Yields (value, SweepResult). Rows are independent (each starts from settings.x0, v0
    at its first w), so a map splits into jobs by rows without any seeding.
    """
    if parameter not in MAP_PARAMETERS:
        raise ValueError(f"map parameter must be one of {MAP_PARAMETERS}, got {parameter!r}")
    vals = np.asarray(values, dtype=float)
    if vals.ndim != 1 or vals.size == 0 or not np.all(np.isfinite(vals)):
        raise ValueError("map parameter values must be a non-empty 1-D sequence of finite numbers")
    w = _check_omegas(omegas)
    for k, value in enumerate(vals):
        row_settings = dataclasses.replace(
            settings, params=dataclasses.replace(settings.params, **{parameter: float(value)})
        )
        yield float(value), continuation(w, row_settings)
        if progress is not None:
            progress(k, vals.size, float(value))


def branch_grid(start: float, fine_from: float, stop: float, coarse_step: float, fine_step: float) -> np.ndarray:
    """Decreasing w grid: start, start - coarse_step, ... (> fine_from), then fine_from to stop by fine_step.

    Why: the paper follows the attractor down from w = 40.86; only the neighbourhood of
    the grazing needs fine steps. Grid points are start - i*step rounded to 1e-9 rad/s, so
    round values such as 23.05 and 23.03 are hit exactly when they lie on the fine grid.
    """
    vals = {"start": start, "fine_from": fine_from, "stop": stop, "coarse_step": coarse_step, "fine_step": fine_step}
    for name, value in vals.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if not start >= fine_from > stop:
        raise ValueError(f"need start >= fine_from > stop (a decreasing branch), got {start}, {fine_from}, {stop}")
    n_c = int(math.floor((start - fine_from) / coarse_step * (1 + 1e-12)))
    coarse = np.round(start - coarse_step * np.arange(n_c + 1), 9)
    coarse = coarse[coarse > fine_from + 1e-9]
    n_f = int(math.floor((fine_from - stop) / fine_step * (1 + 1e-12)))
    fine = np.round(fine_from - fine_step * np.arange(n_f + 1), 9)
    return np.concatenate([coarse, fine])


def regular_grid(start: float, stop: float, step: float) -> np.ndarray:
    """start, start +/- step, ... up to stop inclusive, rounded to 1e-9 (hits round values exactly)."""
    for name, value in (("start", start), ("stop", stop), ("step", step)):
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    n = int(math.floor(abs(stop - start) / step * (1 + 1e-12)))
    return np.round(start + math.copysign(step, stop - start) * np.arange(n + 1), 9)
