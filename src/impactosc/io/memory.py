"""How much memory a request may take: the arrays a command would allocate are estimated and
refused before computing when they exceed what the machine has, instead of a MemoryError late in
the run or the kernel killing the process."""

from __future__ import annotations

import os

#: Share of the available memory one request may take (the rest: the interpreter, the
#: libraries, the file being written and the other processes' growth).
SHARE = 0.8


def available_bytes() -> int:
    """Memory that can be allocated without swapping: /proc/meminfo's MemAvailable where Linux
    states it, else the physical memory."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def gigabytes(n_bytes: float) -> str:
    return f"{n_bytes / 1e9:.3g} GB"


def shortfall(n_bytes: float) -> str | None:
    """None when `n_bytes` fit in memory, else what they need against what there is (for a
    message that then says how to make the request fit)."""
    have = available_bytes()
    if n_bytes <= SHARE * have:
        return None
    return f"needs {gigabytes(n_bytes)} of memory, more than the {gigabytes(SHARE * have)} this machine can give it"
