"""Identification of model BC from records (impactosc.identification).

What is checked against what:
* the elimination of the window states (least_squares._schur) against a dense least-squares
  solve of the whole Jacobian on a random arrow-structured problem (linear algebra only);
* the window predictions against the core's own uninterrupted trajectory (a window restarted
  from the trajectory's state must continue it);
* the identified parameters against the surrogate's known truth, within 3 stated standard errors
  (a deterministic draw: 3 se leaves any one of 8 parameters a 2 % chance of a false alarm for
  this fixed seed, and the coverage over many draws is the slow test's and the
  identify_coverage target's job);
* what the records cannot pin is fixed and named, not fitted as noise.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from impactosc.core.simulation import Window, simulate
from impactosc.identification.fitted_parameters import FIELDS, NAMES, fill_array, params_of, theta_of
from impactosc.identification.least_squares import _inverse_scaled, _schur, _solve_scaled, carried_states
from impactosc.identification.staged_fit import identify
from impactosc.identification.window_predictions import Predictor
from impactosc.identification.windows import WindowSet, cut_windows, split_held_out
from impactosc.model.parameters import ModelParams
from impactosc.records.record import Record
from impactosc.records.surrogate import SurrogateOptions, surrogate_record


def test_theta_round_trip_and_core_array():
    p = dataclasses.replace(ModelParams(), m=5.0, k=2000.0, xI=-1.5e-3)
    th = theta_of(p)
    assert th[NAMES.index("k/m")] == pytest.approx(400.0)
    back = params_of(th, p)
    for f in FIELDS:
        assert getattr(back, f) == pytest.approx(getattr(p, f), rel=1e-14)
    arr = ModelParams(m=p.m).as_array(40.0)  # every fitted field differs from p's
    fill_array(arr, th, p.m)
    assert np.allclose(arr, p.as_array(40.0), rtol=1e-15, atol=0)


def test_schur_elimination_equals_dense_least_squares():
    rng = np.random.default_rng(3)
    n_win, n_per, P = 7, 30, 4
    A = rng.normal(size=(n_win * n_per, 2))
    B = rng.normal(size=(n_win * n_per, P))
    r = rng.normal(size=n_win * n_per)
    n = np.full(n_win, n_per)
    w = WindowSet(
        *(np.zeros(n_win),) * 2, n, *(np.zeros(n_win),) * 3, np.arange(n_win) * n_per, r, *(np.zeros(n_win),) * 2, []
    )
    # dense Jacobian: each window's two state columns, then the shared ones
    J = np.zeros((n_win * n_per, 2 * n_win + P))
    for j in range(n_win):
        J[j * n_per : (j + 1) * n_per, 2 * j : 2 * j + 2] = A[j * n_per : (j + 1) * n_per]
    J[:, 2 * n_win :] = B
    dense = np.linalg.lstsq(J, -r, rcond=None)[0]
    M, rhs, blocks = _schur(A, B, r, w, 0.0)
    dth = _solve_scaled(M, rhs)
    assert np.allclose(dth, dense[2 * n_win :], rtol=1e-10, atol=1e-12)
    for j, (Uinv, Wj, gA) in enumerate(blocks):
        assert np.allclose(-Uinv @ (gA + Wj @ dth), dense[2 * j : 2 * j + 2], rtol=1e-9, atol=1e-12)
    # the reduced information's inverse is the shared block of the full (J^T J)^-1
    assert np.allclose(_inverse_scaled(M), np.linalg.inv(J.T @ J)[2 * n_win :, 2 * n_win :], rtol=1e-9)


@pytest.fixture(scope="module")
def chaos_record():
    rec, _ = surrogate_record(40.86, 20.0, 12.0, SurrogateOptions(rate=2000.0, noise=5e-6, seed=11))
    return rec


def test_windows_start_in_free_flight_and_tile_the_record(chaos_record):
    p = ModelParams()
    w = cut_windows([chaos_record], periods=2.0, level=p.xI)
    ends = w.start + w.n
    assert np.array_equal(w.start[1:], ends[:-1])  # contiguous, no sample twice
    assert np.all(chaos_record.x[w.start] < p.xI - 50e-6)
    assert np.allclose(w.tau0, chaos_record.t[w.start])  # no encoder: model time is the record's
    held = split_held_out(w, every=4)
    assert 0 < held.sum() < w.size


def test_encoder_phase_sets_each_windows_forcing(chaos_record):
    """A record whose clock starts elsewhere but carries the exact phase gets the model's time back."""
    rec = chaos_record
    shifted = Record(rec.t - 7.3, rec.x, None, {}, "<shifted>", phase=40.86 * rec.t)
    w0 = cut_windows([rec], periods=2.0, level=-2.086e-3)
    w1 = cut_windows([shifted], periods=2.0, level=-2.086e-3)
    assert np.array_equal(w0.start, w1.start)
    assert np.allclose(w1.omega, 40.86, rtol=1e-12)
    assert np.allclose(w1.tau0, w0.tau0, atol=1e-9)


