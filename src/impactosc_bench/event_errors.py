"""Errors of a run's events against a reference run: impact times, penetration depths and
Poincare points, each matched to its nearest counterpart (a missed or invented event costs
its distance to the nearest other), so that every solver is judged on what the paper
extracts, not on its trajectory."""

from __future__ import annotations

import numpy as np

METRICS = ("impact_time_error", "penetration_error", "poincare_x_error")


def _nearest(a, b) -> np.ndarray:
    """For each element of sorted a, the distance to the nearest element of sorted b."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if b.size == 0:
        return np.full(a.size, np.inf)
    j = np.clip(np.searchsorted(b, a), 1, max(b.size - 1, 1))
    lo = np.abs(a - b[j - 1])
    hi = np.abs(a - b[np.minimum(j, b.size - 1)])
    return np.minimum(lo, hi)


def event_errors(run: dict, ref: dict) -> dict:
    """Errors of one run against a reference over the same horizon.

    impact_time_error: the larger of (max over reference impacts of the distance to the
        nearest impact of the run) and the converse, so a missed or an invented impact
        counts as the distance to its nearest neighbour instead of shifting every pair;
    penetration_error: max |H - H_ref| over penetrations paired in order when the counts
        agree, else the deepest unmatched penetration (a whole contact missing);
    poincare_x_error / poincare_v_error: max difference at the common section times.
    """
    ti, tr = run["impacts_t"], ref["impacts_t"]
    if ti.size == 0 and tr.size == 0:
        err_t = 0.0
    else:
        err_t = float(max(_nearest(ti, tr).max(initial=0.0), _nearest(tr, ti).max(initial=0.0)))
    h, hr = run["penetrations_h"], ref["penetrations_h"]
    if h.size == hr.size:
        err_h = float(np.abs(h - hr).max(initial=0.0))
    else:
        err_h = float(max(np.abs(h).max(initial=0.0), np.abs(hr).max(initial=0.0)))
    pt, prt = run["poincare_t"], ref["poincare_t"]
    if pt.size != prt.size or (pt.size and np.abs(pt - prt).max() > 1e-9):
        raise ValueError(f"Poincare sections differ: {pt.size} against {prt.size} reference points")
    return {
        "impact_time_error": err_t,
        "penetration_error": err_h,
        "poincare_x_error": float(np.abs(run["poincare_x"] - ref["poincare_x"]).max(initial=0.0)),
        "poincare_v_error": float(np.abs(run["poincare_v"] - ref["poincare_v"]).max(initial=0.0)),
        "n_impacts": int(ti.size),
        "n_impacts_ref": int(tr.size),
    }


def worst_errors(errs: list[dict]) -> dict:
    """Errors over several starts: the largest of each, impact counts summed."""
    out = {k: max(e[k] for e in errs) for k in (*METRICS, "poincare_v_error")}
    out["n_impacts"] = sum(e["n_impacts"] for e in errs)
    out["n_impacts_ref"] = sum(e["n_impacts_ref"] for e in errs)
    return out
