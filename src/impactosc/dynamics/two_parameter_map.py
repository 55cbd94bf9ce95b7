"""Two-parameter curves as tables, and the check of the brute-force 2-D map against them.

Why: the map (:mod:`impactosc.dynamics.maps`) reads the attractor's period cell by cell from time
simulations; each curve (:mod:`.two_parameter`) says where an orbit of one type is born or dies.
Where they agree to a grid cell, each confirms the other; a disagreement points at hysteresis
(coexisting attractors: the map's rows follow increasing w from rest) or a transient the map did
not outlast. The curve files are plain data (:func:`.two_parameter.curve_record` plus the job's
start and cost), so this module needs no integration.
"""

from __future__ import annotations

import itertools

import numpy as np

from impactosc.dynamics.orbit_table import KIND_LABELS, multipliers_text

__all__ = [
    "CODIM_COLUMNS",
    "POINT_COLUMNS",
    "SEPARATION_COLUMNS",
    "UNITS",
    "codim_two_rows",
    "curve_crossings",
    "orbit_types",
    "point_rows",
    "separation",
    "summary_rows",
]

UNITS = {"xI": (1e3, "mm"), "m0e": (1e3, "g m")}  # display scale and unit of the second parameter
POINT_COLUMNS = ["curve", "kind", "period", "omega_rad_s", "parameter", "value_si", "x0_m", "v0_m_s", "multipliers",
                 "condition", "impacts", "sticks", "stable"]  # fmt: skip
CODIM_COLUMNS = ["curve", "what", "omega_rad_s", "parameter", "value", "located", "multipliers"]
SEPARATION_COLUMNS = ["check", "curve", "value", "omega", "cells", "ok"]


def curve_crossings(points: list[dict], value: float) -> list[float]:
    """w where a curve (its points in order) crosses the parameter value: linear interpolation
    between neighbouring points on either side of it (a curve that turns crosses more than once)."""
    out = []
    for a, b in itertools.pairwise(points):
        da, db = a["value"] - value, b["value"] - value
        if da == 0:
            out.append(a["omega"])
        elif da * db < 0:
            out.append(a["omega"] + (b["omega"] - a["omega"]) * da / (da - db))
    if points and points[-1]["value"] == value:
        out.append(points[-1]["omega"])
    return out


def orbit_types(curve: dict) -> tuple[tuple[int, int], tuple[int, int] | None]:
    """(period, impacts per orbit) of the orbit the curve bounds, and of the orbit born there (a
    doubling's doubled orbit; None for a fold or a grazing, past which the attractor jumps). The
    impacts are read at the curve's start, a grazing's touch not counted."""
    start = next(p for p in curve["points"] if p["value"] == curve["start"]["value"])
    n, impacts = curve["n_periods"], start["impacts"]
    if curve["kind"] == "grazing" and start.get("graze_gap", 1.0) <= 0:
        impacts -= 1
    child = (2 * n, 2 * impacts) if curve["kind"] == "period_doubling" else None
    return (n, impacts), child


def _cell(period, impacts, i, j) -> tuple[int, int]:
    return int(period[i, j]), int(impacts[i, j])


def _text(cell) -> str:
    p, k = cell
    return {-1: "no result", 0: "non-periodic"}.get(p, f"period {p}, {k} impacts")


def _crossing_sides(curve, parent, omega, values, period, impacts, dw):
    """Per map row and crossing of the curve: (row, w, nearest cell below and above it beyond one
    grid cell, the side where the bounded orbit is: "below", "above" or None if not exactly one)."""
    out = []
    for i, v in enumerate(values):
        for wc in curve_crossings(curve["points"], v):
            below, above = np.flatnonzero(omega < wc - dw), np.flatnonzero(omega > wc + dw)
            if not below.size or not above.size:
                continue  # within a grid cell of the map's edge, or outside it
            lo, hi = _cell(period, impacts, i, below[-1]), _cell(period, impacts, i, above[0])
            side = {(True, False): "below", (False, True): "above"}.get((lo == parent, hi == parent))
            out.append((i, wc, lo, hi, side))
    return out


def _between(curves, types, sides, omega, values, period, impacts, dw) -> list[dict]:
    """Where two curves bound the same orbit from either side in a map row (a grazing and a
    doubling of the orbit; the doubling that creates an orbit and the one that doubles it again),
    every cell between them farther than one grid cell from both is that orbit."""
    rows = []
    for orbit in {t for pair in types.values() for t in pair if t is not None}:
        bounding = [m for m in curves if orbit in types[m]]
        if len(bounding) < 2:
            continue
        for i, v in enumerate(values):
            marks = []  # (w, side of the crossing where the orbit is)
            for m in bounding:
                for row, wc, _, _, side in sides[m]:
                    if row == i and side is not None:
                        marks.append((wc, side if types[m][0] == orbit else {"below": "above", "above": "below"}[side]))
            marks.sort()
            for (wa, sa), (wb, sb) in itertools.pairwise(marks):
                if sa != "above" or sb != "below":
                    continue
                inside = np.flatnonzero((omega > wa + dw) & (omega < wb - dw))
                other = [j for j in inside if _cell(period, impacts, i, j) != orbit]
                rows.append({"check": "between", "curve": " & ".join(bounding), "value": v, "omega": 0.5 * (wa + wb),
                             "cells": f"{len(inside) - len(other)} of {len(inside)} cells {_text(orbit)}"
                             + (f"; not at w = {', '.join(f'{omega[j]:.2f}' for j in other)}" if other else ""),
                             "ok": not other})  # fmt: skip
    return rows


