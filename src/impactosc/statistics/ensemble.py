"""The ensemble of realisations of the chaotic attractor: which re-runs, and the spread of their numbers.

Why: a chaotic train reproduces statistics, not exact counts. Runs of the chaos scene that
differ only in tolerance or initial state are independent realisations; the spread of
their key numbers (:func:`impactosc.statistics.train_analysis.ensemble_members`) is the
uncertainty every number compared with the paper is judged against. Plain dicts in and
out, so the workflow plans the runs (:func:`ensemble_runs`) before any exists.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

__all__ = ["ensemble_runs", "ensemble_summary", "ensemble_table"]


def ensemble_runs(scene: dict, solver: dict, ensemble: dict) -> dict:
    """Re-runs of a scene that differ only in tolerance or x(0): name -> rtol, atol, x0.

    Why: each is an independent realisation of the attractor (a chaotic trajectory
    decorrelates within seconds), so together they measure the realisation spread.  atol
    is scaled with rtol in the solver's ratio; names are unique and file-name safe.

    Parameters
    ----------
    scene : dict
        Scene config (uses ``x0``, default 0).
    solver : dict
        ``rtol`` and ``atol`` of the scene run.
    ensemble : dict
        ``rtol`` (list of tolerances) and ``x0`` (list of initial displacements, m).
    """
    ratio = solver["atol"] / solver["rtol"]
    runs = {}
    for rtol in ensemble.get("rtol", []):
        runs[f"rtol{rtol:.0e}"] = {"rtol": rtol, "atol": rtol * ratio, "x0": scene.get("x0", 0.0)}
    for x0 in ensemble.get("x0", []):
        runs[f"x0{x0:+.1e}"] = {"rtol": solver["rtol"], "atol": solver["atol"], "x0": x0}
    n = len(ensemble.get("rtol", [])) + len(ensemble.get("x0", []))
    if len(runs) != n:
        raise ValueError("ensemble tolerances or initial states repeat (after rounding to names)")
    return runs


def ensemble_table(members: dict) -> list[dict]:
    """One row per ensemble member for a CSV (lists joined by spaces)."""
    rows = []
    for name, k in members.items():
        row = {"run": name}
        for key, v in k.items():
            row[key] = " ".join(str(x) for x in v) if isinstance(v, list) else v
        rows.append(row)
    return rows


def ensemble_summary(members: dict) -> dict:
    """Spread of key numbers over realisations of the same attractor.

    Why: a chaotic train reproduces statistics, not exact counts; runs that differ only
    in tolerance or initial state are independent realisations, and their spread is the
    honest uncertainty of every number compared with the paper.

    Parameters
    ----------
    members : dict of str -> dict
        Member name -> :func:`key_numbers` output (at least 2 members).

    Returns
    -------
    dict
        ``members`` (as given), ``numeric`` (name -> mean, sd, min, max, n) for scalar
        numbers (run settings ``rtol`` and ``x0`` excluded), ``window_counts`` (all windows pooled: mean, sd) and ``categorical``
        (name -> value counts).
    """
    if len(members) < 2:
        raise ValueError(f"an ensemble needs at least 2 members, got {len(members)}")
    names = sorted({k for m in members.values() for k in m} - {"rtol", "x0"})
    numeric, categorical = {}, {}
    for k in names:
        vals = [m.get(k) for m in members.values() if m.get(k) is not None]
        if not vals or isinstance(vals[0], list):
            continue
        if isinstance(vals[0], str):
            categorical[k] = dict(Counter(vals))
        else:
            a = np.asarray(vals, dtype=float)
            numeric[k] = {
                "mean": float(a.mean()),
                "sd": float(a.std(ddof=1)) if a.size > 1 else 0.0,
                "min": float(a.min()),
                "max": float(a.max()),
                "n": int(a.size),
            }
    out = {"members": members, "numeric": numeric, "categorical": categorical}
    wc = [m["window_counts"] for m in members.values() if "window_counts" in m]
    if wc:
        w = np.asarray(wc, dtype=float).ravel()
        out["window_counts"] = {"mean": float(w.mean()), "sd": float(w.std(ddof=1)), "n": int(w.size)}
    return out
