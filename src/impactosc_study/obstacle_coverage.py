"""Does the obstacle estimate's stated sigma cover the truth?  A Monte-Carlo over record
segments and noise draws.

Why: :func:`impactosc.records.obstacle_estimate.estimate_x_impact` states a 1-sigma uncertainty from
the fit covariance.  A covariance assumes the fit is unbiased and the residuals white; whether
that holds at a given noise level is a question for repeated draws with a known truth, not for
one record.  A clean surrogate record of the chaotic attractor is cut into segments, white
noise of several seeds is added to each, and every (segment, seed) draw is estimated: the mean
error against its standard error says whether there is a bias, the fractions within 1 and 2
stated sigma whether the sigma is honest (68 % and 95 % if it is).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.model.parameters import ModelParams
from impactosc.records.obstacle_estimate import estimate_x_impact
from impactosc.records.record import Record
from impactosc.records.surrogate import SurrogateOptions, surrogate_record

__all__ = ["coverage_summary", "x_impact_draws"]


def x_impact_draws(
    noise,
    *,
    omega=40.86,
    transient=100.0,
    duration=360.0,
    segment=60.0,
    seeds=5,
    rate=2000.0,
    mismatch=None,
    params: ModelParams | None = None,
    seed_base=7000,
    exponent=1.5,
    rtol=1e-10,
    atol=1e-12,
    progress=None,
) -> list[dict]:
    """One draw per (segment, seed): the estimate's error against the surrogate's x_impact and
    its stated sigma.  The record is simulated once without noise (``duration`` s after
    ``transient``, cut into ``segment`` s pieces); draw (k, s) adds noise of std ``noise`` from
    seed ``seed_base + 100 k + s``.  ``exponent``: the contact exponent of the fit (1.5, or None:
    fitted).  ``progress(i, n, row)``, if given, is called after each."""
    if not (noise > 0 and segment > 0 and duration >= segment and seeds >= 1):
        raise ValueError(
            f"need noise > 0 m, 0 < segment <= duration s and seeds >= 1; got {noise}, {segment}, {duration}, {seeds}"
        )
    base = SurrogateOptions(rate=float(rate), noise=0.0, mismatch=mismatch or {})
    rec, _ = surrogate_record(omega, transient, duration, base, params=params, rtol=rtol, atol=atol)
    x_true = float(rec.meta["x_impact"])
    n = int(round(segment * rate))
    n_seg = rec.t.size // n
    rows = []
    for k in range(n_seg):
        t, x = rec.t[k * n : (k + 1) * n], rec.x[k * n : (k + 1) * n]
        for s in range(int(seeds)):
            rng = np.random.default_rng(seed_base + 100 * k + s)
            part = Record(t, x + rng.normal(0.0, noise, x.size), float(omega), {}, f"<segment {k}, seed {s}>")
            est, det = estimate_x_impact(part, exponent=exponent)
            rows.append(
                {
                    "noise_m": float(noise),
                    "exponent": "free" if exponent is None else float(exponent),
                    "segment": k,
                    "seed": s,
                    "t_start": float(t[0]),
                    "error_m": est - x_true,
                    "sigma_m": det["sigma"],
                    "n_windows": det["n_windows"],
                }
            )
            if progress:
                progress(len(rows), n_seg * int(seeds), rows[-1])
    return rows


def coverage_summary(rows: list[dict]) -> dict:
    """Bias and coverage of a list of draws (one noise level): mean error and its standard
    error, sd of the errors against the median stated sigma, counts within 1 and 2 sigma, the
    largest |error|, and the between-segment sd of the segment means (a bias that depends on the
    record, not on the draw, would make it exceed the within-segment expectation)."""
    e = np.array([r["error_m"] for r in rows])
    s = np.array([r["sigma_m"] for r in rows])
    seg = np.array([r["segment"] for r in rows])
    n = e.size
    sd = float(np.std(e, ddof=1)) if n > 1 else float("nan")
    means = np.array([e[seg == k].mean() for k in np.unique(seg)])
    per_seg = n / means.size
    return {
        "noise_m": float(rows[0]["noise_m"]),
        "exponent": rows[0].get("exponent", 1.5),
        "n_draws": n,
        "n_segments": int(means.size),
        "mean_error_m": float(e.mean()),
        "mean_error_se_m": sd / math.sqrt(n),
        "sd_error_m": sd,
        "median_sigma_m": float(np.median(s)),
        "within_1_sigma": int(np.sum(np.abs(e) < s)),
        "within_2_sigma": int(np.sum(np.abs(e) < 2 * s)),
        "max_abs_error_m": float(np.max(np.abs(e))),
        "segment_means_sd_m": float(np.std(means, ddof=1)) if means.size > 1 else float("nan"),
        "segment_means_sd_expected_m": sd / math.sqrt(per_seg),
    }
