"""Which contact law and friction the records support: the laws compared out of sample.

Why these candidates: every contact law of :mod:`impactosc.model.contact_laws` is a member of
model BC's family, each fitted with its own free constants: model BC's b and n3, Hertz none, a
restitution law its e, Kelvin-Voigt its damping cI (its stiffness linear, n1 = 1).  The four
restitution laws are one force, kI h^n1 (1 + g(e) v / v0), whose damping g(e) = chi v0 differs
only in how it is written in e (Hunt-Crossley 3 (1 - e) / 2, Lankarani-Nikravesh 3 (1 - e^2) / 4,
Flores 8 (1 - e) / (5 e), Gonthier (1 - e^2) / e): no record can tell them apart where their
ranges of g overlap, and fitting each would rank identical forces by the noise of their fits.
So one is fitted, Flores (with Gonthier's, the range of every g >= 0), and its row states the e
of each other restitution law that gives the same force, or that the law cannot reach it
(Hunt-Crossley's g stays below 3/2, Lankarani-Nikravesh's below 3/4).  Dry friction T acts in
free flight, the contact law at impacts: whether the records need it is asked once, of the
richest law (model BC's).  Each candidate is fitted to the same windows; two yardsticks say
which the data support:

* prediction error on held-out windows (every ``every``-th block of the records, never fitted:
  only their start states are, with the candidate's parameters), the direct test of a model;
* AIC and BIC of the fit, N ln(RSS / N) + penalty x free parameters, on the samples every
  candidate fitted: each fit cuts its windows at its own obstacle estimate and leaves out the
  windows it fits far worse than the rest, so the candidates' own samples differ, and criteria
  of different samples do not compare.  The residuals are summed in blocks of
  :data:`BLOCK` samples of each record; the blocks every candidate covered whole are the common
  samples (the start states, two per chain of windows, are alike for every candidate there).

The supported model is the one with the smallest BIC: a larger model whose extra parameter the
records do not need pays ln N per parameter, so the true nested law (Hertz inside the others)
wins when it is the simpler one, and the held-out errors say whether the winner also predicts best.

A candidate whose fit fails (:data:`FIT_FAILURES`: a singular system, the core stopped, a start
value its law refuses) is a row that says so and why, and is neither ranked nor chosen: a wrong
law the records reject can break its own fit, and that answers the question as well as a poor
fit would; the other candidates and the identification stand.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from impactosc.core.simulation import StallError
from impactosc.identification.fitted_parameters import QUANTITIES
from impactosc.identification.least_squares import fit_states
from impactosc.identification.staged_fit import STAGES, identify
from impactosc.identification.start import for_law, start_values
from impactosc.identification.window_predictions import Predictor
from impactosc.identification.windows import cut_windows, split_held_out
from impactosc.model.contact_laws import DEFAULT_LAW, LAWS, RestitutionLaw
from impactosc.model.parameters import ModelParams, UntestedParameterWarning

__all__ = [
    "CANDIDATES",
    "FRICTION",
    "RESTITUTION_FITTED",
    "candidates",
    "fit_candidate",
    "try_candidate",
    "failed_row",
    "fit_failed",
    "FIT_FAILURES",
    "rank",
    "choose_model",
    "choice_markdown",
    "same_force",
]

#: Friction: with the dry friction T fitted, or without it.
FRICTION = {"dry friction": {}, "no dry friction": {"T/m": 0.0}}
#: The restitution law fitted for all four (its g(e) covers every g >= 0).
RESTITUTION_FITTED = "flores"
#: (contact law, friction) of every candidate, in a fixed order (the workflow's job numbers): the
#: default law (model BC's, the richest) with and without dry friction, then every other law of
#: :data:`impactosc.model.contact_laws.LAWS` with it, the restitution laws by the one fitted.
CANDIDATES = (
    (DEFAULT_LAW, "dry friction"),
    (DEFAULT_LAW, "no dry friction"),
    *(
        (name, "dry friction")
        for name, law in LAWS.items()
        if name != DEFAULT_LAW and (not isinstance(law, RestitutionLaw) or name == RESTITUTION_FITTED)
    ),
)
_XI, _E = QUANTITIES.index("xI"), QUANTITIES.index("e")
#: Samples per block of a record in which each candidate's residuals are summed (the common
#: samples of the AIC and BIC are the blocks every candidate covered whole).
BLOCK = 64
#: What a candidate's fit can fail with, a row of the table rather than the end of the model
#: choice: a singular system (numpy's LinAlgError; SuperLU's RuntimeError "Factor is exactly
#: singular"), the core stopped (StallError), a value the law or a solver refuses (ValueError),
#: an overflow (ArithmeticError). A programming error (TypeError, KeyError, ...) still raises.
FIT_FAILURES = (np.linalg.LinAlgError, StallError, RuntimeError, ValueError, ArithmeticError)
#: Longest reason a failed row states, characters.
REASON_CHARS = 80


def _block_residuals(ident) -> dict:
    """The fit's residual sum of squares in each block of BLOCK samples of each record that its
    windows cover whole: {"record": [...], "block": [...], "rss": [...]}."""
    w = ident.windows
    r = ident.prediction() - w.y
    rec = np.repeat(w.record, w.n)
    idx = np.concatenate([np.arange(a, a + n) for a, n in zip(w.start, w.n)]) if w.size else np.empty(0, int)
    key = rec.astype(np.int64) * (1 << 40) + idx // BLOCK
    keys, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    rss = np.bincount(inverse, weights=np.nan_to_num(r, nan=1e6) ** 2)
    whole = counts == BLOCK
    return {
        "record": (keys[whole] >> 40).tolist(),
        "block": (keys[whole] & ((1 << 40) - 1)).tolist(),
        "rss": rss[whole].tolist(),
    }


def _not_pinned(ident) -> str:
    """The quantities the records did not pin, fixed at the stated value: 'name = value' each."""
    return " ".join(
        f"{nm}={ident.theta[ident.quantities.index(nm)]:.4g}"
        for nm, why in ident.fixed.items()
        if "not identifiable" in why
    )


def _held_out_error(records, ident, every, rtol):
    """RMS of the held-out windows' residuals with only their start states fitted, the number
    of samples, and the rms's standard error with the windows as the independent units (the
    ratio estimator's, halved for the square root: se(rms) = se(ms) / (2 rms))."""
    windows = cut_windows(records, periods=ident.periods, level=ident.theta_all[_XI])
    held = windows.subset(split_held_out(windows, every=every))
    if held.size == 0:
        return math.nan, 0, math.nan
    pred = Predictor(held, ident.params.as_array(1.0), ident.params.m, rtol=rtol)
    _, rss = fit_states(pred, ident.theta_all, np.column_stack([held.x0, held.v0]))
    n_w = held.n.astype(float)
    ms = float(np.sum(rss)) / n_w.sum()
    k = n_w.size
    se_ms = math.sqrt(k / max(k - 1, 1) * float(np.sum((rss - ms * n_w) ** 2))) / n_w.sum()
    return math.sqrt(ms), int(held.y.size), se_ms / (2.0 * math.sqrt(ms)) if ms > 0 else math.nan


