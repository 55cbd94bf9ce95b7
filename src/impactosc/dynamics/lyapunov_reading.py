"""What the largest Lyapunov exponent says at each w of a sweep, against the period the sweep's
reading detected there.

Why: the sweep names a w periodic when its Poincare points repeat, and non-periodic otherwise;
lambda1 < 0 (a stable orbit) or > 0 (chaos) says the same thing independently. The two must
agree except within a grid step of a bifurcation, where lambda1 passes through zero and a
finite run of either kind is not settled.
"""

from __future__ import annotations

import math

__all__ = ["sign_agreement", "summarise_agreement"]


def sign_agreement(per_w: list[dict], lambda1: dict, transitions: list[float], grid_step: float) -> list[dict]:
    """One row per w of the sweep's reading (rows of bifurcation_per_w.csv for one sweep; period
    0 = non-periodic), with lambda1 (per period, `lambda1[w]`) and the verdict: "agrees",
    "near a transition" (disagrees within one grid step of a sweep transition), "disagrees", or
    "no exponent" (an abandoned w)."""
    rows = []
    for r in per_w:
        w, period = float(r["omega"]), int(r["period"])
        lam = lambda1.get(round(w, 6), math.nan)
        if not math.isfinite(lam):
            verdict = "no exponent"
        elif (lam < 0) == (period > 0):
            verdict = "agrees"
        elif any(abs(w - t) <= grid_step * (1 + 1e-9) for t in transitions):
            verdict = "near a transition"
        else:
            verdict = "disagrees"
        rows.append({"omega": w, "period": period, "lambda1_per_period": lam, "verdict": verdict})
    return rows


def summarise_agreement(rows: list[dict]) -> dict:
    """Counts of each verdict, and the w values where the two disagree away from a transition."""
    counts = {}
    for r in rows:
        counts[r["verdict"]] = counts.get(r["verdict"], 0) + 1
    return {"counts": counts, "disagree_at": [r["omega"] for r in rows if r["verdict"] == "disagrees"]}
