"""Noise in the dynamics: what a run's random forcing is (its intensities, correlation times and seed).

Why a module of its own: a rig's motor jitters and its cart feels random forces, and both enter the
model's right-hand side, unlike sensor noise, which only touches a record (:mod:`impactosc.records`).
Each noise is a smooth random process with a stated correlation time, so that every piece of a
trajectory stays an ODE the event-exact core integrates as it does without noise:

- ``motor``: the motor's phase is phi(t) = w t + theta(t), theta' = u an Ornstein-Uhlenbeck speed
  deviation (``rms`` in rad/s, correlation time ``tau`` in s); the unbalance then forces the cart
  with m0e (phi'^2 sin phi - phi'' cos phi) instead of m0e w^2 sin(w t);
- ``force``: a random force on the cart, an Ornstein-Uhlenbeck process (``rms`` in N, ``tau`` in s).

Each process is drawn exactly on a grid of spacing ``grid`` (default tau / 20) and interpolated by a
quintic spline (:mod:`impactosc.model.noise_realisation`). A model file, the workflow config and the
command line all name it as one block::

    noise: {seed: 0, motor: {rms: 0.5, tau: 0.2}, force: {rms: 0.05, tau: 0.05}}

An rms of 0 (or no block) is the noise-free model, bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from impactosc.io.names import closest_name, shown
from impactosc.model.parameters import ParameterError

#: The noises, each (unit of its rms, dataset of its samples in a run file's group ``noise``, meaning).
PROCESSES = {
    "motor": (
        "rad/s",
        "motor_speed",
        "speed deviation of the motor (its phase phi = w t + theta, theta' an OU process)",
    ),
    "force": ("N", "cart_force", "random force on the cart (an OU process)"),
}
#: Keys of one process, (unit, meaning).
PROCESS_KEYS = {
    "rms": ("see the process", "standard deviation of the stationary process"),
    "tau": ("s", "correlation time (the autocorrelation falls as exp(-|lag| / tau))"),
    "grid": ("s", "spacing of the exact draws the spline interpolates; null: tau / GRID_PER_TAU"),
}
#: Draws per correlation time by default. Why 20: the spline between exact draws must not change the
#: process; measured (tests/test_noise.py), its rms and correlation time stay within 1 % of the OU's.
GRID_PER_TAU = 20
#: Fewest draws per correlation time a grid may have: a coarser grid would show the spline, not the process.
MIN_GRID_PER_TAU = 5


@dataclass(frozen=True)
class NoiseProcess:
    """One Ornstein-Uhlenbeck process: rms, correlation time tau (s), grid spacing (s; None: tau / 20)."""

    rms: float
    tau: float
    grid: float | None = None

    def check(self, name: str) -> None:
        """Refuse what cannot be realised, naming the key (e.g. ``noise.motor.tau``)."""
        for key in ("rms", "tau", "grid"):
            value = getattr(self, key)
            if value is None and key == "grid":
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ParameterError(
                    f"noise.{name}.{key}", f"noise.{name}.{key} must be a finite number, got {shown(value)}"
                )
        if self.rms < 0:
            raise ParameterError(f"noise.{name}.rms", f"noise.{name}.rms must be >= 0, got {self.rms:g}")
        if self.tau <= 0:
            raise ParameterError(
                f"noise.{name}.tau", f"noise.{name}.tau (correlation time) must be > 0 s, got {self.tau:g}"
            )
        if self.grid is not None and not 0 < self.grid <= self.tau / MIN_GRID_PER_TAU:
            raise ParameterError(
                f"noise.{name}.grid",
                f"noise.{name}.grid must be > 0 and at most tau / {MIN_GRID_PER_TAU} = {self.tau / MIN_GRID_PER_TAU:g} s "
                f"(the correlation time must span several draws), got {self.grid:g}",
            )

    @property
    def spacing(self) -> float:
        return self.grid if self.grid is not None else self.tau / GRID_PER_TAU


@dataclass(frozen=True)
class Noise:
    """A run's noise in the dynamics: its seed and each process (None: absent)."""

    seed: int = 0
    motor: NoiseProcess | None = None
    force: NoiseProcess | None = None

    def __post_init__(self):
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError("noise.seed", f"noise.seed must be an integer >= 0, got {shown(self.seed)}")
        for name in PROCESSES:
            process = getattr(self, name)
            if process is not None:
                process.check(name)

    @property
    def active(self) -> bool:
        """Does any process have an rms > 0? If not, the run is the noise-free model bit for bit."""
        return any(p is not None and p.rms > 0 for p in (self.motor, self.force))

    def processes(self) -> dict[str, NoiseProcess]:
        """The processes with rms > 0, by name, in the order of PROCESSES."""
        return {name: p for name in PROCESSES if (p := getattr(self, name)) is not None and p.rms > 0}

    def to_dict(self) -> dict:
        out: dict = {"seed": self.seed}
        for name in PROCESSES:
            p = getattr(self, name)
            if p is not None:
                out[name] = {"rms": p.rms, "tau": p.tau, "grid": p.grid}
        return out

    def attrs(self) -> dict:
        """Flat attributes a run file records (``noise_seed``, ``noise_motor_rms``, ...; grid as used)."""
        out = {"noise_seed": self.seed}
        for name in PROCESSES:
            p = getattr(self, name)
            out[f"noise_{name}_rms"] = 0.0 if p is None else float(p.rms)
            out[f"noise_{name}_tau"] = math.nan if p is None else float(p.tau)
            out[f"noise_{name}_grid"] = math.nan if p is None else float(p.spacing)
        return out

    @classmethod
    def from_dict(cls, block, where: str = "noise") -> Noise:
        """The noise a ``noise:`` block of a model file or config states; unknown keys are refused with
        the closest valid one. None or an empty block: no noise."""
        if block is None:
            return cls()
        if not isinstance(block, dict):
            raise ParameterError(where, f"{where} must be a mapping (seed, motor, force), got {shown(block)}")
        _refuse_unknown(block, ("seed", *PROCESSES), where)
        parts = {}
        for name in PROCESSES:
            sub = block.get(name)
            if sub is None:
                continue
            if not isinstance(sub, dict):
                raise ParameterError(
                    f"{where}.{name}", f"{where}.{name} must be a mapping (rms, tau, grid), got {shown(sub)}"
                )
            _refuse_unknown(sub, PROCESS_KEYS, f"{where}.{name}")
            for key in ("rms", "tau"):
                if key not in sub:
                    raise ParameterError(
                        f"{where}.{name}.{key}", f"{where}.{name} needs {key} ({PROCESS_KEYS[key][1]})"
                    )
            parts[name] = NoiseProcess(rms=sub["rms"], tau=sub["tau"], grid=sub.get("grid"))
        return cls(seed=block.get("seed", 0), **parts)

    @classmethod
    def from_attrs(cls, attrs) -> Noise:
        """The noise a run file's attributes record (:meth:`attrs`); none recorded: no noise."""
        if "noise_seed" not in attrs:
            return cls()
        parts = {}
        for name in PROCESSES:
            rms = float(attrs.get(f"noise_{name}_rms", 0.0))
            if rms > 0:
                parts[name] = NoiseProcess(rms, float(attrs[f"noise_{name}_tau"]), float(attrs[f"noise_{name}_grid"]))
        return cls(seed=int(attrs["noise_seed"]), **parts)


def _refuse_unknown(block: dict, names, where: str) -> None:
    for key in block:
        if key not in names:
            near = closest_name(key, names)
            hint = f" (did you mean {near!r}?)" if near else ""
            raise ParameterError(where, f"unknown key {where}.{key}{hint}; known: {', '.join(names)}")