def candidates() -> list[tuple[str, str]]:
    """Every (contact law, friction) candidate, in a fixed order (the workflow's job numbers)."""
    return list(CANDIDATES)


def same_force(law: str, e: float) -> str:
    """The e of each other restitution law whose force equals law's at e (chi v0 = g(e) alike),
    or that the law cannot reach that damping: 'gonthier e=0.62, ...'."""
    g = LAWS[law].g(e)  # chi v0, the same for every v0
    out = []
    for name, other in LAWS.items():
        if isinstance(other, RestitutionLaw) and name != law:
            e_other = other.e_for(g)
            reached = math.isclose(other.g(e_other), g, rel_tol=1e-6, abs_tol=1e-12)
            cap = other.g(e_other)  # its largest, at the least e
            out.append(f"{name} e={e_other:.4g}" if reached else f"{name} none (chi v0 {g:.3g} > {cap:.3g})")
    return ", ".join(out)


def candidate_base(base: ModelParams, law: str) -> ModelParams:
    """The stated model with the contact law `law`: its own exponent where the law fixes one
    (Kelvin-Voigt's n1 = 1), the others the stated model's Hertz exponents (1.5 when the stated
    law fixes its own)."""
    new, old = LAWS[law].n1, LAWS[base.law].n1
    n1 = new if new is not None else (1.5 if old is not None else base.n1)
    n2 = n1 if new is not None or old is not None else base.n2
    with warnings.catch_warnings():  # n1 = 1 lies outside the tested ranges of model BC's exponents
        warnings.simplefilter("ignore", UntestedParameterWarning)
        return dataclasses.replace(base, law=law, n1=n1, n2=n2)


