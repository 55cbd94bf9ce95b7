"""What a long command says while it runs: its expected wall time, once, after its first seconds.

Why: a run of a long simulated time (or a fine sampling) can take hours; the user learns it
after a few seconds instead of waiting without a word. The estimate is the elapsed time over
the share done, so it assumes the rest costs what the start did (a chaotic run's cost is steady;
a transient that settles on a periodic orbit makes it an upper bound).
"""

from __future__ import annotations

import sys
import time

#: Seconds of progress before the estimate is said (long enough for a steady rate, short
#: enough to stop a mistaken run early).
AFTER = 3.0


def duration_text(seconds: float) -> str:
    """A wall time as a person reads it: 40 s, 12 min, 3.5 h, 14 days."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 2 * 3600:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"


class WallTimeForecast:
    """Called with the share done (0..1) as a run advances; after ``after`` s, says once on
    stderr the run's expected wall time when the rest takes longer than what has passed."""

    def __init__(self, command: str, quiet: bool = False, after: float = AFTER):
        self.command, self.quiet, self.after = command, quiet, after
        self.start = time.perf_counter()
        self.said = quiet

    def __call__(self, done: float) -> None:
        if self.said or not done > 0:
            return
        elapsed = time.perf_counter() - self.start
        if elapsed < self.after:
            return
        self.said = True
        total = elapsed / min(done, 1.0)
        if total - elapsed > elapsed:
            print(
                f"impactosc {self.command}: expected wall time ~{duration_text(total)} "
                f"({100 * done:.2g} % done after {elapsed:.0f} s)",
                file=sys.stderr,
                flush=True,
            )
