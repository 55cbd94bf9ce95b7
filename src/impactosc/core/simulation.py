"""Python API of the core: run one scene and get its events (no Snakemake needed).

The numba core runs in chunks of a bounded number of steps, so long runs report progress
and memory stays bounded by the event arrays; the full integrator state is carried over
between chunks, so chunking changes nothing.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np

from impactosc.core import driver as core
from impactosc.core.layout import (
    C_ATTEMPTS,
    C_BY_MODE,
    C_DENSE,
    C_DIP,
    C_FALLBACK,
    C_NEWTON,
    C_REJECT,
    C_RHS,
    C_SLOW_STEPS,
    C_SLOW_TRANSIT,
    C_STEPS,
    C_STICK,
    C_STIFF,
    C_TRANSFORMED,
    DEFAULT_STEP_BUDGET,
    EVENT_NAMES,
    IMPACT,
    MODE_KEYS,
    MODE_NAMES,
    N_COUNT,
    RUNNING,
    S_FIELD,
    S_H,
    S_MODE,
    S_SLOW,
    S_STATUS,
    S_T,
    S_TSLOW,
    S_V,
    S_X,
    SLOW_FRICTION,
    SLOW_STIFF,
    STALLED,
    STATUS_NAMES,
    record_flags,
)
from impactosc.io.memory import shortfall
from impactosc.model.contact_laws import law_of
from impactosc.model.contact_laws.kernel import contact_onset
from impactosc.model.equations import FIELD_NAMES
from impactosc.model.noise import Noise
from impactosc.model.parameters import MAX_EXPONENT, P_B, P_CHI, P_CHI_PER, ModelParams, ParameterError, cut_velocity

ALL_EVENTS = EVENT_NAMES
DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12
#: Latest end time of a run, s. Why: the clock's rounding (2.2e-16 t) catches up with the steps
#: an impact needs. Measured on the chaotic scene (w = 40.86 rad/s, 30 s of it started at t0):
#: 19 k steps at t0 = 1e5 s, 31 k at 1e6, 413 k at 1e7, 5.1 M at 1e8, and at 1e9 the explicit
#: step underflows. 1e6 s (11.6 days of the rig) keeps the cost of a step that of early times.
MAX_T_END = 1e6
#: Largest |x0| (m) and |v0| (m/s). Why: the contact law raises the state to exponents up to
#: MAX_EXPONENT, which must stay inside double precision (1e30^10 = 1e300); measured, x0 = 1e100
#: divides by zero in the core, while 1e30 ends in a clean step-size underflow.
MAX_STATE = 10 ** (300 / MAX_EXPONENT)
#: Largest watchdog budget, step attempts per forcing period. Why: a stalled run spends it before
#: it stops; measured, 1e6 attempts take about 0.9 s, so 1e9 stops a stall within 15 min.
MAX_STEP_BUDGET = 1e9
#: Bytes a trajectory window takes per sample, up to its file: x, v and t (float64) and the
#: writer's buffers. Measured by the peak RSS of `impactosc simulate --window 0 100 DT`: 31.5 B
#: per sample more at DT = 1e-5 than at 1e-4.
WINDOW_BYTES_PER_SAMPLE = 32
SOLVER_NAME = "DOP853 (explicit, dense output) + Radau IIA-5 (sticking phases), event-split"


class StallError(RuntimeError):
    """The core stopped before the end of the run (watchdog or step-size underflow).

    The message names where: time, piece (vector field, variable, implicit or not), state
    and step size; ``state`` holds the same as a dict for programs.
    """

    def __init__(self, message: str, state: dict):
        super().__init__(message)
        self.state = state

    def __reduce__(self):
        """Rebuilt from its message and state: a worker process hands it back by pickling, and
        the default (the message alone) would not unpickle, which breaks the process pool."""
        return type(self), (str(self), dict(self.state))


def _stall_error(st, cnt, t_end: float, budget: float) -> StallError:
    status = int(st[S_STATUS])
    slow = int(st[S_SLOW])
    piece = FIELD_NAMES[int(st[S_FIELD])]
    if slow == SLOW_FRICTION:
        piece += ", implicit (friction band)"
    elif slow == SLOW_STIFF:
        piece += ", implicit (stiff creep)"
    else:
        piece += f", explicit in {MODE_NAMES[int(st[S_MODE])]}"
    state = dict(
        status=STATUS_NAMES[status],
        t=float(st[S_T]),
        t_end=t_end,
        piece=piece,
        x=float(st[S_X]),
        v=float(st[S_V]),
        step=float(st[S_H]),
        attempts=int(cnt[C_ATTEMPTS]),
    )
    why = STATUS_NAMES[status]
    if status == STALLED:
        why = f"stalled: {budget:.3g} step attempts without advancing one forcing period"
    return StallError(
        f"core {why} at t = {state['t']:.12g} s of {t_end:.6g} s in {piece}: "
        f"x = {state['x']:.9g} m, v = {state['v']:.6g} m/s, step {state['step']:.3g} "
        f"after {state['attempts']} step attempts",
        state,
    )


@dataclass(frozen=True)
class Window:
    """Trajectory samples at t = start + j*dt (absolute time, s) for start <= t <= stop."""

    start: float
    stop: float
    dt: float

    def __post_init__(self):
        for name in ("start", "stop", "dt"):
            if not math.isfinite(getattr(self, name)):
                raise ParameterError("window", f"window {name} must be finite")
        if self.dt <= 0:
            raise ParameterError("window", f"window dt must be > 0, got {self.dt}")
        if self.stop < self.start:
            raise ParameterError("window", f"window stop ({self.stop}) is before its start ({self.start})")

    @property
    def n(self) -> int:
        n = int(math.floor((self.stop - self.start) / self.dt)) + 1
        while n > 1 and self.start + (n - 1) * self.dt > self.stop:  # rounding at the end
            n -= 1
        return n


@dataclass
class SimulationResult:
    """Events with t >= transient, optional trajectory window, and run metadata."""

    events: dict  # name -> dict of arrays, e.g. events["impacts"]["t"]
    trajectory: dict | None
    attrs: dict
    final_state: np.ndarray = field(repr=False)
    #: the noise in the dynamics as drawn (impactosc.model.noise_realisation), None without noise
    realisation: object | None = field(default=None, repr=False)

    @property
    def impact_times(self) -> np.ndarray:
        return self.events["impacts"]["t"]


_COLUMNS = {
    "impacts": ("t", "v"),
    "penetrations": ("t", "h"),
    "near_misses": ("t", "gap"),
    "poincare": ("t", "x", "v"),
}


def _validate(omega, transient, duration, x0, v0, rtol, atol, window):
    """Refuse, before compiling or integrating, what the core cannot run: each error a
    :class:`ParameterError` naming the argument."""
    checks = {
        "omega": omega,
        "transient": transient,
        "duration": duration,
        "x0": x0,
        "v0": v0,
        "rtol": rtol,
        "atol": atol,
    }
    for name, value in checks.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(value):
            raise ParameterError(name, f"{name} must be a finite number, got {value!r}")
    if omega <= 0:
        raise ParameterError("omega", f"omega must be > 0 rad/s, got {omega}")
    if transient < 0:
        raise ParameterError("transient", f"transient must be >= 0 s, got {transient}")
    if duration <= 0:
        raise ParameterError("duration", f"duration must be > 0 s, got {duration}")
    if transient + duration > MAX_T_END:
        raise ParameterError(
            "t_end",
            f"transient + duration = {transient + duration:.6g} s is beyond the {MAX_T_END:g} s a run can reach "
            "at full cost per step (the clock's rounding catches up with the impacts' steps); split the run",
        )
    for name, value, unit in (("x0", x0, "m"), ("v0", v0, "m/s")):
        if abs(value) > MAX_STATE:
            raise ParameterError(name, f"|{name}| must be <= {MAX_STATE:g} {unit}, got {value:g}")
    if not 0 < rtol < 1:
        raise ParameterError("rtol", f"rtol must be in (0, 1), got {rtol}")
    if atol <= 0:
        raise ParameterError("atol", f"atol must be > 0, got {atol}")
    if window is not None:
        if window.start < 0 or window.stop > transient + duration:
            raise ParameterError(
                "window",
                f"window [{window.start}, {window.stop}] s must lie inside the run [0, {transient + duration}] s",
            )
        need = shortfall(WINDOW_BYTES_PER_SAMPLE * ((window.stop - window.start) / window.dt + 1))
        if need:
            raise ParameterError(
                "window",
                f"a window of {(window.stop - window.start) / window.dt + 1:.3g} samples {need}; "
                "take a coarser step or a shorter window",
            )


def check_step_budget(step_budget) -> None:
    """The watchdog's budget: at least 100 step attempts per forcing period, at most
    MAX_STEP_BUDGET, so that a stalled run stops within minutes."""
    if not 100 <= step_budget <= MAX_STEP_BUDGET:
        raise ParameterError(
            "step_budget",
            f"step_budget must be from 100 to {MAX_STEP_BUDGET:g} step attempts per forcing period, got {step_budget!r}",
        )


def warm_up() -> float:
    """Compile (or load from the on-disk cache) the core; returns the seconds it took."""
    t0 = time.perf_counter()
    simulate(0.1, 0.0, 1e-3, x0=-2e-3, record=ALL_EVENTS, window=Window(0.0, 1e-3, 1e-4), _timing_only=True)
    return time.perf_counter() - t0


def _start_contact(params: ModelParams, p, x0: float, v0: float, contact_v0) -> float:
    """The cut velocity a run starts with. A law that keeps its contact's onset velocity (a
    restitution law's damping comes from it) needs it for a run that starts inside a contact
    (``contact_v0``, the ``contact_v0`` attribute of the run that ended there). One that starts at
    the obstacle moving in starts that contact itself; one that starts at rest inside the obstacle
    (model BC's rest lies 2 mm past xI) is a contact without approach speed, undamped (chi = 0) as
    every touch at v0 = 0 is. Sets the contact's damping in `p`."""
    if not law_of(params.law).keeps_contact_state:
        return cut_velocity(p)
    if contact_v0 is None and ((x0 == params.xI and v0 > 0) or (x0 > params.xI and v0 == 0)):
        contact_v0 = v0  # an onset now, or a contact at rest
    if x0 > params.xI or contact_v0 is not None:
        if contact_v0 is None or not math.isfinite(contact_v0) or contact_v0 < 0:
            raise ParameterError(
                "contact_v0",
                f"a run that starts inside a contact (x0 > xI) of the {params.law} law needs that contact's onset "
                f"velocity, contact_v0 >= 0 m/s (a run's end state gives it as attrs['contact_v0']), got {contact_v0!r}",
            )
        return contact_onset(p, float(contact_v0), math.inf)
    return math.inf


def _end_contact_v0(params: ModelParams, p, x_end: float) -> float:
    """The onset velocity of the contact a run ends in, for a law that keeps it (nan otherwise):
    what a run continuing from the end state passes as ``contact_v0``."""
    if not law_of(params.law).keeps_contact_state or x_end <= params.xI:
        return math.nan
    if p[P_B] <= 0:  # a contact without approach speed (or e = 1: every v0 gives chi = 0)
        return 0.0
    return p[P_CHI] / (p[P_CHI_PER] * p[P_B])  # b = chi = P_CHI / (P_CHI_PER v0)


def start_of(state) -> dict:
    """simulate's start arguments (x0, v0, contact_v0) from a state (x, v) or (x, v, contact_v0),
    contact_v0 nan outside a restitution law's contact (:func:`end_state`): one run of a chain
    starts where the last one ended, inside a contact too."""
    carried = float(state[2]) if len(state) > 2 and math.isfinite(state[2]) else None
    return {"x0": float(state[0]), "v0": float(state[1]), "contact_v0": carried}


def end_state(result: SimulationResult) -> np.ndarray:
    """(x, v, contact_v0) at the end of a run, the start (:func:`start_of`) of the run that goes on
    from there: a restitution law's state inside a contact includes the contact's onset velocity."""
    st = result.final_state
    return np.array([st[S_X], st[S_V], result.attrs["contact_v0"]])


def simulate(
    omega: float,
    transient: float,
    duration: float,
    *,
    x0: float = 0.0,
    v0: float = 0.0,
    params: ModelParams | None = None,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    window: Window | None = None,
    record: Iterable[str] = ALL_EVENTS,
    chunk_steps: int = 200_000,
    step_budget: float = DEFAULT_STEP_BUDGET,
    progress: Callable[[float, float, int], None] | None = None,
    contact_v0: float | None = None,
    noise: Noise | None = None,
    _timing_only: bool = False,
) -> SimulationResult:
    """Integrate model BC from (x0, v0) at t = 0 to transient + duration.

    Only the events named in `record` (subset of impacts, penetrations, near_misses,
    poincare) with t >= transient are stored, plus the optional trajectory `window`.
    The core runs in calls of at most `chunk_steps` steps (the state carries over exactly,
    so this changes nothing but the memory held and the progress granularity);
    `progress(t, t_end, n_impacts)` is called after each.

    Never hangs: a run that spends `step_budget` step attempts without advancing one
    forcing period raises :class:`StallError` naming where it stuck (as does a step-size
    underflow); the default budget is ~10^4 times what the chaotic scene needs.

    The contact law is ``params.law`` (:mod:`impactosc.model.contact_laws`). A restitution law's
    contact remembers its onset velocity: a run that starts inside one takes it as
    `contact_v0` (a run that ends inside one states it as ``attrs["contact_v0"]``).

    `noise` adds noise in the dynamics (:class:`impactosc.model.noise.Noise`: the motor's speed
    jitter, a random force), drawn for its seed over the whole run and integrated as exactly as the
    noise-free model; without it, or with every rms 0, the run is the noise-free model bit for bit.
    The draws come back as ``result.realisation`` (written out by
    :func:`impactosc.model.noise_realisation.realisation_datasets`).
    """
    params = params or ModelParams()
    record = tuple(record)
    unknown = set(record) - set(ALL_EVENTS)
    if unknown:
        raise ValueError(f"unknown event kind(s) {sorted(unknown)}; choose from {list(ALL_EVENTS)}")
    _validate(omega, transient, duration, x0, v0, rtol, atol, window)
    check_step_budget(step_budget)
    flags = record_flags(record)

    p = params.as_array(float(omega))
    vcut = _start_contact(params, p, float(x0), float(v0), contact_v0)
    period = 2.0 * math.pi / omega
    t_end = float(transient) + float(duration)
    realisation = None
    if noise is not None and noise.active:
        from impactosc.model.noise_realisation import pack, realise  # SciPy's splines: only for noisy runs

        realisation = realise(noise, t_end)
        p = pack(p, realisation)
    st = core.initial_state(p, 0.0, float(x0), float(v0), period, vcut, float(step_budget))
    cnt = np.zeros(N_COUNT, dtype=np.int64)
    ev = np.empty((1024, 4))
    n_ev = 0
    if window is not None:
        win_x = np.full(window.n, np.nan)
        win_v = np.full(window.n, np.nan)
        win_t0, win_dt = float(window.start), float(window.dt)
    else:
        win_x = win_v = np.empty(0)
        win_t0, win_dt = 0.0, 1.0

    rs = core.run_settings(t_end, float(transient), float(rtol), float(atol), flags, period, win_t0, win_dt)
    wall = 0.0
    while st[S_T] < t_end:
        t0 = time.perf_counter()
        ev, n_ev = core.run(p, st, cnt, rs, ev, n_ev, win_x, win_v, int(chunk_steps))
        wall += time.perf_counter() - t0
        if st[S_STATUS] != RUNNING:
            raise _stall_error(st, cnt, t_end, step_budget)
        if progress is not None:
            n_imp = int(np.count_nonzero(ev[:n_ev, 0] == IMPACT))
            progress(float(st[S_T]), t_end, n_imp)

    ev = ev[:n_ev]
    events = {}
    for kind, name in enumerate(ALL_EVENTS):
        if name not in record:
            continue
        rows = ev[ev[:, 0] == kind]
        events[name] = {col: np.ascontiguousarray(rows[:, 1 + i]) for i, col in enumerate(_COLUMNS[name])}
    trajectory = None
    if window is not None:
        trajectory = {"t": win_t0 + win_dt * np.arange(window.n), "x": win_x, "v": win_v}

    attrs = {f"param_{k}": v for k, v in params.to_dict().items()}
    if noise is not None:
        attrs.update(noise.attrs())
    attrs["contact_v0"] = _end_contact_v0(params, p, float(st[S_X]))
    attrs.update(
        omega=float(omega),
        transient=float(transient),
        duration=float(duration),
        x0=float(x0),
        v0=float(v0),
        solver=SOLVER_NAME,
        rtol=float(rtol),
        atol=float(atol),
        n_steps=int(cnt[C_STEPS]),
        n_rejected=int(cnt[C_REJECT]),
        n_rhs=int(cnt[C_RHS]),
        n_implicit_steps=int(cnt[C_SLOW_STEPS]),
        n_stick=int(cnt[C_STICK]),
        n_slow_reversal=int(cnt[C_SLOW_TRANSIT]),
        time_implicit=float(st[S_TSLOW]),
        n_dense=int(cnt[C_DENSE]),
        n_dip_checks=int(cnt[C_DIP]),
        n_newton=int(cnt[C_NEWTON]),
        n_transformed_steps=int(cnt[C_TRANSFORMED]),
        n_fallback=int(cnt[C_FALLBACK]),
        n_stiff=int(cnt[C_STIFF]),
        n_attempts=int(cnt[C_ATTEMPTS]),
        **{f"n_attempts_{name}": int(cnt[C_BY_MODE + mode]) for mode, name in enumerate(MODE_KEYS)},
        step_budget=float(step_budget),
        wall_time=wall,
        recorded=",".join(record),
    )
    return SimulationResult(
        events=events, trajectory=trajectory, attrs=attrs, final_state=st.copy(), realisation=realisation
    )
