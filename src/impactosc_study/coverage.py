"""Are the stated uncertainties honest? Coverage measured on surrogates of known truth.

Two claims are checked here, each by repeated draws with a known truth:

- the obstacle estimate's stated sigma (:func:`x_impact_draws`, :func:`coverage_summary`);
- the identification's standard errors (:func:`identification_draw`, :func:`coverage_table`).

The obstacle estimate
---------------------
Why: :func:`impactosc.records.obstacle_estimate.estimate_x_impact` states a 1-sigma uncertainty from
the fit covariance.  A covariance assumes the fit is unbiased and the residuals white; whether
that holds at a given noise level is a question for repeated draws with a known truth, not for
one record.  A clean surrogate record of the chaotic attractor is cut into segments, white
noise of several seeds is added to each, and every (segment, seed) draw is estimated: the mean
error against its standard error says whether there is a bias, the fractions within 1 and 2
stated sigma whether the sigma is honest (68 % and 95 % if it is).

The identification
------------------
Why: a covariance from the Jacobian assumes the fit is unbiased, the residuals white and the
problem close to linear over the error bars.  Whether that holds for multiple shooting on this
model is a question for repeated draws: each draw takes the stated model's parameters (model BC's
by default, or another contact law's) scaled by random factors within +-``spread`` (m, eps, n1,
n2 kept; a restitution law's loss 1 - e scaled, so that e stays below 1), makes surrogate records
of it (the rig's sampling and noise) at several w, identifies them with the same law, and counts
how often each of the law's quantities lies within 2 stated standard errors of the truth (95 %
if the errors are honest).

Each draw also compares the identified model's Fig 2 branch with the true model's: both are
followed by continuation over the same w grid, and at every w where both are periodic with the
same period their Poincare points (as sets) are compared on the same orbit (where the two
continuations took two coexisting orbits, the identified model is started from the true
model's state); the largest distance is the branch error.  Chaotic w values are counted, not compared point by point (two samples of one chaotic
attractor differ by more than a model error).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from impactosc.identification.fitted_parameters import law_quantities, theta_of
from impactosc.identification.report import write_identified_model
from impactosc.identification.staged_fit import STAGES, identify
from impactosc.model.contact_laws import DEFAULT_LAW, LAWS
from impactosc.model.model_file import read_model_file
from impactosc.model.parameters import ModelParams
from impactosc.records.obstacle_estimate import estimate_x_impact
from impactosc.records.record import Record
from impactosc.records.surrogate import SurrogateOptions, surrogate_record

__all__ = [
    "x_impact_draws",
    "coverage_summary",
    "SCALED_FIELDS",
    "random_truth",
    "identification_draw",
    "branch_distance",
    "coverage_table",
    "coverage_markdown",
]


# ======================================================================== the obstacle estimate
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


# ======================================================================== the identification
#: The Fig 2 branches of the identified and the true model should agree within this (m).
BRANCH_TOL = 10e-6
#: Fields of ModelParams drawn at random (each scaled by a factor in [1 - spread, 1 + spread]).
SCALED_FIELDS = ("m0e", "k", "c", "T", "kI", "b", "n3", "xI")


def random_truth(seed: int, spread: float = 0.3, base: ModelParams | None = None) -> ModelParams:
    """``base`` (default model BC) with each of its law's SCALED_FIELDS, then its e or cI, scaled
    by an independent uniform factor; e through its loss, 1 - e (a factor above 1 would take e
    past 1). Model BC's draws are those of every earlier version (same fields, same order)."""
    base = base or ModelParams()
    rng = np.random.default_rng(seed)
    law = LAWS[base.law]
    fields = [f for f in SCALED_FIELDS if f in law.family]
    values = {f: getattr(base, f) * rng.uniform(1 - spread, 1 + spread) for f in fields}
    for prm in law.parameters:  # the law's own, in its order (a bounded one through its distance to the bound)
        value = getattr(base, prm.name)
        if prm.high < math.inf and not prm.high_open:
            values[prm.name] = prm.high - (prm.high - value) * rng.uniform(1 - spread, 1 + spread)
        else:
            values[prm.name] = value * rng.uniform(1 - spread, 1 + spread)
    return dataclasses.replace(base, **values)


def _section_state(sweep, i: int) -> tuple:
    """A section state of the attractor at w number i: the last Poincare point, or inside a
    restitution contact the run's end (one period later, on the same orbit), whose onset
    velocity the sweep keeps."""
    if math.isfinite(sweep.contact_v0_end[i]):
        return sweep.x_end[i], sweep.v_end[i], sweep.contact_v0_end[i]
    return sweep.poincare_x[i, -1], sweep.poincare_v[i, -1]


def _orbit_from(params: ModelParams, omega: float, state, period: int, n_transient: int) -> np.ndarray:
    """The sorted Poincare points of the period-``period`` orbit that ``params`` reaches from the
    section state ``state`` (x, v, and a contact's v0 inside one) after ``n_transient`` periods."""
    from impactosc.core.simulation import simulate, start_of

    t_period = 2 * math.pi / omega
    r = simulate(
        omega, n_transient * t_period, 2 * period * t_period, **start_of(state), params=params, record=("poincare",)
    )
    return np.sort(r.events["poincare"]["x"][-period:])


