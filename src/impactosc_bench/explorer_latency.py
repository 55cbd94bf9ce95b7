"""Latency of the live explorer, measured through the scheduler the page uses.

Why through :class:`impactosc.explorer.scheduler.Scheduler`: what a user waits for is the
pool's hand-over, the batching and the pickling as much as the core. The page's own drawing
(Bokeh's websocket, the browser) is not in these numbers. Three waits, each the median of
several repeats after the workers are warm:

- a new w to its attractor's data (the time series, Poincare points and intervals), when the
  w lies inside the diagram shown (continued from the nearest column's end state, as the page
  does) and when it does not (from rest, n_initial periods first); target 0.5 s;
- a 400-column diagram (20-45 rad/s) complete; target 10 s on 2 cores;
- its first columns drawn; target 1 s;

and how long a page waits when a worker has died: a new w's attractor asked for right after one
worker was killed (SIGKILL), the pool replaced and its workers loading the core first.

    python -m impactosc_bench.explorer_latency [--repeats 5] [--columns 400] [--output FILE]

prints the table and writes it (Markdown) to FILE.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import threading
import time
from pathlib import Path

from impactosc.explorer.scheduler import Scheduler, WorkerPool
from impactosc.explorer.view import View

OMEGAS = (25.0, 33.0, 37.6, 40.86, 43.0)
TARGETS = {"attractor": 0.5, "first": 1.0, "diagram": 10.0}


def time_diagram(s: Scheduler, view: View) -> tuple[float, float, dict, float]:
    """(first columns, complete) seconds of one diagram, the end state of every column, and
    the CPU seconds its columns took in the workers."""
    done, first, seeds, cpu = threading.Event(), [], {}, []
    t0 = time.perf_counter()

    def columns(_gen, cols):
        if not first:
            first.append(time.perf_counter() - t0)
        for c in cols:
            seeds[c["omega"]] = c["state_end"]
            cpu.append(c["cpu"])

    s.diagram(view, columns, on_done=lambda _gen, _s: done.set())
    if not done.wait(300):
        raise RuntimeError("the diagram did not complete in 300 s")
    return first[0], time.perf_counter() - t0, seeds, sum(cpu)


def time_attractor(s: Scheduler, view: View, omega: float, seed) -> float:
    """Seconds from the request to the attractor's data (before its orbit is shot)."""
    ready = threading.Event()
    t0 = time.perf_counter()
    s.attractor(view, omega, lambda _gen, _out: ready.set(), seed=seed)
    if not ready.wait(60):
        raise RuntimeError(f"no attractor at w = {omega} in 60 s")
    return time.perf_counter() - t0


def time_healing(s: Scheduler, pool: WorkerPool, view: View) -> float:
    """Seconds to a new w's attractor (from rest) asked for after a worker was killed: the pool
    is replaced and its workers load the core before they compute it."""
    os.kill(pool.pids()[0], signal.SIGKILL)
    time.sleep(0.5)  # the user's next request comes later than the pool's notice of the death
    return time_attractor(s, view, OMEGAS[0], None)


def measure_latency(repeats: int, workers: int = 2, columns: int = 400) -> list[dict]:
    """The three waits, each its median over `repeats` (the attractor's over OMEGAS as well), on a
    diagram of `columns` columns (the targets are set for 400), and the wait after a dead worker."""
    pool = WorkerPool(workers)
    s = Scheduler(workers, pool=pool)
    warm = s.warm()
    view = View(w_lo=20.0, w_hi=45.0, n_columns=columns)
    firsts, totals, cpus, seeds = [], [], [], {}
    for _ in range(repeats):
        first, total, seeds, cpu = time_diagram(s, view)
        firsts.append(first)
        totals.append(total)
        cpus.append(cpu / workers)
    seeded, rest = [], []
    for _ in range(repeats):
        for w in OMEGAS:
            near = min(seeds, key=lambda c: abs(c - w))
            seeded.append(time_attractor(s, view, w, seeds[near]))
            rest.append(time_attractor(s, view, w, None))
    healed = [time_healing(s, pool, view) for _ in range(repeats)]
    s.close()
    per_w = f"{view.n_transient} + {view.n_record} forcing periods per w"
    return [
        dict(what=f"a new w's attractor, w inside the diagram ({view.n_transient} + 60 periods)", runs=len(seeded),
             median=statistics.median(seeded), worst=max(seeded), target=TARGETS["attractor"]),
        dict(what=f"a new w's attractor, from rest ({view.n_initial} + 60 periods)", runs=len(rest),
             median=statistics.median(rest), worst=max(rest), target=TARGETS["attractor"]),
        dict(what=f"{columns}-column diagram, first columns ({per_w})", runs=repeats, median=statistics.median(firsts),
             worst=max(firsts), target=TARGETS["first"]),
        dict(what=f"{columns}-column diagram, complete ({per_w})", runs=repeats, median=statistics.median(totals),
             worst=max(totals), target=TARGETS["diagram"]),
        dict(what=f"{columns}-column diagram, its columns' CPU time / {workers} (complete on {workers} idle cores)",
             runs=repeats, median=statistics.median(cpus), worst=max(cpus), target=TARGETS["diagram"]),
        dict(what="workers started and the compiled core loaded (once, before the page is served)", runs=1,
             median=warm, worst=warm, target=float("nan")),
        dict(what="a new w's attractor after a worker was killed (workers replaced and warmed first)",
             runs=len(healed), median=statistics.median(healed), worst=max(healed), target=float("nan")),
    ]  # fmt: skip


def markdown(rows: list[dict], workers: int) -> str:
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines = [
        f"Measured by `python -m impactosc_bench.explorer_latency` on {os.cpu_count()} cores, {workers} workers "
        f"(load average {load:.1f} when it ended).",
        "",
        "| wait | runs | median (s) | worst (s) | target (s) |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        target = f"{r['target']:g}" if r["target"] == r["target"] else ""
        lines.append(f"| {r['what']} | {r['runs']} | {r['median']:.3f} | {r['worst']:.3f} | {target} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="repeats of each wait (default 3)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--columns", type=int, default=400, help="columns of the diagram timed (default 400)")
    parser.add_argument("--output", default="results/benchmarks/explorer_latency.md", help="Markdown table to write")
    args = parser.parse_args(argv)
    text = markdown(measure_latency(args.repeats, args.workers, args.columns), args.workers)
    print(text, end="")
    out = Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(f"written to {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