def fit_candidate(records, law, friction, *, base=None, start=None, every=4, stages=STAGES, rtol=1e-10, progress=None):
    """One candidate fitted on the records' windows outside the held-out blocks: its row.
    start: the start values of model BC's law (:func:`start_values`), converted to `law`'s."""
    from impactosc.records.sample_fits import estimate_noise

    base = candidate_base(base or ModelParams(), law)
    if start is None:
        sigma = float(np.median([estimate_noise(r.x) for r in records]))
        start = start_values(records, candidate_base(base, DEFAULT_LAW), sigma=sigma)
    with warnings.catch_warnings():  # a wrong law's best fit may leave the tested ranges: it only ranks
        warnings.simplefilter("ignore", UntestedParameterWarning)
        ident = identify(
            records,
            base=base,
            fixed=FRICTION[friction],
            start=for_law(start, law),
            stages=stages,
            select=lambda w: ~split_held_out(w, every=every),
            rtol=rtol,
            progress=progress,
        )
        err, n_held, err_se = _held_out_error(records, ident, every, rtol)
    res = ident.fit
    n = res.n_samples
    return {
        "law": law,
        "friction": friction,
        "free": " ".join(ident.free_names),
        "not_pinned": _not_pinned(ident),
        "same_force": same_force(law, float(ident.theta_all[_E])) if isinstance(LAWS[law], RestitutionLaw) else "",
        "n_free": int(ident.free.sum()),
        "rss_m2": res.rss,
        "n": n,
        "rms_m": math.sqrt(res.rss / n),
        "held_out_rms_m": err,
        "held_out_se_m": err_se,
        "n_held_out": n_held,
        "seconds": ident.seconds,
        "converged": bool(res.converged),
        **{f"{nm}": float(v) for nm, v in zip(ident.quantities, ident.theta)},
        "blocks": _block_residuals(ident),
    }


def _one_line(exc: BaseException) -> str:
    """'Type: first line of the message', cut to REASON_CHARS characters."""
    text = str(exc).strip().splitlines()
    reason = f"{type(exc).__name__}: {text[0].strip()}" if text else type(exc).__name__
    return reason if len(reason) <= REASON_CHARS else reason[: REASON_CHARS - 3].rstrip() + "..."


def failed_row(law: str, friction: str, exc: BaseException) -> dict:
    """The row of a candidate whose fit failed: its law, friction and why, no numbers."""
    return {"law": law, "friction": friction, "failure": f"fit failed: {_one_line(exc)}", "converged": False}


def fit_failed(row: dict) -> bool:
    """Whether the row is that of a failed fit (:func:`failed_row`)."""
    return bool(row.get("failure"))


def try_candidate(records, law, friction, **options) -> dict:
    """:func:`fit_candidate`'s row, or :func:`failed_row` when the fit fails (FIT_FAILURES)."""
    try:
        return fit_candidate(records, law, friction, **options)
    except FIT_FAILURES as exc:
        return failed_row(law, friction, exc)


def best_held_out(rows: list[dict]) -> dict:
    """The candidate that predicts the held-out windows best, by the one-standard-error rule
    (Breiman et al. 1984; Hastie, Tibshirani and Friedman, ESL 7.10): the fewest free parameters
    among those whose held-out rms lies within one standard error of the smallest. Why: a law
    nested in a larger one (Hertz in model BC, at b = 0) reaches the same force, and the larger
    one's extra parameters, fitted to the noise, move its held-out rms by some 1e-5 of itself
    either way, far below what the held-out windows resolve."""
    least = min(rows, key=lambda r: r["held_out_rms_m"])
    bound = least["held_out_rms_m"] + least["held_out_se_m"]
    within = [r for r in rows if r["held_out_rms_m"] <= bound]
    return min(within, key=lambda r: (r["n_free"], r["held_out_rms_m"]))


def rank(rows: list[dict]) -> list[dict]:
    """Rows with AIC and BIC on the samples every candidate fitted (``n_common``, ``rms_common_m``;
    the block residuals are dropped), sorted by BIC, with their differences to the best, the
    supported one and the best held out (:func:`best_held_out`) marked.  The rows of failed fits
    (:func:`failed_row`) are neither ranked nor marked: they follow the others, in their order."""
    failures = [dict(r, supported=False, best_held_out=False) for r in rows if fit_failed(r)]
    rows = [r for r in rows if not fit_failed(r)]
    if not rows:
        return failures
    keys = [set(zip(r["blocks"]["record"], r["blocks"]["block"])) for r in rows]
    common = set.intersection(*keys) if keys else set()
    if not common:
        raise ValueError("the candidates' fits share no samples; their AIC and BIC cannot be compared")
    n = len(common) * BLOCK
    for r in rows:
        b = r.pop("blocks")
        rss = sum(v for rec, blk, v in zip(b["record"], b["block"], b["rss"]) if (rec, blk) in common)
        r["n_common"] = n
        r["rms_common_m"] = math.sqrt(rss / n)
        r["aic"] = n * math.log(rss / n) + 2 * r["n_free"]
        r["bic"] = n * math.log(rss / n) + r["n_free"] * math.log(n)
    rows = sorted(rows, key=lambda r: r["bic"])
    best_aic = min(r["aic"] for r in rows)
    best_held = best_held_out(rows)
    for i, r in enumerate(rows):
        r["delta_aic"] = r["aic"] - best_aic
        r["delta_bic"] = r["bic"] - rows[0]["bic"]
        r["best_held_out"] = r is best_held
        r["supported"] = i == 0
    return rows + failures


