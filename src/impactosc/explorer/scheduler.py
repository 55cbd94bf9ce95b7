"""The explorer's computations on both cores, streamed, with stale requests cancelled.

Why a process pool: the core is compiled numba that does not release the interpreter lock, so
two threads would take turns on one core; two worker processes use both. Why batches: a
continuation is sequential and a pool task returns only when it ends, so a diagram is split into
``lanes`` contiguous stretches of w (one per worker, each a continuation of its own) and every
lane into small batches of columns; each batch starts from the state the previous one ended on,
and its columns reach the page as soon as it ends. The first batch of a lane is the shortest, so
the first columns come quickly.

Why a generation counter: a new diagram (a zoom, a changed slider) or a new w makes the older
request stale. Each request takes the next generation of its kind; the older generation's
queued batches are cancelled, its running batch finishes but starts no successor, and its
results are handed on with their generation so that the page can drop them
(:meth:`Scheduler.is_current`), checked again when the page draws: a stale picture is never
drawn over a new one.
"""

from __future__ import annotations

import itertools
import multiprocessing
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor

import numpy as np

from impactosc.explorer import work
from impactosc.explorer.view import View

__all__ = ["Scheduler", "make_pool", "lane_plan", "DIAGRAM", "ATTRACTOR", "POINTS"]

DIAGRAM, ATTRACTOR, POINTS = "diagram", "attractor", "points"
#: Columns in a lane's first batch and in every later one: small first (first columns fast),
#: larger after (fewer hand-overs)
FIRST_BATCH, BATCH = 3, 8
#: Periods recorded for the attractor panel (the diagram's n_record is shorter, for speed)
ATTRACTOR_RECORD = 60


def lane_plan(n: int, lanes: int) -> list[tuple[int, int]]:
    """Split columns 0..n-1 (in sweep order) into `lanes` contiguous ranges [a, b)."""
    lanes = max(1, min(lanes, n))
    cuts = np.linspace(0, n, lanes + 1).round().astype(int)
    return [(int(a), int(b)) for a, b in itertools.pairwise(cuts) if b > a]


def _batches(a: int, b: int) -> list[tuple[int, int]]:
    out, i = [], a
    while i < b:
        j = min(b, i + (FIRST_BATCH if i == a else BATCH))
        out.append((i, j))
        i = j
    return out


def make_pool(workers: int) -> ProcessPoolExecutor:
    """Worker processes started fresh ("spawn"): forking the server, whose threads may hold
    locks, is unsafe."""
    return ProcessPoolExecutor(int(workers), mp_context=multiprocessing.get_context("spawn"))


