"""The two-stage law, kI h^n1 and past h = h1 also k2 (h - h1)^n1: added by its definition alone
(impactosc/model/contact_laws/two_stage.py). Its second stop is a switching surface inside the
contact, which the core locates and splits at as it does at the onset; checked against SciPy on
the law's published form split at h = 0 and h = h1 (impactosc_bench.scipy_reference)."""

import dataclasses
import warnings

import numpy as np
import pytest

from impactosc.core.simulation import Window, simulate
from impactosc.explorer.view import shown_parameters
from impactosc.identification.fitted_parameters import law_quantities
from impactosc.model.model_file import apply_overrides, read_model_file
from impactosc.model.parameters import ModelParams, UntestedParameterWarning
from impactosc_bench.scipy_reference import solve_reference

LAW = "two-stage"
FREE = dict(k=1e-60, c=0.0, T=0.0, m0e=1e-60, xI=0.0)


def model(**changes):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UntestedParameterWarning)
        return ModelParams(law=LAW, **{"h1": 5.0e-5, "k2": 2.0e9, **changes})


def test_the_chaotic_scene_from_rest_agrees_with_scipy_split_at_the_second_stop():
    """3 s of w = 40.86 rad/s from rest: every impact and every penetration within 1e-8 s of SciPy
    at rtol 1e-13, split at h = 0 and h = h1; most contacts reach the second stop."""
    params = model()
    run = simulate(40.86, 0.0, 3.0, params=params, rtol=1e-12, atol=1e-15, record=("impacts", "penetrations"))
    ref = solve_reference(40.86, 3.0, params=params, rtol=1e-13, atol=1e-16)
    t_core, t_ref = run.events["impacts"]["t"], ref["impacts_t"]
    assert t_core.size == t_ref.size > 10
    assert np.max(np.abs(t_core - t_ref)) < 1e-8
    depth = run.events["penetrations"]["h"]
    assert depth.size == ref["penetrations_h"].size and np.max(np.abs(depth - ref["penetrations_h"])) < 1e-12
    assert np.mean(depth > params.h1) > 0.5


@pytest.mark.parametrize("v0", [0.1, 0.25, 0.4])
@pytest.mark.parametrize("h1", [1e-5, 5e-5, 2e-4])
def test_a_free_impact_restitutes_as_scipy_says(v0, h1):
    """No spring, friction or forcing: e_eff within 1e-6 of SciPy's split integration. The law
    dissipates nothing: both give 1 (to 1e-9), whether the stop is reached (h1 below the
    penetration) or not."""
    params = model(h1=h1, **FREE)
    t_end = 0.02
    run = simulate(10.0, 0.0, t_end, x0=-1e-6, v0=v0, params=params, rtol=1e-12, atol=1e-15,
                   window=Window(t_end - 1e-3, t_end, 1e-3), record=("impacts", "penetrations"))  # fmt: skip
    ref = solve_reference(10.0, t_end, x0=-1e-6, v0=v0, params=params, rtol=1e-13, atol=1e-18)
    assert ref["impacts_t"].size == 1 and ref["final"][0] < params.xI
    e_core, e_ref = -run.trajectory["v"][-1] / v0, -ref["final"][1] / v0
    assert e_core == pytest.approx(e_ref, abs=1e-6) and e_ref == pytest.approx(1.0, abs=1e-9)
    assert run.events["penetrations"]["h"][0] == pytest.approx(ref["penetrations_h"][0], rel=1e-9)


def test_the_second_stop_is_a_surface_the_core_splits_at():
    """A contact that reaches h1 takes steps that end on it: the step count with the split is far
    below what steps across the kink of (h - h1)^1.5 cost, and the deepest penetration agrees with
    the energy balance kI h^2.5 / 2.5 + k2 (h - h1)^2.5 / 2.5 = m v0^2 / 2 to 1e-9."""
    from scipy.optimize import brentq

    params = model(**FREE)
    v0 = 0.3
    run = simulate(10.0, 0.0, 0.01, x0=-1e-6, v0=v0, params=params, rtol=1e-12, atol=1e-15, record=("penetrations",))
    h = run.events["penetrations"]["h"][0]

    def energy(d):
        return params.kI * d**2.5 / 2.5 + params.k2 * max(d - params.h1, 0.0) ** 2.5 / 2.5 - params.m * v0**2 / 2

    assert h > params.h1 and h == pytest.approx(brentq(energy, 0.0, 1e-2, xtol=1e-16, rtol=1e-15), rel=1e-9)


def test_it_is_named_as_the_other_laws(tmp_path):
    path = tmp_path / "rig.yaml"
    path.write_text(
        "format: impactosc-model/1\ncontact: {law: two-stage, h1: 5.0e-5, k2: 2.0e+9}\nparameters: {k: 1500}\n"
    )
    params = read_model_file(path).params
    assert params == dataclasses.replace(model(), k=1500.0)
    assert apply_overrides(params, ["h1=1e-4"]).h1 == 1e-4
    with pytest.raises(ValueError, match="h1"):
        apply_overrides(params, ["h1=-1e-4"])
    assert shown_parameters(LAW)[-2:] == ("h1", "k2")
    assert law_quantities(LAW)[-2:] == ("h1", "k2/m")
