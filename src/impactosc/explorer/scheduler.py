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

Why a pool that heals (:class:`WorkerPool`): a worker that dies (killed, out of memory) breaks a
ProcessPoolExecutor for good, for every page. The pool is replaced as soon as a worker dies, busy
or idle; the page whose request failed so is told why, and the next request runs on the new
workers.

Why a process of its own for a record (:class:`OneShot`): reading a file may take long and cannot
be stopped inside a shared worker; a process of its own is killed when its page closes, when a
newer record is asked for, or when it runs out of time.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import math
import multiprocessing
import multiprocessing.connection
import signal
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool

import numpy as np

from impactosc.explorer import work
from impactosc.explorer.view import View

__all__ = ["Scheduler", "WorkerPool", "OneShot", "make_pool", "lane_plan", "DIAGRAM", "ATTRACTOR", "POINTS", "RECORD"]

log = logging.getLogger(__name__)

DIAGRAM, ATTRACTOR, POINTS, RECORD = "diagram", "attractor", "points", "record"
#: Seconds a record may take to load before its process is killed
RECORD_TIMEOUT = 120.0
#: Columns in a lane's first batch and in every later one: small first (first columns fast),
#: larger after (fewer hand-overs)
FIRST_BATCH, BATCH = 3, 8
#: Periods recorded for the attractor panel (the diagram's n_record is shorter, for speed)
ATTRACTOR_RECORD = 60
#: Seconds between the pool's looks at which workers it has (they are started on demand)
WATCH_PERIOD = 0.5


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


def _exit_reason(code: int) -> str:
    if code < 0:
        try:
            return f"killed by {signal.Signals(-code).name}"
        except ValueError:
            return f"killed by signal {-code}"
    return f"exit code {code}"


def _exit_code(proc, timeout: float = 1.0) -> int | None:
    """The exit code of a process whose end was seen. Its end is seen before it is reaped, and the
    executor's own thread may reap it meanwhile (then this thread's wait finds no child until that
    one has stored the code): wait for it a little."""
    deadline = time.monotonic() + timeout
    proc.join(timeout)
    while proc.exitcode is None and time.monotonic() < deadline:
        time.sleep(0.01)
    return proc.exitcode


def _death(executor: ProcessPoolExecutor, exc: BaseException | None, dead=None) -> str:
    """Why a pool broke, in a few words: the worker that ended (among `dead`, the processes seen
    ending, if given) and how, or the last line of the cause the pool gives (a result it could not
    read back). A broken executor stops its other workers with SIGTERM: when several are seen
    ended, the one that ended otherwise is the cause."""
    if dead is None:
        procs = list((getattr(executor, "_processes", None) or {}).values())
        ended = multiprocessing.connection.wait([p.sentinel for p in procs], timeout=0)
        dead = [p for p in procs if p.sentinel in ended]
    codes = [(proc.pid, code) for proc in dead if (code := _exit_code(proc))]
    codes.sort(key=lambda pc: pc[1] == -signal.SIGTERM)  # a stable sort: the others first, in order
    if codes:
        pid, code = codes[0]
        return f"worker {pid} {_exit_reason(code)}"
    cause = getattr(exc, "__cause__", None)
    lines = [line.strip() for line in str(cause or "").splitlines() if line.strip().strip("'")]
    return lines[-1] if lines else "a worker process ended abruptly"


class PoolClosed(RuntimeError):
    """A request after the workers were shut down (the server is stopping)."""