@pytest.fixture(scope="module")
def clean_trajectory():
    """3 s of the chaotic attractor sampled at 2 kHz without noise, and the record of it."""
    res = simulate(40.86, 20.0, 3.0, params=ModelParams(), window=Window(20.0, 23.0, 5e-4), record=())
    tr = res.trajectory
    return tr, Record(tr["t"], tr["x"], 40.86, {}, "<clean>")


def test_window_prediction_continues_the_trajectory(clean_trajectory):
    par = ModelParams()
    tr, rec = clean_trajectory
    w = cut_windows([rec], periods=2.0, level=par.xI)
    states = np.column_stack([tr["x"][w.start], tr["v"][w.start]])
    pred = Predictor(w, par.as_array(40.86), par.m).predict(theta_of(par), states)
    assert np.max(np.abs(pred - w.y)) < 1e-9  # the integration tolerance, far below any noise


def test_carried_states_continue_the_fitted_trajectory(clean_trajectory):
    # the next stage's start states from the last stage's trajectories: on a clean record with
    # the true states of half-period windows, the two-period windows get the true states at
    # their own starts (the integration tolerance), and none from windows not trusted
    par = ModelParams()
    tr, rec = clean_trajectory
    short = cut_windows([rec], periods=0.5, level=par.xI)
    fitted = Predictor(short, par.as_array(40.86), par.m)
    true_short = np.column_stack([tr["x"][short.start], tr["v"][short.start]])
    long = cut_windows([rec], periods=2.0, level=par.xI)
    trusted = np.ones(short.size, dtype=bool)
    states, close = carried_states(fitted, true_short, trusted, theta_of(par), long)
    inside = long.start >= short.start[0]
    assert np.array_equal(close, inside) and close.sum() >= long.size - 1
    # measured 7e-13 m and 1.4e-11 m/s (rtol 1e-10 on a few-mm, 0.1 m/s motion); bounds 100x
    assert np.max(np.abs(states[close, 0] - tr["x"][long.start[close]])) < 1e-10
    assert np.max(np.abs(states[close, 1] - tr["v"][long.start[close]])) < 1e-8
    assert not np.array_equal(long.start, short.start[: long.size])  # they start elsewhere
    states, close = carried_states(fitted, true_short, ~trusted, theta_of(par), long)
    assert not close.any() and np.array_equal(states, np.column_stack([long.x0, long.v0]))