def branch_distance(truth: ModelParams, model: ModelParams, omegas, *, n_transient=100, n_record=32, n_initial=300):
    """Fig 2 branches of two models over ``omegas`` (increasing continuation from rest).

    At the w values where both are periodic with the same period the Poincare point sets are
    compared. Where they differ by more than BRANCH_TOL the two continuations may have landed
    on two coexisting orbits of that period (one each): the identified model is then started
    from the true model's section state, and the distance is taken on the orbit it reaches
    (the same orbit, followed from the same state). Such a w is counted as coexisting when the
    true model, started from the identified model's state, reaches that model's orbit too
    (both models have both orbits).

    Returns the largest distance (m) on the same orbit, the largest distance between the two
    continuations as they ran, how many w are compared, at how many of them the distance on
    the same orbit still exceeds BRANCH_TOL, at how many two coexisting orbits were taken, how
    many are non-periodic in both, and how many differ in kind or period.
    """
    from impactosc.dynamics.diagram import classify_sweep
    from impactosc.dynamics.sweep import SweepSettings, continuation

    sweeps = [
        continuation(omegas, SweepSettings(n_transient=n_transient, n_record=n_record, n_initial=n_initial, params=p))
        for p in (truth, model)
    ]
    tables = [classify_sweep(s) for s in sweeps]
    worst, worst_as_run, same, chaotic, differ, far, coexisting = 0.0, 0.0, 0, 0, 0, 0, 0
    for i, w in enumerate(omegas):
        pa, pb = int(tables[0].period[i]), int(tables[1].period[i])
        if pa > 0 and pa == pb:
            xa = np.sort(sweeps[0].poincare_x[i, -pa:])
            xb = np.sort(sweeps[1].poincare_x[i, -pb:])
            dist = float(np.max(np.abs(xa - xb)))
            worst_as_run = max(worst_as_run, dist)
            if dist > BRANCH_TOL:
                on_a = _orbit_from(model, w, _section_state(sweeps[0], i), pa, 4 * n_transient)
                on_b = _orbit_from(truth, w, _section_state(sweeps[1], i), pa, 4 * n_transient)
                coexisting += int(np.max(np.abs(on_b - xb)) <= BRANCH_TOL)
                dist = float(np.max(np.abs(on_a - xa)))
            worst = max(worst, dist)
            far += int(dist > BRANCH_TOL)
            same += 1
        elif pa == 0 and pb == 0:
            chaotic += 1
        else:
            differ += 1
    return {
        "branch_max_m": worst,
        "branch_max_as_run_m": worst_as_run,
        "branch_periodic_w": same,
        "branch_w_beyond_tol": far,
        "branch_coexisting_w": coexisting,
        "branch_nonperiodic_w": chaotic,
        "branch_differ_w": differ,
    }


def identification_draw(
    seed: int,
    *,
    omegas=(23.03, 31.0, 40.86),
    duration=60.0,
    transient=60.0,
    rate=2000.0,
    noise=5e-6,
    spread=0.3,
    branch_omegas=None,
    base: ModelParams | None = None,
    stages=STAGES,
    progress=None,
) -> dict:
    """One draw: random truth around ``base`` (default model BC), surrogate records at ``omegas``,
    identification with base's law and ``stages``, errors in standard errors per quantity of the
    law, and (with ``branch_omegas``) the Fig 2 branch comparison."""
    base = base or ModelParams()
    truth = random_truth(seed, spread, base)
    records = [
        surrogate_record(
            w, transient, duration, SurrogateOptions(rate=rate, noise=noise, seed=1000 * seed + i), params=truth
        )[0]
        for i, w in enumerate(omegas)
    ]
    ident = identify(records, base=base, stages=tuple(stages), progress=progress)
    th = theta_of(truth)
    row = {
        "seed": int(seed),
        "law": truth.law,
        "seconds": ident.seconds,
        "noise_fit_m": ident.noise,
        "converged": ident.fit.converged,
    }
    names = law_quantities(truth.law)
    for i, nm in enumerate(names):
        se = ident.stderr[i]
        row[f"{nm}_true"] = float(th[i])
        row[f"{nm}_fit"] = float(ident.theta[i])
        row[f"{nm}_se"] = float(se)
        row[f"{nm}_z"] = float((ident.theta[i] - th[i]) / se) if ident.free[i] and se > 0 else math.nan
    row["all_within_2se"] = bool(all(abs(row[f"{nm}_z"]) <= 2 for nm in names if math.isfinite(row[f"{nm}_z"])))
    row.update(covariance_as_written(ident))
    if branch_omegas is not None:
        row.update(branch_distance(truth, ident.params, branch_omegas))
    return row


