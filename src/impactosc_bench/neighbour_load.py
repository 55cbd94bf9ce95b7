"""Does a busy neighbour change the timings? The evidence behind ``timing.exclusive: false``.

Why: a timing job of the workflow that claims the whole machine leaves the second core idle
for its whole length; one that runs beside another job is only fair if the neighbour does not
change the times, or changes every contestant's alike. This measures it on the machine at
hand: the core and CyRK Vern7 over the chaotic scene (w = 40.86, from rest, 500 s, rtol 1e-10,
as in benchmark_core), alone and beside a busy neighbour (a process integrating the same scene
without pause, as a sweep job does), the two conditions alternated round by round, and prints
the medians and the CyRK / core ratio per condition.

    python -m impactosc_bench.neighbour_load --rounds 12
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

from impactosc_bench.core_speed import run_core_from_rest
from impactosc_bench.cyrk_runs import run_cyrk

NEIGHBOUR = "from impactosc.core.simulation import simulate\nwhile True:\n    simulate(40.86, 0.0, 2000.0, record=('impacts',))\n"
CONTESTANTS = {
    "core": lambda: run_core_from_rest(1e-10, 1e-12).wall_time,
    "CyRK Vern7": lambda: run_cyrk("Vern7", 500.0, 1e-10, 1e-12).wall_time,
}


def measure_neighbour_load(rounds: int, settle: float = 2.0) -> dict:
    """{condition: {contestant: [wall time per round]}} for the conditions alone and beside a
    busy neighbour, alternated (ABBA...) so that a drift of the machine's load falls on both."""
    if rounds < 1:
        raise ValueError(f"rounds must be >= 1, got {rounds}")
    for run in CONTESTANTS.values():  # compile, build the shim, warm the caches
        run()
    out = {cond: {name: [] for name in CONTESTANTS} for cond in ("alone", "beside a neighbour")}
    for k in range(rounds):
        for cond in ("alone", "beside a neighbour") if k % 2 == 0 else ("beside a neighbour", "alone"):
            neighbour = subprocess.Popen([sys.executable, "-c", NEIGHBOUR]) if cond != "alone" else None
            try:
                if neighbour is not None:
                    time.sleep(settle)  # let it load the cached core and start integrating
                for name, run in CONTESTANTS.items():
                    out[cond][name].append(run())
            finally:
                if neighbour is not None:
                    neighbour.kill()
                    neighbour.wait()
    return out


def summarise_load(out: dict) -> list[str]:
    """One line per condition: median wall times and the median per-round CyRK / core ratio."""
    lines = []
    for cond, walls in out.items():
        ratios = [p / c for c, p in zip(walls["core"], walls["CyRK Vern7"])]
        lines.append(
            f"{cond:>20s}: core {statistics.median(walls['core']):.3f} s, "
            f"CyRK Vern7 {statistics.median(walls['CyRK Vern7']):.3f} s, CyRK/core median "
            f"{statistics.median(ratios):.2f} (rounds {min(ratios):.2f}-{max(ratios):.2f})"
        )
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=12, help="rounds per condition (default 12)")
    args = ap.parse_args(argv)
    for line in summarise_load(measure_neighbour_load(args.rounds)):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
