"""The hertz-viscous law, F = max(0, kI h^n1 + cI v): added by its definition alone
(impactosc/model/contact_laws/hertz_viscous.py), checked against SciPy on its published form
split at its switching surfaces (impactosc_bench.scipy_reference), and named as every law is."""

import dataclasses
import warnings

import numpy as np
import pytest

from impactosc.core.simulation import Window, simulate
from impactosc.explorer.view import shown_parameters, with_law
from impactosc.identification.fitted_parameters import law_quantities
from impactosc.model.model_file import apply_overrides, read_model_file
from impactosc.model.parameters import ModelParams, UntestedParameterWarning
from impactosc_bench.scipy_reference import solve_reference

LAW = "hertz-viscous"
#: a free impact: no spring, forcing or friction worth the name (the smallest values the model takes)
FREE = dict(k=1e-60, c=0.0, T=0.0, m0e=1e-60, xI=0.0)


def model(**changes):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UntestedParameterWarning)
        return ModelParams(law=LAW, **{"cI": 400.0, **changes})


def test_the_chaotic_scene_from_rest_agrees_with_scipy_split_at_its_cut():
    """3 s of w = 40.86 rad/s from rest: every impact within 1e-8 s of SciPy at rtol 1e-13 on
    max(0, kI h^1.5 + cI v), split at onset, exit and the cut kI h^1.5 + cI v = 0 (a curve in (h, v))."""
    params = model()
    run = simulate(40.86, 0.0, 3.0, params=params, rtol=1e-12, atol=1e-15, record=("impacts",))
    ref = solve_reference(40.86, 3.0, params=params, rtol=1e-13, atol=1e-16)
    t_core, t_ref = run.events["impacts"]["t"], ref["impacts_t"]
    assert t_core.size == t_ref.size > 10
    assert np.max(np.abs(t_core - t_ref)) < 1e-8


@pytest.mark.parametrize("v0", [0.1, 0.25, 0.4])
@pytest.mark.parametrize("cI", [100.0, 400.0, 1600.0])
def test_a_free_impact_restitutes_as_scipy_says(v0, cI):
    """No spring, friction or forcing: the velocity after the exit over v0, within 1e-6 of SciPy's
    split integration (measured: 1e-11 or closer). The damper lets go inside the obstacle, at the
    cut, and the cart leaves with the velocity it had there."""
    params = model(cI=cI, **FREE)
    t_end = 0.02
    run = simulate(10.0, 0.0, t_end, x0=-1e-6, v0=v0, params=params, rtol=1e-12, atol=1e-15,
                   window=Window(t_end - 1e-3, t_end, 1e-3))  # fmt: skip
    ref = solve_reference(10.0, t_end, x0=-1e-6, v0=v0, params=params, rtol=1e-13, atol=1e-18)
    assert ref["impacts_t"].size == 1 and ref["final"][0] < params.xI
    e_core, e_ref = -run.trajectory["v"][-1] / v0, -ref["final"][1] / v0
    assert 0.0 < e_ref < 1.0 and e_core == pytest.approx(e_ref, abs=1e-6)


def test_it_is_named_as_the_other_laws(tmp_path):
    path = tmp_path / "rig.yaml"
    path.write_text("format: impactosc-model/1\ncontact: {law: hertz-viscous, cI: 400}\nparameters: {k: 1500}\n")
    params = read_model_file(path).params
    assert params == dataclasses.replace(model(), k=1500.0)
    assert apply_overrides(params, ["cI=250"]).cI == 250.0
    assert shown_parameters(LAW)[-1] == "cI" and "b" not in shown_parameters(LAW)
    assert with_law(ModelParams(), LAW).n1 == 1.5  # Hertz's exponent: not a linear law
    assert law_quantities(LAW)[-1] == "cI/m"
