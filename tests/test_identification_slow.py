"""The identification's headline checks on surrogates of known truth (slow: pytest -m slow).

* Coverage: 24 random truths within +-30 % of model BC (m0e, k, c, T, kI, b, n3, xI), records at
  w = 23.03, 31 and 40.86 of 60 s each, 2 kHz, 5 um noise: each parameter within 2 stated
  standard errors in at least 90 % of the draws (22 of 24; the seeds are fixed, so the test is
  deterministic; honest errors hold the truth within 2 se in 95.4 % of draws), and the identified
  model's Fig 2 branch within 10 um of the true model's at every w where both are periodic with
  the same period, on the same orbit (where the two continuations took two coexisting orbits,
  as in two of the draws, the identified model is followed from the true model's state).  About 25 min on 2 cores; the workflow's identify_coverage target writes the
  same table (results/paper/tables/identification/coverage.md).
* Model choice: records made with model BC's, Hertz's and Flores' contact laws (e = 0.6, the rest
  model BC's) are each given to the candidates; the supported one (least BIC) is the true law
  with dry friction; held out it predicts best, tied only with the laws that contain it. 6-10 min
  each on 2 cores (the seven fits, 10-170 s each: a wrong law's fit takes longest). Rigs of the
  two laws added last (hertz-viscous, two-stage) are ranked first too.
"""

from __future__ import annotations

import dataclasses
import math
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from impactosc.identification.choice import choose_model
from impactosc.model.parameters import ModelParams
from impactosc.records.surrogate import SurrogateOptions, surrogate_record
from impactosc_study.coverage import coverage_table, identification_draw

pytestmark = pytest.mark.slow

BRANCH = np.arange(20.0, 45.0001, 0.25)


def _draw(seed):
    return identification_draw(seed, branch_omegas=BRANCH)


def test_stated_standard_errors_cover_the_truth():
    with ProcessPoolExecutor(2) as pool:
        draws = list(pool.map(_draw, range(24)))
    table = {r["parameter"]: r for r in coverage_table(draws)}
    for name, r in table.items():
        assert r["draws"] == 24, name
        assert r["within_2se"] >= 22, (name, r)
    for d in draws:
        # the model file a user reads back states a covariance the delta method can use
        assert d["covariance_pd"], d["covariance_error"]
        assert d["branch_w_beyond_tol"] == 0, d
        assert d["branch_periodic_w"] >= 50, d  # most of the grid is periodic in both models


LAWS = {"bc": {}, "hertz": {"law": "hertz"}, "flores": {"law": "flores", "e": 0.6}}
#: The candidates whose law contains the true one: Hertz is model BC at b = 0 and every
#: restitution law at e = 1.
CONTAIN = {"bc": {"bc"}, "hertz": {"hertz", "bc", "flores"}, "flores": {"flores"}}


@pytest.mark.parametrize("law", list(LAWS))
def test_model_choice_finds_the_true_contact_law(law, capsys):
    truth = dataclasses.replace(ModelParams(), **LAWS[law])
    records = [
        surrogate_record(w, 60.0, 20.0, SurrogateOptions(rate=2000.0, noise=5e-6, seed=i), params=truth)[0]
        for i, w in enumerate((23.03, 31.0, 40.86))
    ]
    rows = choose_model(records)
    with capsys.disabled():
        print(f"\n  model choice on surrogates of {law}: law, friction, held-out rms (um), dBIC, fit (s)")
        for r in rows:
            held, se, dbic = r["held_out_rms_m"] * 1e6, r["held_out_se_m"] * 1e6, r["delta_bic"]
            print(
                f"    {r['law']:<13} {r['friction']:<16} {held:.6f} +- {se:.4f} {dbic:9.1f} {r['seconds']:6.1f} "
                f"{'(best held out) ' * r['best_held_out']}{r['same_force']}"
            )
    best = rows[0]
    table = [(r["law"], r["friction"], r["held_out_rms_m"], r["bic"]) for r in rows]
    assert (best["law"], best["friction"]) == (law, "dry friction"), table
    # held out, the true law predicts best (the one-standard-error rule: the laws that contain it
    # reach the same force, and fitting their one or two more parameters to some 80 000 samples
    # moves the held-out rms by about p / 2N = 1e-5 of itself, either way; measured on Hertz:
    # 1.2e-5), tied within 1e-4 with those laws; every other candidate is worse by more than 1 %
    assert [(r["law"], r["friction"]) for r in rows if r["best_held_out"]] == [(law, "dry friction")], table
    held = {(r["law"], r["friction"]): r["held_out_rms_m"] for r in rows}
    true_held = held[(law, "dry friction")]
    for (other, friction), value in held.items():
        if other in CONTAIN[law] and friction == "dry friction":
            assert true_held < value * (1 + 1e-4), table
        else:
            assert value > 1.01 * true_held, table
    # when the true law is nested in the runner-up (Hertz in every other), the runner-up's BIC is
    # worse by ln N - chi2(1): beyond ln N - 9 unless chi2(1) > 9 (probability 0.3 %)
    assert rows[1]["delta_bic"] > math.log(best["n_common"]) - 9


#: Rigs of the laws added as definitions alone, moved from model BC (m0e +10 %, k -5 %, c +25 %,
#: T -15 %, kI +20 %, xI -7 %) and from the laws' own defaults (cI 330 N s/m; h1 6.5e-5 m, k2 1.6e9).
NEW_LAWS = {"hertz-viscous": {"cI": 330.0}, "two-stage": {"h1": 6.5e-5, "k2": 1.6e9}}


@pytest.mark.parametrize("law", list(NEW_LAWS))
def test_model_choice_ranks_a_rig_of_each_new_law_first(law, capsys):
    """Three records (w = 40.86, 30, 25; 12 s each at 2 kHz, 5 um noise) of a rig of the law: it
    is among the candidates, and the one the records support (least BIC). Measured: hertz-viscous
    first by BIC and best held out (4.921 um against Kelvin-Voigt's 33 um); two-stage first by BIC
    (dBIC 827 to Hertz), but held out tied with Hertz within one standard error (4.936 against
    4.942 +- 0.037 um: its second stop barely shows in the motion), so the one-standard-error rule
    names Hertz, the smaller law. About 5-6 min each on one core."""
    base = ModelParams()
    truth = dataclasses.replace(
        base, law=law, m0e=base.m0e * 1.1, k=base.k * 0.95, c=base.c * 1.25, T=base.T * 0.85, kI=base.kI * 1.2,
        xI=base.xI * 0.93, **NEW_LAWS[law],
    )  # fmt: skip
    records = [
        surrogate_record(w, 20.0, 12.0, SurrogateOptions(rate=2000.0, noise=5e-6, seed=s), params=truth)[0]
        for w, s in ((40.86, 1), (30.0, 2), (25.0, 3))
    ]
    rows = choose_model(records)
    with capsys.disabled():
        print(f"\n  model choice on a {law} rig: law, friction, held-out rms (um), dBIC")
        for r in rows:
            print(
                f"    {r['law']:<13} {r['friction']:<16} {r.get('held_out_rms_m', math.nan) * 1e6:.4f} {r.get('delta_bic', math.nan):9.1f}"
            )
    assert law in {r["law"] for r in rows}
    assert (rows[0]["law"], rows[0]["friction"]) == (law, "dry friction"), [(r["law"], r.get("bic")) for r in rows]
    if law == "hertz-viscous":
        assert next(r for r in rows if r["best_held_out"])["law"] == law
