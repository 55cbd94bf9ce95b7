"""The timing rounds of the chaotic-scene benchmark: any solver as a contestant, its runs timed
round-robin with the others, and its row.

Why a module: the core (core_speed.py) and the compiled peers (peers.py) are timed in the same
rounds, so that a change in the machine's load spreads over all rows instead of favouring
some; this is what they share.

The scene: w = 40.86 rad/s, model BC defaults, rest at t = 0 (x = v = 0), 500 s = 100 s
transient + 400 s. Impacts are the upward crossings of x = xI. Per solver and rtol
(:func:`measure_contestants`):

  * wall time of the 500 s run: median of `repeats` runs, taken round-robin over the rows,
    compilation excluded (each contestant compiles, and makes one short run, before any
    timing);
  * accepted steps of that run and steps per forcing period (period 2 pi / w);
  * impacts in 100-500 s and ``on_attractor`` (below);
  * impact-time error over the first 1.5 s (a separate run, before chaos amplifies
    differences): max |t - t_ref| against SciPy DOP853 split at contacts
    (integration.reference) at rtol 1e-13 / atol 1e-15 (:func:`reference_times`); inf when
    the counts differ.

On the attractor: the chaotic attractor has about 2900 impacts in 100-500 s. A row is on the
attractor when its run reached 500 s and its count is within ATTRACTOR_TOLERANCE (10 %) of
the count of the project's core at rtol 1e-10 / atol 1e-12 on the same scene (computed by
:func:`reference_impact_count`; 2898 when written). Chaos makes two accurate runs differ in
their counts by a few per cent at most (2878-2914 measured); a run that settles on another
orbit differs by tens of per cent. A run that stops early is not on the attractor either: its
row gives the time it reached, its count and steps up to there, and the solver's message.
The 1177 impacts of CyRK DOP853 at rtol 1e-12 are such a stop, not another orbit: at
t = 263.8 s, at the velocity reversal inside a contact (x - xI = 1.8e-4 m, v = -2e-11 m/s),
where |v|^n3 makes the contact force's slope in v infinite, its step size underflows
(Vern7 at rtol 1e-12 likewise, at t = 262.3 s).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from impactosc_bench.scene import DURATION, ERR_HORIZON, OMEGA, TRANSIENT, impact_error

__all__ = [
    "PeerRun",
    "Contestant",
    "measure_contestants",
    "serpentine",
    "on_attractor",
    "reference_impact_count",
    "reference_times",
    "format_table",
]

T_END = TRANSIENT + DURATION
PERIOD = 2 * math.pi / OMEGA
REF_RTOL, REF_ATOL = 1e-13, 1e-15
CORE_RTOL, CORE_ATOL = 1e-10, 1e-12  # the core's run that defines the attractor's impact count
ATTRACTOR_TOLERANCE = 0.10


@dataclass
class PeerRun:
    """One integration by a peer: wall time, accepted steps, impact times, final state, how it ended."""

    wall_time: float
    steps: int
    impacts_t: np.ndarray
    t_reached: float  # where it stopped: the requested end unless it failed
    state_end: np.ndarray  # (x, v) there
    success: bool
    message: str
    extra: dict = dataclasses.field(default_factory=dict)  # solver-specific counters for the row (e.g. RHS calls)


def reference_impact_count(rtol: float = CORE_RTOL, atol: float = CORE_ATOL) -> int:
    """Impacts in 100-500 s of the project's core on the scene: the attractor's count."""
    from impactosc.core.simulation import simulate

    res = simulate(OMEGA, TRANSIENT, DURATION, rtol=rtol, atol=atol, record=("impacts",))
    return len(res.events["impacts"]["t"])


def on_attractor(n_impacts: float, reference: float, tolerance: float = ATTRACTOR_TOLERANCE) -> bool:
    """Whether an impact count in 100-500 s is within `tolerance` (relative) of the attractor's."""
    return bool(abs(n_impacts - reference) <= tolerance * reference)


def _row(solver: str, kind: str, rtol: float, atol: float, runs: list[PeerRun], **extra) -> dict:
    # The runs are deterministic: the repeats differ in wall time only.
    walls = [r.wall_time for r in runs]
    last = runs[-1]
    status = "ok" if last.success else f"stopped at t = {last.t_reached:.6g} s: {last.message}"
    return dict(
        solver=solver,
        kind=kind,
        rtol=rtol,
        atol=atol,
        wall_time=float(np.median(walls)),
        wall_time_min=min(walls),
        repeats=len(runs),
        t_reached=last.t_reached,
        steps=last.steps,
        steps_per_period=last.steps / (last.t_reached / PERIOD),
        status=status,
        **last.extra,
        **extra,
    )


