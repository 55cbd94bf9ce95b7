"""The benchmarks' report: every speed the project states, and the hard cases' verdict, as rows in
the paper table's format (section, quantity, paper, replication, tolerance, agrees, command).

Why a module of its own: a wall-clock ratio changes from build to build and with the machine's
load, so no speed is stated in the paper-vs-replication table (which two builds must give alike);
the benchmarks tier (rule benchmarks_report) states them here, each with the table it comes from.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["benchmark_rows", "report_markdown"]


def _finite(v) -> bool:
    try:
        return bool(np.isfinite(float(v)))
    except (TypeError, ValueError):
        return False


def _scipy_speed(head: list[dict]) -> str:
    """Core against the fastest SciPy solver at each headline error level, per scene."""
    parts = []
    for h in head:
        if h["metric"] != "impact_time_error":
            continue
        where = f"{h['scene']} at {h['error_level']:g} s"
        if _finite(h["speedup"]):
            parts.append(f"{where}: {float(h['speedup']):.0f}x {h['best_scipy']}")
        elif _finite(h.get("speedup_at_least", math.nan)):
            parts.append(f"{where}: > {float(h['speedup_at_least']):.0f}x (SciPy stopped by the time budget)")
    return "; ".join(parts) or "no error level reached by both"


def _peer_speed(core_head: list[dict]) -> tuple[str, str]:
    """The core against the fastest compiled peer at the headline error (benchmark_core), and its verdict."""
    by_role = {r["role"]: r for r in core_head}
    core, peer = by_role.get("core"), by_role.get("fastest compiled peer")
    if not core or not _finite(core.get("wall_time")):
        return "the core reached no run within the error bound", "no"
    text = f"core {float(core['wall_time']):.3f} s at rtol {float(core['rtol']):g}"
    if peer and _finite(peer.get("wall_time")):
        ratio = float(peer["wall_time"]) / float(core["wall_time"])
        text += f"; {peer['solver']} {float(peer['wall_time']):.3f} s at rtol {float(peer['rtol']):g}: {ratio:.2f}x the core's time"
        return text, "yes" if ratio >= 1.0 else "no"
    return text + "; no compiled peer within the error bound (peers extra not installed?)", "n.a."


def _piece_shares(pieces: list[dict]) -> str:
    """This core's time per forcing period and each piece's share of it (benchmark_pieces)."""
    label = pieces[0]["core"] if pieces else None
    rows = [r for r in pieces if r["core"] == label]
    by_piece = {r["piece"]: r for r in rows}
    core, total = by_piece.get("core"), by_piece.get("sum of the pieces")
    if core is None or total is None:
        return "not measured"
    shares = "; ".join(
        f"{r['piece']} {float(r['us_per_period']):.1f} us ({float(r['share']):.0%})"
        for r in rows
        if r["piece"] not in ("core", "sum of the pieces") and _finite(r.get("share")) and float(r["share"]) >= 0.005
    )
    return (
        f"over {float(core['t_end']):g} s from rest at rtol {float(core['rtol']):g}: core {float(core['us_per_period']):.1f} us per forcing period; "
        f"its pieces replayed: {shares}; "
        f"their sum {float(total['us_per_period']):.1f} us"
    )


def benchmark_rows(
    wp_head: list[dict], core_head: list[dict], hard: list[dict], command: str, pieces: list[dict] = ()
) -> list[dict]:
    """Rows of the benchmarks' report from the work-precision headline (``wp_head``), the core
    benchmark's headline (``core_head``), the hard-case table (``hard``) and the piece-by-piece
    breakdown (``pieces``, benchmark_pieces' table)."""
    bound = next((float(r["max_error"]) for r in core_head if _finite(r.get("max_error"))), math.nan)
    peer_text, peer_ok = _peer_speed(core_head)
    failed = [r for r in hard if r["passed"] in (False, "no")]
    return [
        {
            "section": "2.2 (numerics)",
            "quantity": "speed at equal impact-time error, core vs the fastest SciPy solver",
            "paper": "not stated",
            "replication": _scipy_speed(wp_head),
            "tolerance": "n.a. (wall-clock ratios: they vary between builds and machines)",
            "agrees": "n.a.",
            "command": command,
        },
        {
            "section": "2.2 (numerics)",
            "quantity": "speed at equal impact-time error, core vs the fastest compiled peer (chaotic scene, 500 s)",
            "paper": "not stated",
            "replication": peer_text,
            "tolerance": f"impact-time error <= {bound:g} s over the first 1.5 s; the core at least as fast",
            "agrees": peer_ok,
            "command": command,
        },
        {
            "section": "2.2 (numerics)",
            "quantity": "where the core's time goes per forcing period, by kind of piece (chaotic scene)",
            "paper": "not stated",
            "replication": _piece_shares(list(pieces)),
            "tolerance": "n.a. (wall-clock times: results/<study>/tables/benchmark/benchmark_pieces.md)",
            "agrees": "n.a.",
            "command": command,
        },
        {
            "section": "numerics",
            "quantity": "hard cases: grazing, chattering, sticking, stiff friction, long runs",
            "paper": "not stated",
            "replication": f"{len(hard) - len(failed)} of {len(hard)} checks passed"
            + (": failed " + "; ".join(str(r["check"]) for r in failed) if failed else ""),
            "tolerance": "every check within its bound (results/<study>/tables/work_precision/hard_cases.csv)",
            "agrees": "yes" if not failed else "no",
            "command": command,
        },
    ]


def report_markdown(rows: list[dict], table: str) -> str:
    """The report's page: what it is, then the rows (``table``: the rows as a Markdown table)."""
    return (
        "# Benchmarks\n\n"
        "Every speed the workflow measures, with the table it comes from, and the hard cases' verdict. "
        "Wall-clock ratios vary between builds and with the machine's load: compare them within one build.\n\n" + table
    )
