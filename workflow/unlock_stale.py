"""Remove the lock a killed Snakemake left in a working directory, never one a live Snakemake holds.

Why: a build killed with SIGKILL (or by a lost terminal, a reboot, an out-of-memory kill) leaves
Snakemake's lock files in .snakemake/locks, and the next run stops with a LockException until
someone runs `snakemake --unlock`. `make` calls this before Snakemake (which it runs with
--rerun-incomplete), so a plain `make` resumes a killed build.

A lock is stale when no Snakemake process works in the directory. A process counts as one when
an argument of its command line contains "snakemake" (the snakemake command, `python -m
snakemake`, the scripts Snakemake runs from .snakemake/scripts) and its current directory is the
working directory (Snakemake changes into it, its jobs run there) or a --directory/-d argument
names it. Linux only (/proc): elsewhere nothing is removed and Snakemake says what to do.

Usage: python workflow/unlock_stale.py [DIRECTORY]   (default: the current directory)
Exit 0 whether a lock was removed, kept (a live Snakemake holds it: Snakemake then decides
whether the new run may go on beside it) or absent.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

PROC = Path("/proc")


def _cmdline(pid: str) -> list[str]:
    """A process's arguments; [] when it has gone, is a zombie or cannot be read."""
    try:
        raw = (PROC / pid / "cmdline").read_bytes()
    except OSError:
        return []
    return [a.decode(errors="replace") for a in raw.split(b"\0") if a]


def _cwd(pid: str) -> Path | None:
    """A process's current directory; None when it cannot be read (another user's process)."""
    try:
        return Path(os.readlink(PROC / pid / "cwd"))
    except OSError:
        return None


def _named_directory(args: list[str], cwd: Path | None) -> Path | None:
    """The directory a --directory/-d argument names (relative to the process's own directory)."""
    for i, arg in enumerate(args):
        value = None
        if arg in ("-d", "--directory") and i + 1 < len(args):
            value = args[i + 1]
        elif arg.startswith("--directory="):
            value = arg.split("=", 1)[1]
        if value is not None:
            path = Path(value)
            if not path.is_absolute():
                if cwd is None:
                    return None
                path = cwd / path
            return Path(os.path.realpath(path))
    return None


def snakemake_processes(directory) -> list[tuple[int, str]]:
    """(pid, command line) of every other process that runs Snakemake, or a Snakemake job, in directory."""
    directory = Path(os.path.realpath(directory))
    found = []
    for entry in PROC.iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        args = _cmdline(entry.name)
        if not any("snakemake" in arg for arg in args):
            continue
        cwd = _cwd(entry.name)
        here = cwd is not None and Path(os.path.realpath(cwd)) == directory
        if here or _named_directory(args, cwd) == directory:
            found.append((int(entry.name), " ".join(args)))
    return found


def lock_files(directory) -> list[Path]:
    """Snakemake's lock files in directory (.snakemake/locks/<n>.input.lock and <n>.output.lock)."""
    return sorted((Path(directory) / ".snakemake" / "locks").glob("*.lock"))


def unlock_stale(directory) -> str:
    """Remove the locks in directory unless a Snakemake process works there; say what was done."""
    directory = os.path.realpath(directory)
    locks = lock_files(directory)
    if not locks:
        return ""
    if not PROC.is_dir():
        return f"kept the Snakemake lock in {directory}: no /proc to tell whether a Snakemake still runs there"
    holders = snakemake_processes(directory)
    if holders:
        who = "; ".join(f"pid {pid}: {cmd[:120]}" for pid, cmd in holders)
        return (
            f"kept the Snakemake lock in {directory}: a Snakemake process still works there ({who}); "
            "wait for it to finish, or stop it and run make again"
        )
    shutil.rmtree(locks[0].parent)  # as `snakemake --unlock` does
    return (
        f"removed the lock an interrupted build left in {directory} (no Snakemake process runs there); "
        "its incomplete outputs are made again (--rerun-incomplete)"
    )


def main(argv: list[str]) -> int:
    if len(argv) > 2:
        print("usage: python workflow/unlock_stale.py [DIRECTORY]", file=sys.stderr)
        return 2
    message = unlock_stale(argv[1] if len(argv) == 2 else ".")
    if message:
        print(f"unlock_stale: {message}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