class WorkerPool:
    """The worker processes every page shares, replaced when they break.

    Why: a dead worker breaks a ProcessPoolExecutor for good (every pending future fails with
    BrokenProcessPool and every later submit raises it). The first future that fails so, a submit
    that finds the pool broken, or the watcher that sees a worker end (:meth:`_watch`) replaces
    that executor by a new one, warmed; the others find it replaced already. :attr:`last_death`
    says why it broke."""

    def __init__(self, workers: int = 2):
        self.workers = int(workers)
        self.restarts = 0
        self.last_death = ""
        self._lock = threading.Lock()
        self._closed = False
        self._executor = make_pool(self.workers)
        threading.Thread(target=self._watch, name="impactosc-pool-watch", daemon=True).start()

    def submit(self, fn, *args) -> Future:
        """fn(*args) on a worker; PoolClosed once :meth:`shutdown` was called."""
        with self._lock:
            if self._closed:
                raise PoolClosed("the explorer's workers are shut down")
            executor = self._executor
            try:
                future = executor.submit(fn, *args)
            except BrokenProcessPool as exc:
                executor = self._replace(executor, exc)
                future = executor.submit(fn, *args)
        future.add_done_callback(lambda f: self._check(executor, f))
        return future

    def _check(self, executor: ProcessPoolExecutor, future: Future) -> None:
        if not future.cancelled() and isinstance(future.exception(), BrokenProcessPool):
            with self._lock:
                self._replace(executor, future.exception())

    def _watch(self) -> None:
        """Replace the executor as soon as one of its workers ends, busy or idle.

        Why: the executor fails only the futures it holds when a worker dies. One that dies
        between requests (killed, out of memory) would leave a broken pool, said nowhere, until a
        request finds it and waits for new workers; watched, the pool is replaced (and the death
        logged) when it happens. A worker started since the last look is watched from the next."""
        while True:
            with self._lock:
                if self._closed:
                    return
                executor = self._executor
                procs = list((getattr(executor, "_processes", None) or {}).values())
            if not procs:
                time.sleep(WATCH_PERIOD)
                continue
            # the Process objects held here keep their sentinels open while they are waited on
            ended = multiprocessing.connection.wait([p.sentinel for p in procs], timeout=WATCH_PERIOD)
            if ended:
                with self._lock:
                    self._replace(executor, None, [p for p in procs if p.sentinel in ended])

    def _replace(self, broken: ProcessPoolExecutor, exc: BaseException | None, dead=None) -> ProcessPoolExecutor:
        """The new executor, made unless `broken` was replaced already (lock held); its workers
        load the core before the requests queued after them run. `dead`: the workers seen ending."""
        if self._executor is broken and not self._closed:
            self.last_death = _death(broken, exc, dead)
            self.restarts += 1
            log.warning("impactosc explore: %s; workers restarted (%d so far)", self.last_death, self.restarts)
            self._executor = make_pool(self.workers)
            for _ in range(self.workers):
                self._executor.submit(work.warm)
        return self._executor

    def pids(self) -> list[int]:
        """The worker processes' ids (those started so far)."""
        with self._lock:
            return sorted(getattr(self._executor, "_processes", None) or {})

    def shutdown(self, wait: bool = True, cancel_futures: bool = False) -> None:
        """Stop the workers. The lock is not held while waiting: the callbacks of the last
        results, run meanwhile, may still try to submit (and are told PoolClosed)."""
        with self._lock:
            self._closed = True
            executor = self._executor
        executor.shutdown(wait=wait, cancel_futures=cancel_futures)


def error_text(exc: BaseException, pool) -> str:
    """What a page says of a failed request: the error, or for a dead worker why it died and
    that the workers were restarted."""
    if isinstance(exc, BrokenProcessPool):
        why = getattr(pool, "last_death", "") or "a worker process ended abruptly"
        return f"a worker process died ({why}); the workers were restarted: ask again"
    if isinstance(exc, work.WorkerError):
        return str(exc)
    return f"{type(exc).__name__}: {exc}"


def _one_shot(conn, fn, args) -> None:
    """A OneShot's process: fn's result, or its error as text (always plain to pickle)."""
    try:
        result = (True, fn(*args))
    except Exception as exc:  # the reason goes back to the page; the process ends either way
        result = (False, f"{type(exc).__name__}: {exc}")
    conn.send(result)
    conn.close()


class OneShot:
    """fn(*args) in a process of its own, which :meth:`cancel` kills; then, from a thread,
    `on_done(True, result)` or `on_done(False, reason)`, unless cancelled. A run longer than
    `timeout` seconds is killed and reported."""

    def __init__(self, fn, args, on_done: Callable[[bool, object], None], timeout: float = RECORD_TIMEOUT):
        ctx = multiprocessing.get_context("spawn")
        self._conn, sender = ctx.Pipe(duplex=False)
        self._proc = ctx.Process(target=_one_shot, args=(sender, fn, args), daemon=True)
        self._cancelled = threading.Event()
        self._proc.start()
        sender.close()
        threading.Thread(target=self._wait, args=(on_done, timeout), daemon=True).start()

    def _wait(self, on_done, timeout: float) -> None:
        ready = multiprocessing.connection.wait([self._conn, self._proc.sentinel], timeout)
        answer = None
        if self._conn in ready:
            with contextlib.suppress(EOFError, OSError):  # it ended without an answer (killed, or cancelled)
                answer = self._conn.recv()
        self._proc.kill()
        self._proc.join()
        self._conn.close()
        if answer is None:
            late = not ready
            answer = (False, f"took more than {timeout:g} s" if late else f"it {_exit_reason(self._proc.exitcode)}")
        if not self._cancelled.is_set():
            on_done(*answer)

    def cancel(self) -> bool:
        """Kill the process; `on_done` is not called."""
        self._cancelled.set()
        self._proc.kill()
        return True

    def done(self) -> bool:
        """Whether the process has ended."""
        return not self._proc.is_alive()