def test_identified_parameters_cover_the_truth(chaos_record):
    truth = ModelParams()
    ident = identify([chaos_record])
    th = theta_of(truth)
    z = (ident.theta - th) / ident.stderr
    assert ident.fit.converged
    assert np.all(ident.free), ident.fixed
    assert np.all(np.abs(z) < 3), dict(zip(NAMES, np.round(z, 2)))
    assert ident.noise == pytest.approx(5e-6, rel=0.05)
    # the errors are small: a few per mille for the ratios, well below a micrometre for xI
    assert ident.stderr[NAMES.index("xI")] < 1e-6
    assert np.all(ident.stderr[:5] / th[:5] < 0.02)
    # the surrogate record declares its truth: the parameter table shows it and each error in
    # standard errors (the z above, in the ModelParams fields' units)
    from impactosc.identification.report import parameter_markdown, parameter_table
    from impactosc.records.surrogate_truth import record_truth

    assert record_truth([chaos_record]) == truth
    rows = parameter_table(ident, truth=record_truth([chaos_record]))
    np.testing.assert_allclose([r["z"] for r in rows], z, rtol=1e-9)
    assert [r["truth"] for r in rows][NAMES.index("xI")] == truth.xI
    table = parameter_markdown(rows, ident)
    assert "| truth | error / stderr |" in table and f"| {z[NAMES.index('k/m')]:+.2f} |" in table
    # a rig's record (no truth in its metadata), or records of two different models: no truth
    assert record_truth([Record(chaos_record.t, chaos_record.x, 40.86, {}, "<rig>")]) is None
    other = {**chaos_record.meta, "true_c": truth.c * 1.01}
    assert record_truth([chaos_record, Record(chaos_record.t, chaos_record.x, 40.86, other, "<b>")]) is None


def test_a_record_without_contacts_fixes_the_contact_law_and_says_why():
    """Two w: at one w a steady free motion is a sinusoid, and k/m trades off against m0e/m."""
    far = dataclasses.replace(ModelParams(), xI=10e-3)  # beyond reach at w = 30, 40 (amplitude 2.5 mm)
    recs = []
    for w in (30.0, 40.0):
        rec, truth = surrogate_record(w, 20.0, 8.0, SurrogateOptions(rate=2000.0, noise=5e-6, seed=2), params=far)
        assert truth["impacts"]["t"].size == 0
        recs.append(rec)
    stated = dataclasses.replace(far, k=1300.0, c=7.0, T=0.5, m0e=0.02)  # the free-flight constants are fitted
    ident = identify(recs, base=stated)
    for nm in ("kI/m", "b", "n3", "xI"):
        assert not ident.free[NAMES.index(nm)]
        assert "not identifiable" in ident.fixed[nm]
        assert ident.theta[NAMES.index(nm)] == theta_of(stated)[NAMES.index(nm)]
    assert "no contacts" in ident.fixed["kI/m"] and "stay below the obstacle" in ident.fixed["xI"]
    assert np.all(ident.free[:4])
    z = (ident.theta[:4] - theta_of(far)[:4]) / ident.stderr[:4]
    assert np.all(np.abs(z) < 3), z


def test_bad_input_is_named():
    rec, _ = surrogate_record(40.86, 10.0, 0.05, SurrogateOptions(rate=2000.0, noise=5e-6))
    with pytest.raises(ValueError, match="too short"):
        cut_windows([rec], periods=2.0, level=-2.086e-3)
    nophase = Record(rec.t, rec.x, None, {}, "nophase.csv")
    with pytest.raises(ValueError, match=r"nophase\.csv: neither omega nor an encoder phase"):
        cut_windows([nophase], periods=2.0, level=-2.086e-3)
    with pytest.raises(ValueError, match="unknown parameter 'kl'"):
        identify([rec], fixed={"kl": 1.0})
    with pytest.raises(ValueError, match="at least one record"):
        identify([])


def test_branch_comparison_follows_one_of_two_coexisting_orbits():
    """A random truth of the coverage study (seed 18) has two period-3 orbits at w = 20.25, about
    160 um apart; the section states below lie on them (taken from its continuation and from the
    identified model's). Started from each state the model stays on that orbit, and a model 0.1 %
    off in kI, started from the same state, reaches the same orbit within the branch tolerance:
    the comparison the coverage makes where two continuations took different orbits."""
    from impactosc_study.coverage import BRANCH_TOL, _orbit_from, random_truth

    truth = random_truth(18)
    near = dataclasses.replace(truth, kI=1.001 * truth.kI)
    states = [(-0.0032104749668557023, -0.0023799031725474633), (-0.0033445760322028777, -7.619462366503389e-05)]
    orbits = [_orbit_from(truth, 20.25, state, 3, 400) for state in states]
    assert np.max(np.abs(orbits[0] - orbits[1])) > 100e-6  # two orbits, not one
    for state, orbit in zip(states, orbits):
        assert np.max(np.abs(_orbit_from(near, 20.25, state, 3, 400) - orbit)) < BRANCH_TOL


