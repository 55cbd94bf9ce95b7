"""The chaotic train's statistics against the core's tolerance: for a chaotic attractor the
trajectory cannot converge in tolerance, its statistics must; they are compared with the
spread of an ensemble of realisations (other tolerances and starts), in standard deviations.
The verdict makes many tests at once (every statistic and window at every tolerance), so it
allows for their number: Holm's step-down over the z-scores' two-sided p-values
(:mod:`impactosc.statistics.multiple_testing`) at the level of one 3-sd test.
The work of each run is its count of right-hand-side evaluations, not a wall time: the paper's table
cites this check, and a table that cites no timing gives the same numbers on every build."""

from __future__ import annotations

import math

import numpy as np

from impactosc.core.simulation import simulate, warm_up
from impactosc.model.parameters import ModelParams
from impactosc.statistics.impact_train import ImpactTrain
from impactosc.statistics.multiple_testing import THREE_SD_LEVEL, holm, two_sided_p
from impactosc.statistics.train_analysis import analyse_train, key_numbers

STAT_KEYS = ("n_impacts", "cv2_paper", "cv2", "isi_first_maximum", "isi_last_maximum")


def train_statistics(times, t_start, t_stop, omega, options=None) -> dict:
    """The numbers the chaotic group reports (impactosc.statistics.train_analysis): counts, C_V^2, maxima."""
    train = ImpactTrain(times, t_start, t_stop, omega=omega)
    k = key_numbers(analyse_train(train, options, parts=("stationarity", "variability", "isi_density")))
    return {
        "n_impacts": k["n_impacts"],
        "window_counts": k["window_counts"],
        "cv2_paper": k["cv2_paper"],
        "cv2": k["cv2"],
        "isi_first_maximum": k["isi_first_maximum"],
        "isi_last_maximum": k["isi_last_maximum"],
    }


def statistics_convergence(
    omega,
    transient,
    duration,
    rtols,
    atol_ratio,
    ensemble_x0,
    ensemble_rtol,
    params: ModelParams,
    options=None,
    log=print,
) -> list[dict]:
    """The chaotic scene's statistics at each tolerance, and an ensemble that fixes their
    converged value and spread: runs at `ensemble_rtol` from the perturbed starts x(0) in
    `ensemble_x0` (each an independent realisation of the attractor).
    """
    warm_up()
    rows = []
    runs = [("sweep", r, 0.0) for r in rtols] + [("ensemble", ensemble_rtol, x0) for x0 in ensemble_x0]
    for kind, rtol, x0 in runs:
        res = simulate(
            omega, transient, duration, x0=x0, params=params, rtol=rtol, atol=rtol * atol_ratio, record=("impacts",)
        )
        s = train_statistics(res.events["impacts"]["t"], transient, transient + duration, omega, options)
        rows.append(
            {
                "kind": kind,
                "rtol": rtol,
                "atol": rtol * atol_ratio,
                "x0": x0,
                "rhs_evals": res.attrs["n_rhs"],
                **s,
            }
        )
        log(
            f"statistics {kind} rtol {rtol:g} x0 {x0:g}: {res.attrs['n_rhs']} RHS evaluations, {s['n_impacts']} impacts, "
            f"C_V^2 {s['cv2_paper']:.4f} s"
        )
    return rows


def zscores(stats: dict, ensemble: list[dict]) -> dict:
    """(value - ensemble mean) / ensemble std for each statistic in STAT_KEYS, and for the
    window counts the largest |z| over the windows against the pooled ensemble windows
    (the train is stationary, so every window shares one distribution; pooling gives a
    far steadier spread than per-window estimates from a dozen runs)."""
    if len(ensemble) < 3:
        raise ValueError(f"the ensemble needs >= 3 runs for a spread, got {len(ensemble)}")
    z = {}
    for k in STAT_KEYS:
        vals = np.array([e[k] for e in ensemble], float)
        sd = vals.std(ddof=1)
        z[k] = (stats[k] - vals.mean()) / sd if sd > 0 else math.nan
    wc = np.concatenate([np.asarray(e["window_counts"], float) for e in ensemble])
    z["window_counts"] = float(np.max(np.abs(np.asarray(stats["window_counts"], float) - wc.mean()) / wc.std(ddof=1)))
    return z


def window_zscores(stats: dict, ensemble: list[dict]) -> np.ndarray:
    """z of each window count against the pooled ensemble windows (see :func:`zscores`)."""
    wc = np.concatenate([np.asarray(e["window_counts"], float) for e in ensemble])
    return (np.asarray(stats["window_counts"], float) - wc.mean()) / wc.std(ddof=1)


def statistics_summary(rows: list[dict], alpha: float = THREE_SD_LEVEL) -> list[dict]:
    """Each sweep row against the ensemble: z-scores (see :func:`zscores`) and whether the
    statistics have converged to within the sampling noise.

    Why Holm: the verdict tests every statistic and every window count at every tolerance
    (12 tolerances x 10 numbers in the paper's config); at 3 sd each, one |z| > 3 among them
    comes up by chance in a clean sweep about a quarter of the time. The z-scores' two-sided
    normal p-values go through Holm's step-down together, at the family-wise level ``alpha``
    (default: that of one 3-sd test, 0.0027); a tolerance has converged when none of its tests
    is rejected. ``n_tests`` is the family's size, ``holm_p`` the smallest adjusted p-value of the row.
    """
    ens = [r for r in rows if r["kind"] == "ensemble"]
    if len(ens) < 3:
        raise ValueError(f"the ensemble needs >= 3 runs for a spread, got {len(ens)}")
    mean = {k: float(np.mean([r[k] for r in ens])) for k in STAT_KEYS}
    std = {k: float(np.std([r[k] for r in ens], ddof=1)) for k in STAT_KEYS}
    sweep = [r for r in rows if r["kind"] == "sweep"]
    z = [zscores(r, ens) for r in sweep]
    # the family: each statistic and each window count of every sweep row (a z without a spread,
    # NaN, is no test)
    family = [np.array([zi[k] for k in STAT_KEYS] + list(window_zscores(r, ens))) for r, zi in zip(sweep, z)]
    flat = np.concatenate(family)
    tested = np.isfinite(flat)
    verdict = holm(two_sided_p(flat[tested]), alpha)
    adjusted = np.full(flat.size, np.nan)
    adjusted[tested] = verdict.adjusted
    rejected = np.zeros(flat.size, bool)
    rejected[tested] = verdict.rejected
    bounds = np.cumsum([0] + [f.size for f in family])
    out = []
    for i, (r, zi) in enumerate(zip(sweep, z)):
        part = slice(bounds[i], bounds[i + 1])
        out.append(
            {
                "rtol": r["rtol"],
                "rhs_evals": r["rhs_evals"],
                **{k: r[k] for k in STAT_KEYS},
                **{f"z_{k}": v for k, v in zi.items()},
                "max_abs_z": float(np.nanmax(np.abs(family[i]))),
                "holm_p": float(np.nanmin(adjusted[part])),
                "n_tests": verdict.n_tests,
                "family_level": alpha,
                "converged": not bool(rejected[part].any()),
                **{f"ensemble_mean_{k}": mean[k] for k in STAT_KEYS},
                **{f"ensemble_std_{k}": std[k] for k in STAT_KEYS},
            }
        )
    return out