def choose_model(
    records, *, base: ModelParams | None = None, every: int = 4, stages=STAGES, rtol: float = 1e-10, progress=None
):
    """Fit every (contact law, friction) candidate; one row each, best BIC first (:func:`rank`),
    a candidate whose fit failed last, saying why (:func:`try_candidate`)."""
    from impactosc.records.sample_fits import estimate_noise

    records = list(records)
    say = progress or (lambda msg: None)
    base = base or ModelParams()
    sigma = float(np.median([estimate_noise(r.x) for r in records]))
    start = start_values(records, candidate_base(base, DEFAULT_LAW), sigma=sigma)
    rows = []
    for law, fr in candidates():
        say(f"candidate {law}, {fr}")
        rows.append(try_candidate(records, law, fr, base=base, start=start, every=every, stages=stages, rtol=rtol))
        r = rows[-1]
        if fit_failed(r):
            say(f"  {r['failure']}")
        else:
            say(f"  rms {r['rms_m'] * 1e6:.3f} um on {r['n']} samples, held out {r['held_out_rms_m'] * 1e6:.3f} um")
    return rank(rows)


def choice_markdown(rows: list[dict]) -> str:
    """The ranked candidates as Markdown: which model the records support, and by how much; the
    candidates whose fit failed last, each saying why."""
    ranked = [r for r in rows if not fit_failed(r)]
    failures = [r for r in rows if fit_failed(r)]
    failed_note = (
        f" A candidate whose fit failed ({len(failures)} here) is a row that says so and why, with no numbers: "
        "it is neither ranked nor chosen."
        if failures
        else ""
    )
    if ranked:
        best = ranked[0]
        held = next(r for r in ranked if r["best_held_out"])
        own = [r["n"] for r in ranked]
        intro = (
            f"Supported (smallest BIC): **{best['law']}, {best['friction']}**. Fits on the windows outside the "
            "held-out blocks; held-out error: rms residual of the held-out windows with only their start states "
            f"fitted, with its standard error (the windows as units); best held out: **{held['law']}, "
            f"{held['friction']}**, the fewest free parameters within one standard error of the smallest held-out "
            "rms (a law nested in a larger one reaches the same force; the larger one's extra parameters move "
            "its held-out rms by far less than the windows resolve). Each fit has its own windows "
            f"({min(own)}-{max(own)} samples: it cuts them at its own obstacle "
            "estimate and leaves out those it fits far worse than the rest); AIC and BIC, and the rms beside them, "
            f"are those of the {best['n_common']} samples every candidate fitted, with the free parameters as "
            "penalty. Not pinned: what the records could not determine for that candidate, fixed at the stated "
            "value shown. A candidate whose fit did not converge is marked so: its rms is only an upper bound "
            f"on what its law reaches.{failed_note} The restitution laws are one force, kI h^n1 (1 + g(e) v / v0), "
            "written in e four ways: "
            f"{RESTITUTION_FITTED} is fitted, and its row gives the e of each other one with the same force (none "
            "where that law's g cannot reach it)."
        )
    else:
        intro = "No candidate's fit succeeded: the records support none of them here." + failed_note
    lines = [
        "# Model choice: which contact law and friction the records support",
        "",
        intro,
        "",
        "| contact law | friction | free | not pinned | rms fit (um), own samples | rms fit (um), common samples "
        "| rms held out (um) +- se | dAIC | dBIC | same force |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in ranked:
        held = f"{r['held_out_rms_m'] * 1e6:.3f} +- {r['held_out_se_m'] * 1e6:.3f}" + (
            " (best)" if r["best_held_out"] else ""
        )
        law = r["law"] if r.get("converged", True) else f"{r['law']} (not converged)"
        lines.append(
            f"| {law} | {r['friction']} | {r['free']} | {r['not_pinned'] or '-'} | {r['rms_m'] * 1e6:.3f} "
            f"({r['n']}) | {r['rms_common_m'] * 1e6:.3f} | {held} | {r['delta_aic']:.1f} | {r['delta_bic']:.1f} "
            f"| {r.get('same_force') or '-'} |"
        )
    for r in failures:
        why = r["failure"].replace("|", "\\|")
        lines.append(f"| {r['law']} | {r['friction']} | {why} | - | - | - | - | - | - | - |")
    return "\n".join(lines) + "\n"