def test_model_choice_compares_criteria_on_the_samples_every_candidate_fitted():
    # candidate "small" fits better on its own samples because it left out a badly fitted block
    # that "large" kept; on the common blocks "large" fits better: AIC/BIC follow the rms of the
    # common samples shown beside them, not the own-sample rms
    from impactosc.identification.choice import BLOCK, choice_markdown, rank

    def row(name, n_free, rss_by_block, n):
        rec, blk = zip(*rss_by_block)
        return {
            "law": name,
            "friction": "dry friction",
            "free": "k/m c/m",
            "not_pinned": "",
            "n_free": n_free,
            "n": n,
            "rms_m": 1e-6,
            "held_out_rms_m": 1e-6,
            "held_out_se_m": 1e-8,
            "blocks": {"record": [r for r, _ in rec], "block": [b for _, b in rec], "rss": list(blk)},
        }

    common = [((0, b), 1e-9) for b in range(10)]
    small = row("small", 6, [((0, b), 2e-9) for b in range(10)], 10 * BLOCK)
    large = row("large", 7, [*common, ((0, 10), 1e-6)], 11 * BLOCK)
    ranked = rank([small, large])
    assert [r["law"] for r in ranked] == ["large", "small"]
    assert all(r["n_common"] == 10 * BLOCK and "blocks" not in r for r in ranked)
    assert ranked[0]["rms_common_m"] == pytest.approx(np.sqrt(10 * 1e-9 / (10 * BLOCK)))
    n = 10 * BLOCK
    assert ranked[1]["delta_bic"] == pytest.approx(n * np.log(2.0) - np.log(n), rel=1e-9)
    text = choice_markdown(ranked)
    assert f"{10 * BLOCK} samples every candidate fitted" in text and "(not converged)" not in text
    # a candidate whose fit did not converge is marked in the table
    ranked[1]["converged"] = False
    assert "| small (not converged) |" in choice_markdown(ranked) and "| large |" in choice_markdown(ranked)
    with pytest.raises(ValueError, match="share no samples"):
        rank([row("a", 6, [((0, 1), 1e-9)], BLOCK), row("b", 6, [((1, 1), 1e-9)], BLOCK)])


def test_the_best_held_out_is_the_simplest_within_one_standard_error():
    from impactosc.identification.choice import best_held_out

    def row(law, n_free, rms, se):
        return {"law": law, "n_free": n_free, "held_out_rms_m": rms, "held_out_se_m": se}

    # Hertz's records: model BC (b fitted near 0) a hair below Hertz, far inside one standard error
    nested = [row("bc", 8, 4.998851e-6, 2e-8), row("hertz", 6, 4.998856e-6, 2e-8), row("flores", 7, 4.998915e-6, 2e-8)]
    assert best_held_out(nested)["law"] == "hertz"
    # a simpler law worse by more than the smallest rms's standard error does not count
    apart = [row("flores", 7, 5.0117e-6, 2e-8), row("hertz", 6, 5.06e-6, 2e-8), row("bc", 8, 6.81e-6, 3e-8)]
    assert best_held_out(apart)["law"] == "flores"


def _choice_row(law, friction, n_free, rss, held_out):
    """A fitted candidate's row as fit_candidate gives it: ten common blocks of rss each."""
    from impactosc.identification.choice import BLOCK

    return {
        "law": law,
        "friction": friction,
        "free": "k/m c/m",
        "not_pinned": "",
        "n_free": n_free,
        "n": 10 * BLOCK,
        "rms_m": 1e-6,
        "held_out_rms_m": held_out,
        "held_out_se_m": 1e-9,
        "n_held_out": 4 * BLOCK,
        "converged": True,
        "blocks": {"record": [0] * 10, "block": list(range(10)), "rss": [rss] * 10},
    }