def covariance_as_written(ident) -> dict:
    """Whether the covariance a user reads back from the model file of ``ident`` is positive
    definite (what the delta method needs), and the smallest eigenvalue of its correlation (how
    close to singular the fit is)."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        path = write_identified_model(Path(folder) / "model.yaml", ident)
        try:
            _names, _units, cov = read_model_file(path).covariance
        except ValueError as exc:
            return {"covariance_pd": False, "covariance_error": str(exc), "correlation_min_eig": math.nan}
    d = np.sqrt(np.diag(cov))
    return {
        "covariance_pd": True,
        "covariance_error": "",
        "correlation_min_eig": float(np.linalg.eigvalsh(cov / np.outer(d, d))[0]),
    }


def draws_law(rows: list[dict]) -> str:
    """The contact law of the draws (one per table; rows without one are model BC's)."""
    laws = {r.get("law", DEFAULT_LAW) for r in rows}
    if len(laws) != 1:
        raise ValueError(f"coverage draws of several contact laws ({', '.join(sorted(laws))}): one table per law")
    return laws.pop()


def coverage_table(rows: list[dict]) -> list[dict]:
    """Per quantity of the draws' law: draws, how many within 1 and 2 standard errors, mean and
    sd of the errors in standard errors (0 and 1 if honest), median relative standard error."""
    out = []
    for nm in law_quantities(draws_law(rows)):
        z = np.array([r[f"{nm}_z"] for r in rows], dtype=float)
        z = z[np.isfinite(z)]
        rel = np.array([r[f"{nm}_se"] / abs(r[f"{nm}_true"]) for r in rows if r[f"{nm}_true"] != 0])
        out.append(
            {
                "parameter": nm,
                "draws": int(z.size),
                "within_1se": int(np.sum(np.abs(z) <= 1)),
                "within_2se": int(np.sum(np.abs(z) <= 2)),
                "fraction_within_2se": float(np.mean(np.abs(z) <= 2)) if z.size else math.nan,
                "mean_z": float(np.mean(z)) if z.size else math.nan,
                "sd_z": float(np.std(z, ddof=1)) if z.size > 1 else math.nan,
                "median_relative_se": float(np.median(rel)) if rel.size else math.nan,
            }
        )
    return out


def _covariance_line(draws: list[dict]) -> list[str]:
    """What the draws' model files say of their covariance, as read back by a user."""
    rows = [d for d in draws if "covariance_pd" in d]
    if not rows:
        return []
    pd = sum(bool(d["covariance_pd"]) for d in rows)
    eig = [d["correlation_min_eig"] for d in rows if d["covariance_pd"]]
    smallest = f"; smallest eigenvalue of its correlation {min(eig):.2e} (median {np.median(eig):.2e})" if eig else ""
    return [
        f"The covariance read back from each draw's model file is symmetric positive definite in {pd}/{len(rows)} "
        f"draws{smallest}.",
        "",
    ]


def coverage_markdown(table: list[dict], draws: list[dict]) -> str:
    """The coverage table and the Fig 2 branch comparison as Markdown."""
    n = len(draws)
    joint = sum(bool(d["all_within_2se"]) for d in draws)
    law = draws_law(draws)
    model = "model BC" if law == DEFAULT_LAW else f"the {law} contact law's model"
    lines = [
        f"# Identification coverage: random truths within the configured spread of {model}",
        "",
        f"{n} draws; every quantity within 2 stated standard errors at once in {joint}/{n} draws "
        f"(for {len(table)} independent quantities at 95.4 % each that is expected in about "
        f"{0.9545 ** len(table):.0%}).",
        "",
        *_covariance_line(draws),
        "| parameter | within 1 se | within 2 se | mean z | sd z | median relative se |",
        "|---|---|---|---|---|---|",
    ]
    lines += [
        f"| {r['parameter']} | {r['within_1se']}/{r['draws']} | {r['within_2se']}/{r['draws']} | "
        f"{r['mean_z']:+.2f} | {r['sd_z']:.2f} | {r['median_relative_se']:.2e} |"
        for r in table
    ]
    br = [d for d in draws if "branch_max_m" in d]
    if br:
        n_w = sum(d["branch_periodic_w"] for d in br)
        beyond = sum(d["branch_w_beyond_tol"] for d in br)
        coexisting = sum(d.get("branch_coexisting_w", 0) for d in br)
        med = sorted(d["branch_max_m"] for d in br)[len(br) // 2]
        lines += [
            "",
            f"Fig 2 branch (increasing continuation from rest, identified vs true model): at the {n_w} w of "
            f"{len(br)} draws where both are periodic with the same period, the Poincare points on the same "
            f"orbit differ by more than {BRANCH_TOL * 1e6:g} um at {beyond}; the largest difference per draw "
            f"has median {med * 1e6:.2f} um, maximum {max(d['branch_max_m'] for d in br) * 1e6:.2f} um. At "
            f"{coexisting} w the two continuations took two coexisting orbits of the same period (each model "
            "has both; the distance there is taken from the same start). w where the two differ in kind or "
            f"period: at most {max(d['branch_differ_w'] for d in br)} per draw.",
        ]
    return "\n".join(lines) + "\n"