class Scheduler:
    """Runs the explorer's requests on a pool of `workers` processes.

    Results are handed to the callbacks with their generation, from a pool thread; the caller
    marshals them into its own thread and asks :meth:`is_current` before drawing."""

    def __init__(self, workers: int = 2, pool: ProcessPoolExecutor | None = None):
        self.workers = int(workers)
        # the server's pages share one pool (pool given), each page its own generations
        self._owns_pool = pool is None
        self._pool = pool or make_pool(self.workers)
        self._lock = threading.Lock()
        self._generation = {DIAGRAM: 0, ATTRACTOR: 0, POINTS: 0}
        self._futures: dict[str, list[Future]] = {DIAGRAM: [], ATTRACTOR: [], POINTS: []}
        self._counter = itertools.count(1)

    # ------------------------------------------------------------------ generations

    def is_current(self, kind: str, generation: int) -> bool:
        """Whether `generation` is still the newest request of `kind`."""
        with self._lock:
            return self._generation[kind] == generation

    def _next(self, kind: str) -> int:
        """A new generation of `kind`: queued work of the older ones is cancelled."""
        with self._lock:
            self._generation[kind] = gen = next(self._counter)
            stale, self._futures[kind] = self._futures[kind], []
        for f in stale:
            f.cancel()
        return gen

    def cancel(self, kind: str) -> None:
        """Drop the current request of `kind` (its results will not be handed on)."""
        self._next(kind)

    def _submit(self, kind: str, generation: int, fn, *args) -> Future | None:
        with self._lock:
            if self._generation[kind] != generation:
                return None
            future = self._pool.submit(fn, *args)
            self._futures[kind] = [f for f in self._futures[kind] if not f.done()] + [future]
        return future

    # ------------------------------------------------------------------ requests

    def warm(self, timeout: float = 900.0) -> float:
        """Start every worker and load the compiled core in it; returns the seconds taken.

        One worker first: without numba's cache on disk it compiles the core (minutes) and
        writes the cache, which the others then load in a second, instead of all compiling."""
        t0 = time.perf_counter()
        self._pool.submit(work.warm).result(timeout=timeout)
        for f in [self._pool.submit(work.warm) for _ in range(self.workers)]:
            f.result(timeout=timeout)
        return time.perf_counter() - t0

    def diagram(
        self,
        view: View,
        on_columns: Callable[[int, list], None],
        on_done: Callable[[int, float], None] | None = None,
        on_error: Callable[[int, str], None] | None = None,
        seed: Callable[[float], tuple[float, float] | None] | None = None,
    ) -> int:
        """Compute the view's diagram; returns its generation.

        `on_columns(generation, columns)` receives each batch (dicts of :func:`.work.diagram_batch`)
        and `on_done(generation, seconds)` the end. `seed(w)` may give a state on the attractor
        near w (from the diagram shown before a zoom): a lane starting there discards
        n_transient periods instead of n_initial from rest."""
        gen = self._next(DIAGRAM)
        omegas, settings = view.omegas(), view.settings()
        t0 = time.perf_counter()
        plan = lane_plan(omegas.size, self.workers)
        remaining = {"lanes": len(plan)}

        def run(batches, x0, v0, first_transient):
            (a, b), rest = batches[0], batches[1:]
            future = self._submit(DIAGRAM, gen, work.diagram_batch, omegas[a:b], settings, x0, v0, first_transient)
            if future is not None:
                future.add_done_callback(lambda f: finished(f, rest))

        def finished(future: Future, rest):
            if future.cancelled() or not self.is_current(DIAGRAM, gen):
                return
            exc = future.exception()
            if exc is not None:
                if on_error is not None:
                    on_error(gen, f"{type(exc).__name__}: {exc}")
                return
            out = future.result()
            on_columns(gen, out["columns"])
            if rest:
                run(rest, out["x_end"], out["v_end"], settings.n_transient)
                return
            with self._lock:
                remaining["lanes"] -= 1
                last = remaining["lanes"] == 0
            if last and on_done is not None:
                on_done(gen, time.perf_counter() - t0)

        for a, b in plan:
            start = seed(float(omegas[a])) if seed is not None else None
            if start is None:
                run(_batches(a, b), settings.x0, settings.v0, settings.n_initial)
            else:
                run(_batches(a, b), start[0], start[1], settings.n_transient)
        return gen

    def attractor(
        self,
        view: View,
        omega: float,
        on_attractor: Callable[[int, dict], None],
        on_orbit: Callable[[int, dict], None] | None = None,
        on_error: Callable[[int, str], None] | None = None,
        seed: tuple[float, float] | None = None,
    ) -> int:
        """The attractor at `omega` (from `seed`, a state near it, else from rest), then, when it
        is periodic, its orbit shot with its multipliers; returns the generation."""
        gen = self._next(ATTRACTOR)
        x0, v0 = seed if seed is not None else (view.settings().x0, view.settings().v0)
        n_tr = view.n_transient if seed is not None else view.n_initial
        future = self._submit(ATTRACTOR, gen, work.attractor, omega, view.params, x0, v0, n_tr, ATTRACTOR_RECORD)

        def got_orbit(f: Future):
            if f.cancelled() or not self.is_current(ATTRACTOR, gen) or on_orbit is None:
                return
            exc = f.exception()
            on_orbit(gen, {"omega": omega, "error": str(exc)} if exc is not None else f.result())

        def got_attractor(f: Future):
            if f.cancelled() or not self.is_current(ATTRACTOR, gen):
                return
            exc = f.exception()
            if exc is not None:
                if on_error is not None:
                    on_error(gen, f"w = {omega:g}: {type(exc).__name__}: {exc}")
                return
            out = f.result()
            on_attractor(gen, out)
            p = out["period"]
            if 0 < p <= work.MAX_SHOT_PERIOD and on_orbit is not None:
                y = (out["poincare_x"][-1], out["poincare_v"][-1])
                nxt = self._submit(ATTRACTOR, gen, work.periodic_orbit, omega, view.params, y, p)
                if nxt is not None:
                    nxt.add_done_callback(got_orbit)

        if future is not None:
            future.add_done_callback(got_attractor)
        return gen

    def points(
        self, view: View, on_points: Callable[[int, list], None], on_error: Callable[[int, str], None] | None = None
    ) -> int:
        """The located points of the period-1 branch over the view's window; returns the generation."""
        gen = self._next(POINTS)
        future = self._submit(POINTS, gen, work.located_points, view.params, view.w_lo, view.w_hi)

        def got(f: Future):
            if f.cancelled() or not self.is_current(POINTS, gen):
                return
            exc = f.exception()
            if exc is not None:
                if on_error is not None:
                    on_error(gen, f"located points: {type(exc).__name__}: {exc}")
                return
            on_points(gen, f.result())

        if future is not None:
            future.add_done_callback(got)
        return gen

    def call(self, fn, *args) -> Future:
        """Any other work function (a record's points) on the pool."""
        return self._pool.submit(fn, *args)

    def close(self) -> None:
        with self._lock:
            for kind in self._generation:
                self._generation[kind] = -1
        for futures in self._futures.values():
            for f in futures:
                f.cancel()
        if self._owns_pool:
            self._pool.shutdown(wait=False, cancel_futures=True)