def _fake_fits(failing, exc):
    """A stand-in for choice.fit_candidate: model BC's law fits best, ``failing`` raises exc."""

    def fit(records, law, friction, **options):
        if law == failing:
            raise exc
        bc = law == "bc" and friction == "dry friction"
        return _choice_row(law, friction, 6 if law == "hertz" else 7, 1e-9 if bc else 2e-9, 5e-6 if bc else 6e-6)

    return fit


@pytest.mark.parametrize(
    "exc",
    [
        np.linalg.LinAlgError("Factor is exactly singular"),
        RuntimeError("Factor is exactly singular"),  # SuperLU's, from the continuity stage
        ValueError("x0 = nan: the start state must be finite"),
    ],
    ids=["LinAlgError", "RuntimeError", "ValueError"],
)
def test_a_candidate_whose_fit_fails_is_a_row_saying_so_not_ranked(monkeypatch, exc):
    from types import SimpleNamespace

    from impactosc.identification import choice

    monkeypatch.setattr(choice, "fit_candidate", _fake_fits(choice.RESTITUTION_FITTED, exc))
    monkeypatch.setattr(choice, "start_values", lambda *args, **kwargs: None)
    records = [SimpleNamespace(x=np.random.default_rng(1).normal(0.0, 5e-6, 4000))]
    said = []
    rows = choice.choose_model(records, progress=said.append)
    # by BIC (Hertz's one parameter fewer ranks it above the others of equal rss, which keep the
    # candidates' order), the failed one last
    first, failing = [("bc", "dry friction"), ("hertz", "dry friction")], (choice.RESTITUTION_FITTED, "dry friction")
    others = [c for c in choice.candidates() if c not in (*first, failing)]
    assert [(r["law"], r["friction"]) for r in rows] == [*first, *others, failing]
    failed = rows[-1]
    assert failed["law"] == choice.RESTITUTION_FITTED and choice.fit_failed(failed)
    assert failed["failure"] == f"fit failed: {type(exc).__name__}: {exc}"
    assert not failed["supported"] and not failed["best_held_out"] and "bic" not in failed
    assert not any(choice.fit_failed(r) for r in rows[:-1]) and all("bic" in r for r in rows[:-1])
    assert rows[0]["supported"] and (rows[0]["law"], rows[0]["friction"]) == ("bc", "dry friction")
    assert [r["best_held_out"] for r in rows].count(True) == 1 and rows[0]["best_held_out"]
    assert f"  {failed['failure']}" in said
    text = choice.choice_markdown(rows)
    assert f"| {choice.RESTITUTION_FITTED} | dry friction | {failed['failure']} | - |" in text
    assert "Supported (smallest BIC): **bc, dry friction**" in text and "a row that says so" in text


def test_a_failed_fit_states_one_line_of_its_reason_and_a_programming_error_still_raises(monkeypatch):
    from impactosc.core.simulation import StallError
    from impactosc.identification import choice

    long = StallError("the core stopped at t = 1.5 s: " + "step size underflow " * 10 + "\nstate: ...", {})
    monkeypatch.setattr(choice, "fit_candidate", _fake_fits("hertz", long))
    row = choice.try_candidate([], "hertz", "dry friction")
    assert row["failure"].startswith("fit failed: StallError: the core stopped at t = 1.5 s: step size underflow")
    assert len(row["failure"]) <= len("fit failed: ") + choice.REASON_CHARS and row["failure"].endswith("...")
    assert "\n" not in row["failure"] and "state" not in row["failure"]
    monkeypatch.setattr(choice, "fit_candidate", _fake_fits("hertz", TypeError("a bug")))
    with pytest.raises(TypeError):
        choice.try_candidate([], "hertz", "dry friction")
    # every fit failed: the table says so and chooses none
    rows = choice.rank([choice.failed_row(law, fr, RuntimeError("x | y")) for law, fr in choice.candidates()])
    assert len(rows) == len(choice.candidates()) and not any(r["supported"] or r["best_held_out"] for r in rows)
    text = choice.choice_markdown(rows)
    assert "No candidate's fit succeeded" in text and "fit failed: RuntimeError: x \\| y" in text


