"""Speed at equal error, from the rows of a work-precision sweep: the least time each solver
needs to be at least as accurate as a level, and the headline ratios (the core against the
fastest SciPy solver and the fastest compiled peer), with a lower bound where the time
budget stopped SciPy's sweeps before the level."""

from __future__ import annotations

import math

from impactosc_bench.wp_solvers import CORE, SCIPY_METHODS, is_peer


def cost_at_error(rows: list[dict], scene: str, solver: str, metric: str, level: float) -> float:
    """Least wall time of any run of `solver` on `scene` whose error is <= level (nan if none).

    A step function on the measured points, not an interpolation: the time one actually
    has to spend to be at least that accurate. A run whose 500 s check left the attractor
    (on_attractor no) does not count.
    """
    walls = [
        r["wall_time"]
        for r in rows
        if r["scene"] == scene
        and r["solver"] == solver
        and r.get("status") == "ok"
        and r.get("on_attractor") not in (False, "no")
        and r[metric] <= level
    ]
    return min(walls) if walls else math.nan


def budget_bound(rows: list[dict], scene: str, solvers) -> float:
    """Least time any of `solvers` would need for an error none of them reached, where the time
    budget stopped sweeps: a solver stopped by it would have needed a tighter tolerance than
    its last point, which costs more, so at least that point's time; a solver that ran its
    whole sweep without reaching the error cannot reach it. nan if no sweep was stopped."""
    lows = []
    for solver in solvers:
        mine = [r for r in rows if r["scene"] == scene and r["solver"] == solver]
        done = [float(r["wall_time"]) for r in mine if r.get("status") == "ok"]
        if done and any(r.get("status") == "skipped" for r in mine):
            lows.append(max(done))
    return min(lows) if lows else math.nan


def _fastest(rows, scene, solvers, metric, level):
    """(costs per solver, the fastest solver or None) at an error level."""
    costs = {s: cost_at_error(rows, scene, s, metric, level) for s in solvers}
    finite = {s: c for s, c in costs.items() if not math.isnan(c)}
    return costs, (min(finite, key=finite.get) if finite else None)


def speed_at_error_headline(rows: list[dict], levels: dict) -> list[dict]:
    """Speed ratio at equal error: the fastest SciPy solver's cost over the core's, and the
    fastest compiled peer's (if any were measured) over the core's.

    levels: metric -> list of error levels. One row per (scene, metric, level).
    """
    out = []
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    solvers = list(dict.fromkeys(r["solver"] for r in rows if r["solver"] in SCIPY_METHODS))
    compiled = list(
        dict.fromkeys(r["solver"] for r in rows if is_peer(str(r["solver"])) and r.get("status") != "unavailable")
    )
    for scene in scenes:
        unc = next(r for r in rows if r["scene"] == scene)
        for metric, lv in levels.items():
            for level in lv:
                core = cost_at_error(rows, scene, CORE, metric, level)
                costs, best = _fastest(rows, scene, solvers, metric, level)
                row = {
                    "scene": scene,
                    "metric": metric,
                    "error_level": level,
                    "reference_uncertainty": unc[f"reference_{metric}"],
                    "core_wall_time": core,
                    "best_scipy": best or "none",
                    "best_scipy_wall_time": costs[best] if best else math.nan,
                    "speedup": costs[best] / core if best and core > 0 else math.nan,
                    "speedup_at_least": (
                        budget_bound(rows, scene, solvers) / core if not best and core > 0 else math.nan
                    ),
                    **{f"{s}_wall_time": c for s, c in costs.items()},
                }
                if compiled:
                    peer_costs, peer = _fastest(rows, scene, compiled, metric, level)
                    row.update(
                        {
                            "best_peer": peer or "none",
                            "best_peer_wall_time": peer_costs[peer] if peer else math.nan,
                            "peer_over_core": peer_costs[peer] / core if peer and core > 0 else math.nan,
                        }
                    )
                out.append(row)
    return out