@dataclass
class Contestant:
    """One row of the scene's table: a timed 500 s run and, for a scene row, the 1.5 s run of its error.

    kind "scene" (model BC with contact: error, impacts, on_attractor) or "floor" (free flight).
    `run` and `short` return a PeerRun; `short` runs from rest to ERR_HORIZON with impacts.
    """

    solver: str
    kind: str
    rtol: float
    atol: float
    run: Callable[[], PeerRun]
    short: Callable[[], PeerRun] | None = None


def serpentine(items: list, round_index: int) -> list:
    """The order of one timing round: forward in even rounds, backward in odd ones, so that
    every item's mean position (and its share of a drift in the machine's load) is alike."""
    return list(items) if round_index % 2 == 0 else list(reversed(items))


def measure_contestants(
    contestants: list[Contestant], repeats: int, *, reference_impacts: int, ref_times: np.ndarray, log=print
) -> list[dict]:
    """Rows of the contestants: errors first (untimed), then `repeats` timing rounds in which
    every contestant runs once (serpentine order), so that a change in the machine's load
    spreads over all rows instead of favouring some; wall_time is the median of the rounds."""
    if int(repeats) < 1:
        raise ValueError(f"repeats must be >= 1, got {repeats}")
    errors = {}
    for i, c in enumerate(contestants):
        if c.short is not None:
            short = c.short()
            errors[i] = impact_error(short.impacts_t, ref_times) if short.success else math.inf
    runs = {i: [] for i in range(len(contestants))}
    for k in range(int(repeats)):
        log(f"round {k + 1} of {repeats}: {len(contestants)} runs of {T_END:g} s")
        for i in serpentine(range(len(contestants)), k):
            runs[i].append(contestants[i].run())
    rows = []
    for i, c in enumerate(contestants):
        done = runs[i]
        if c.kind == "scene":
            n = int(np.count_nonzero(done[-1].impacts_t >= TRANSIENT))
            rows.append(
                _row(
                    c.solver,
                    c.kind,
                    c.rtol,
                    c.atol,
                    done,
                    impact_time_error_1p5s=errors[i],
                    n_impacts=n,
                    on_attractor=done[-1].success and on_attractor(n, reference_impacts),
                )
            )
        else:
            rows.append(_row(c.solver, c.kind, c.rtol, c.atol, done))
        log(_line(rows[-1]))
    return rows


def reference_times() -> np.ndarray:
    """Impact times over the first ERR_HORIZON s from rest: SciPy DOP853 split at contacts at rtol 1e-13."""
    from impactosc_bench.scipy_reference import solve_reference

    return solve_reference(OMEGA, ERR_HORIZON, rtol=REF_RTOL, atol=REF_ATOL)["impacts_t"]


# --- output ---------------------------------------------------------------------------------

_COLUMNS = (  # key, title, width (negative: left-aligned), format spec
    ("solver", "solver", -40, "s"),
    ("rtol", "rtol", 7, ".0e"),
    ("wall_time", "wall [s]", 9, ".3f"),
    ("steps_per_period", "steps/T", 8, ".1f"),
    ("impact_time_error_1p5s", "err 1.5 s", 10, ".2e"),
    ("n_impacts", "impacts", 8, "d"),
    ("on_attractor", "attractor", 10, "s"),
)


def _cells(row: dict, header: bool = False) -> str:
    cells = []
    for key, title, width, spec in _COLUMNS:
        value = row.get(key)
        if header:
            text = title
        elif value is None:
            text = "-"  # the column does not apply (floor rows: no contact, no impacts)
        elif isinstance(value, bool):
            text = "yes" if value else "no"
        else:
            text = format(value, spec)
        cells.append(text.ljust(-width) if width < 0 else text.rjust(width))
    return " ".join(cells)


def _line(row: dict) -> str:
    status = row.get("status", "ok")
    return _cells(row) + ("" if status == "ok" else f"  ({status})")


def format_table(rows: list[dict]) -> str:
    """The rows as a fixed-width text table, '-' where a column does not apply."""
    return "\n".join([_cells({}, header=True)] + [_line(r) for r in rows])