def test_the_ranking_ignores_failed_rows():
    from impactosc.identification.choice import failed_row, rank

    rows = rank(
        [
            failed_row("bc", "dry friction", np.linalg.LinAlgError("Singular matrix")),
            _choice_row("hertz", "dry friction", 6, 2e-9, 6e-6),
            _choice_row("flores", "dry friction", 7, 1e-9, 5e-6),
        ]
    )
    assert [r["law"] for r in rows] == ["flores", "hertz", "bc"]
    assert rows[0]["supported"] and rows[0]["best_held_out"] and rows[0]["delta_bic"] == 0.0
    assert rows[2]["failure"] == "fit failed: LinAlgError: Singular matrix" and "delta_bic" not in rows[2]


def test_the_continuity_step_survives_a_window_whose_difference_runs_failed(clean_trajectory):
    """A run the core stops gives NaN samples; in one window's sensitivities, such a NaN made the
    KKT matrix's LU report 'Factor is exactly singular' and ended the whole fit. That window
    now sits out the step; a parameter without effect (a zero column) stays solvable too."""
    from impactosc.identification import continuity
    from impactosc.identification.fitted_parameters import LOWER, QUANTITIES, UPPER, law_quantities

    par = ModelParams()
    tr, clean = clean_trajectory
    noisy = np.random.default_rng(3).normal(0.0, 5e-6, clean.x.size)
    w = cut_windows([Record(clean.t, clean.x + noisy, 40.86, {}, "<noisy>")], periods=2.0, level=par.xI)
    theta = theta_of(par, full=True)
    free = np.array([nm in law_quantities("bc") for nm in QUANTITIES])
    states = np.column_stack([tr["x"][w.start], tr["v"][w.start]])
    pred = Predictor(w, par.as_array(40.86), par.m)
    _, E, A, Phi, B, G = pred.jacobian(theta, states, free, QUANTITIES)
    r = pred.predict(theta, states) - w.y
    lk = continuity.links(w)
    gaps = E[lk] - states[lk + 1]
    assert w.size >= 8 and lk.size >= 6
    zero = B.copy()
    zero[:, 0] = 0.0  # k/m without effect: solvable as it was
    continuity._kkt(A, Phi, zero, G, r, gaps, w, lk, 0.0)
    spoiled = A.copy()
    spoiled[w.offset[3] + 5, 1] = np.nan  # window 3's run from v0 + a step stopped
    with pytest.raises(RuntimeError, match="Factor is exactly singular"):
        continuity._kkt(spoiled, Phi, B, G, r, gaps, w, lk, 0.0)

    class Stopped(Predictor):
        """Window 3's difference runs stop, at every point of the fit."""

        def jacobian(self, *args):
            out = list(super().jacobian(*args))
            rows = slice(self.w.offset[3], self.w.offset[3] + self.w.n[3])
            out[2][rows], out[4][rows], out[3][3], out[5][3] = np.nan, np.nan, np.nan, np.nan
            return tuple(out)

    shifted = theta.copy()
    shifted[QUANTITIES.index("k/m")] *= 1.0 + 1e-5  # a step to take
    res = continuity.fit_continuous(
        Stopped(w, par.as_array(40.86), par.m), shifted, states, free, QUANTITIES, lower=LOWER, upper=UPPER
    )
    assert np.all(np.isfinite(res.theta)) and np.all(np.isfinite(res.cov)) and res.iterations >= 2
    z = (res.theta - theta)[free] / res.stderr[free]
    assert np.all(np.abs(z) < 4), dict(zip(np.array(QUANTITIES)[free], np.round(z, 2)))