class Scheduler:
    """Runs the explorer's requests on a pool of `workers` processes.

    Results are handed to the callbacks with their generation, from a pool thread; the caller
    marshals them into its own thread and asks :meth:`is_current` before drawing."""

    def __init__(self, workers: int = 2, pool: WorkerPool | None = None):
        self.workers = int(workers)
        # the server's pages share one pool (pool given), each page its own generations
        self._owns_pool = pool is None
        self._pool = pool or WorkerPool(self.workers)
        self._lock = threading.Lock()
        kinds = (DIAGRAM, ATTRACTOR, POINTS, RECORD)
        self._generation = dict.fromkeys(kinds, 0)
        self._futures: dict[str, list] = {k: [] for k in kinds}
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
            try:
                future = self._pool.submit(fn, *args)
            except PoolClosed:
                return None  # the server is stopping: nobody waits for this
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

        def run(batches, state, first_transient):
            (a, b), rest = batches[0], batches[1:]
            future = self._submit(DIAGRAM, gen, work.diagram_batch, omegas[a:b], settings, state, first_transient)
            if future is not None:
                future.add_done_callback(lambda f: finished(f, rest))

        def finished(future: Future, rest):
            if future.cancelled() or not self.is_current(DIAGRAM, gen):
                return
            exc = future.exception()
            if exc is not None:
                if on_error is not None:
                    on_error(gen, error_text(exc, self._pool))
                return
            out = future.result()
            on_columns(gen, out["columns"])
            if rest:
                run(rest, out["state_end"], settings.n_transient)
                return
            with self._lock:
                remaining["lanes"] -= 1
                last = remaining["lanes"] == 0
            if last and on_done is not None:
                on_done(gen, time.perf_counter() - t0)

        for a, b in plan:
            start = seed(float(omegas[a])) if seed is not None else None
            if start is None:
                run(_batches(a, b), (settings.x0, settings.v0, math.nan), settings.n_initial)
            else:
                run(_batches(a, b), start, settings.n_transient)
        return gen

    def attractor(
        self,
        view: View,
        omega: float,
        on_attractor: Callable[[int, dict], None],
        on_orbit: Callable[[int, dict], None] | None = None,
        on_error: Callable[[int, str], None] | None = None,
        seed: tuple[float, float, float] | None = None,
    ) -> int:
        """The attractor at `omega` (from `seed`, a state (x, v, contact_v0) near it, else from
        rest), then, when it is periodic, its orbit shot with its multipliers from its last
        Poincare point; returns the generation."""
        gen = self._next(ATTRACTOR)
        state = seed if seed is not None else (view.settings().x0, view.settings().v0, math.nan)
        n_tr = view.n_transient if seed is not None else view.n_initial
        future = self._submit(ATTRACTOR, gen, work.attractor, omega, view.params, state, n_tr, ATTRACTOR_RECORD)

        def got_orbit(f: Future):
            if f.cancelled() or not self.is_current(ATTRACTOR, gen) or on_orbit is None:
                return
            exc = f.exception()
            on_orbit(gen, {"omega": omega, "error": error_text(exc, self._pool)} if exc is not None else f.result())

        def got_attractor(f: Future):
            if f.cancelled() or not self.is_current(ATTRACTOR, gen):
                return
            exc = f.exception()
            if exc is not None:
                if on_error is not None:
                    on_error(gen, f"w = {omega:g}: {error_text(exc, self._pool)}")
                return
            out = f.result()
            on_attractor(gen, out)
            p = out["period"]
            if 0 < p <= work.MAX_SHOT_PERIOD and on_orbit is not None:
                y = out["state_end"]  # the last Poincare point, with its contact's v0 inside one
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
                    on_error(gen, f"located points: {error_text(exc, self._pool)}")
                return
            on_points(gen, f.result())

        if future is not None:
            future.add_done_callback(got)
        return gen

    def record(
        self, path: str, on_record: Callable[[int, dict], None], on_error: Callable[[int, str], None],
        timeout: float = RECORD_TIMEOUT, load=work.record_points,
    ) -> int:  # fmt: skip
        """A record's Poincare points (`load` of `path`: :func:`.work.record_points`) in a process
        of its own, killed by a newer record request, :meth:`close` or `timeout`; returns the
        generation."""
        gen = self._next(RECORD)

        def done(ok: bool, value):
            if self.is_current(RECORD, gen):
                (on_record if ok else on_error)(gen, value)

        with self._lock:
            if self._generation[RECORD] == gen:
                self._futures[RECORD].append(OneShot(load, (path,), done, timeout))
        return gen

    def close(self) -> None:
        with self._lock:
            for kind in self._generation:
                self._generation[kind] = -1
        for futures in self._futures.values():
            for f in futures:
                f.cancel()
        if self._owns_pool:
            self._pool.shutdown(wait=False, cancel_futures=True)