def separation(omega, values, period, impacts, curves: dict) -> list[dict]:
    """The map's cells against the curves (dict name -> curve file), row by row, to one grid
    cell. `sides`: at each crossing of a row, the nearest cells beyond one grid cell have the
    curve's orbit (period, impacts) on exactly one side (a doubling's other side is its doubled
    orbit, or already a later one of the cascade). `between`: where two curves bound one orbit
    from either side, every cell between them beyond one grid cell is that orbit. One row per
    check, with `ok`."""
    omega, values = np.asarray(omega, float), np.asarray(values, float)
    period, impacts = np.asarray(period), np.asarray(impacts)
    if period.shape != (values.size, omega.size) or impacts.shape != period.shape:
        raise ValueError(f"map arrays must be (values, omega) = ({values.size}, {omega.size}), got {period.shape}")
    dw = float(np.median(np.diff(omega))) if omega.size > 1 else 0.0
    types = {name: orbit_types(c) for name, c in curves.items()}
    sides = {name: _crossing_sides(c, types[name][0], omega, values, period, impacts, dw) for name, c in curves.items()}
    rows = [
        {"check": "sides", "curve": name, "value": values[i], "omega": wc, "cells": f"{_text(lo)} | {_text(hi)}",
         "ok": side is not None}
        for name in curves for i, wc, lo, hi, side in sides[name]
    ]  # fmt: skip
    return rows + _between(curves, types, sides, omega, values, period, impacts, dw)


def point_rows(curves: dict) -> list[dict]:
    """One row per curve point (SI units, POINT_COLUMNS), in each curve's order."""
    return [
        {
            "curve": name, "kind": c["kind"], "period": c["n_periods"], "omega_rad_s": p["omega"],
            "parameter": c["parameter"], "value_si": p["value"], "x0_m": p["x0"], "v0_m_s": p["v0"],
            "multipliers": multipliers_text(p["mu_re"], p["mu_im"]), "condition": p["condition"],
            "impacts": p["impacts"], "sticks": p["sticks"], "stable": p["stable"],
        }
        for name, c in curves.items()
        for p in c["points"]
    ]  # fmt: skip


def summary_rows(curves: dict) -> list[dict]:
    """One row per curve: where it starts (beside the one-parameter table's point), how far it
    goes, why it stops, what it meets, what it cost."""
    rows = []
    for name, c in curves.items():
        scale, unit = UNITS[c["parameter"]]
        s, pts = c["start"], c["points"]
        rows.append({
            "curve": name, "kind": KIND_LABELS.get(c["kind"], c["kind"]), "period": c["n_periods"],
            "table_w_rad_s": f"{s['table_omega']:.10f}", "curve_w_rad_s": f"{s['omega']:.10f}",
            "difference_rad_s": f"{s['omega'] - s['table_omega']:+.1e}", "points": len(pts),
            f"{c['parameter']}_range_{unit.replace(' ', '')}": f"{min(p['value'] for p in pts) * scale:.4g} to {max(p['value'] for p in pts) * scale:.4g}",
            "w_range_rad_s": f"{min(p['omega'] for p in pts):.4f} to {max(p['omega'] for p in pts):.4f}",
            "ends": f"{c['stops']['start']}; {c['stops']['end']}", "codim_two": len(c["codim_two"]),
            "cpu_s": f"{c['cpu_seconds']:.1f}",
        })  # fmt: skip
    return rows


def codim_two_rows(curves: dict) -> list[dict]:
    """One row per codimension-two point met on a curve (CODIM_COLUMNS)."""
    rows = []
    for name, c in curves.items():
        scale, unit = UNITS[c["parameter"]]
        for d in c["codim_two"]:
            mu = np.array(d.get("multipliers") or [], float).reshape(-1, 2)
            rows.append({
                "curve": name, "what": d["what"], "omega_rad_s": f"{d['omega']:.8f}",
                "parameter": c["parameter"], "value": f"{d['value'] * scale:.6f} {unit}",
                "located": "yes" if d["located"] else "no (middle of the bracket)",
                "multipliers": multipliers_text(mu[:, 0], mu[:, 1]) if mu.size else "",
            })  # fmt: skip
    return rows
