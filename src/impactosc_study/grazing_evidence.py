"""The paper's grazing claim: the evidence that the attractor followed down in w grazes the
obstacle between the paper's two w values (Figs 3b and 4: 23.05 and 23.03 rad/s).

Why in the study: locating the grazing is the library's (:mod:`impactosc.dynamics.grazing`);
comparing it with the paper's w values, and gathering the workflow's sweep files into the
statistics the figure and the paper-vs-replication rows read, is this study's.
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.dynamics.grazing import extrapolate_gap_zero, find_grazing_step, sweep_summary
from impactosc.dynamics.sweep import load_sweep
from impactosc.io.files import read_json
from impactosc.statistics.periods import poincare_period
from impactosc_study.paper.numbers import GRAZING

__all__ = ["grazing_statistics", "grazing_summary_file"]


def _attractor_at(summary: dict, omega: float, periods=None) -> dict | None:
    w = np.asarray(summary["omega"])
    i = int(np.argmin(np.abs(w - omega)))
    if abs(w[i] - omega) > 1e-9:
        return None
    out = {k: float(np.asarray(summary[k])[i]) for k in ("impacts_per_period", "min_gap", "min_impact_v")}
    if periods is not None:
        out["period"] = int(periods[i])
    return out


def grazing_statistics(
    branch: dict,
    bracket: dict,
    from_rest: dict,
    paper_omegas=GRAZING["omegas"],
    n_fit: int = 5,
    branch_periods=None,
    rest_periods=None,
) -> dict:
    """Everything the grazing claim rests on, as a JSON-ready dict.

    branch / from_rest: per-w summaries (:func:`sweep_summary`), branch in branch order;
    bracket: :meth:`GrazingBracket.to_dict`. Adds the straight-line gap extrapolation, the
    attractor at each paper w on the branch and from rest, where w_g sits relative to the
    paper's w values, and the from-rest grid points on either side of the attractor switch.
    """
    i = find_grazing_step(branch["omega"], branch["min_gap"], branch["impacts_per_period"])
    fit = extrapolate_gap_zero(branch["omega"][: i + 1], branch["min_gap"][: i + 1], n_fit)
    wg = 0.5 * (bracket["omega_miss"] + bracket["omega_contact"])
    ref = float(branch["impacts_per_period"][i])
    pre = float(np.asarray(branch["omega"])[i])
    out = {
        "omega_g": wg,
        "bracket": bracket,
        "branch_step": {
            "omega_miss": pre,
            "omega_contact": float(branch["omega"][i + 1]),
            "impacts_per_period_before": ref,
            "impacts_per_period_after": float(branch["impacts_per_period"][i + 1]),
        },
        "gap_fit": fit.to_dict(),
        "fit_minus_bracket": fit.omega_zero - wg,
        "fit_inside_bracket": bool(
            min(bracket["omega_miss"], bracket["omega_contact"])
            <= fit.omega_zero
            <= max(bracket["omega_miss"], bracket["omega_contact"])
        ),
        "paper_omegas": list(map(float, paper_omegas)),
        "between_paper_omegas": bool(min(paper_omegas) < wg < max(paper_omegas)),
        "branch_at_paper_omegas": {f"{w:g}": _attractor_at(branch, w, branch_periods) for w in paper_omegas},
        "from_rest_at_paper_omegas": {f"{w:g}": _attractor_at(from_rest, w, rest_periods) for w in paper_omegas},
    }
    # from rest: which grid points land on the pre-grazing orbit (ref impacts per period
    # with a near miss) and which on something else
    rw = np.asarray(from_rest["omega"])
    on_pre = np.isclose(np.asarray(from_rest["impacts_per_period"]), ref, atol=1e-9) & np.isfinite(
        np.asarray(from_rest["min_gap"])
    )
    out["from_rest_on_pre_grazing_orbit"] = {"omega": rw[on_pre].tolist(), "other": rw[~on_pre].tolist()}
    return out


def grazing_summary_file(
    branch_path, bisection_path, from_rest_path, paper_omegas=GRAZING["omegas"], n_fit: int = 5
) -> dict:
    """:func:`grazing_statistics` from the workflow's files, plus the per-w arrays to plot.

    Each per-w summary gets the Poincare period of the recorded attractor (forcing
    periods, 0 = none up to half the record: chaotic or unsettled).
    """
    branch, _ = load_sweep(branch_path)
    rest, _ = load_sweep(from_rest_path)
    bracket = read_json(bisection_path)
    summaries = {}
    for name, sweep in (("branch", branch), ("from_rest", rest)):
        s = sweep_summary(sweep)
        s["period"] = np.array([poincare_period(x, v) for x, v in zip(sweep.poincare_x, sweep.poincare_v)])
        summaries[name] = s
    for t in bracket["trials"]:  # JSON null -> NaN
        for k in ("min_gap", "min_impact_v"):
            t[k] = math.nan if t[k] is None else t[k]
    out = grazing_statistics(
        summaries["branch"],
        bracket,
        summaries["from_rest"],
        paper_omegas,
        n_fit,
        summaries["branch"]["period"],
        summaries["from_rest"]["period"],
    )
    out["per_w"] = {name: {k: np.asarray(v).tolist() for k, v in s.items()} for name, s in summaries.items()}
    return out
