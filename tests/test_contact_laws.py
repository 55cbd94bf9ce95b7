"""The contact laws: each against its published form integrated by SciPy (an independent
implementation, impactosc_bench.scipy_reference), model files and the config naming them, and
every mistake in naming one refused with the key."""

import dataclasses
import math
import warnings

import numpy as np
import pytest
import yaml
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from test_config import CONFIG, SCHEMA  # tests/ is on sys.path (pytest's prepend import mode)

from impactosc.core.driver import initial_state, resume, run_settings, step_piece, workspace
from impactosc.core.layout import N_COUNT, S_FIELD, S_V, S_X
from impactosc.core.simulation import Window, simulate
from impactosc.model.contact_laws import LAWS
from impactosc.model.equations import CONTACT, CUT
from impactosc.model.model_file import FORMAT, apply_overrides, read_model_file, write_model_file
from impactosc.model.parameters import ModelParams, UntestedParameterWarning
from impactosc_bench.scipy_reference import RESTITUTION_CHI, model_forces, solve_reference
from impactosc_study.config import ConfigError, validate_config

RESTITUTION = list(RESTITUTION_CHI)
#: a free impact: no spring, forcing or friction worth the name (the smallest values the model takes)
FREE = dict(k=1e-60, c=0.0, T=0.0, m0e=1e-60, xI=0.0)

#: A model of each law that takes numbers of its own (a linear law's kI in N/m)
EXAMPLES = {"kelvin-voigt": {"cI": 60.0, "n1": 1.0, "kI": 2.0e6}, "hertz-viscous": {"cI": 400.0}}


def law_params(law, **changes):
    own = {"e": 0.7} if "e" in LAWS[law].own else EXAMPLES.get(law, {})
    with warnings.catch_warnings():  # a linear law's n1 = 1 lies outside model BC's tested exponents
        warnings.simplefilter("ignore", UntestedParameterWarning)
        return ModelParams(law=law, **{**own, **changes})


def core_restitution(params, v0=0.2):
    """e_eff = -v_exit / v0 of a free impact at v0 by the core (the velocity after the exit,
    constant in free flight)."""
    run = simulate(10.0, 0.0, 0.02, x0=-1e-6, v0=v0, params=params, rtol=1e-12, atol=1e-15,
                   window=Window(0.019, 0.02, 0.001))  # fmt: skip
    return -run.trajectory["v"][-1] / v0


def scipy_restitution(params, v0=0.2):
    """The same by SciPy at rtol 1e-13 on the law's published form (the reference's pieces)."""
    ref = solve_reference(10.0, 0.02, x0=-1e-6, v0=v0, params=params, rtol=1e-13, atol=1e-18)
    assert ref["impacts_t"].size == 1
    # the exit velocity: the contact integrated again, alone, on the law's force
    state = {"chi": RESTITUTION_CHI[params.law](params.e, v0) if params.law in RESTITUTION_CHI else 0.0}
    _, contact, _ = model_forces(params, 10.0, state)

    def rhs(t, y):
        return [y[1], -contact(y[0], y[1]) / params.m]

    def leave(t, y):
        return y[0] - params.xI

    leave.terminal, leave.direction = True, -1
    sol = solve_ivp(rhs, (0, 1.0), [params.xI, v0], method="DOP853", rtol=1e-13, atol=1e-18, events=leave,
                    first_step=1e-10)  # fmt: skip
    return -sol.y_events[0][0][1] / v0


@pytest.mark.parametrize("law", [*RESTITUTION, "hertz", "kelvin-voigt", "hertz-viscous"])
@pytest.mark.parametrize("e", [0.3, 0.9])
def test_a_free_impact_restitutes_as_the_law_says(law, e):
    # within 1e-6 of SciPy at rtol 1e-13 on the law's own formula (measured: 2e-12 or closer);
    # Kelvin-Voigt's restitution follows from cI (e sets its damping here: cI = 200 (1 - e) N s/m)
    own = {"e": e} if "e" in LAWS[law].own else {"cI": 200.0 * (1 - e)} if "cI" in LAWS[law].own else {}
    params = law_params(law, **own, **FREE)
    assert core_restitution(params) == pytest.approx(scipy_restitution(params), abs=1e-6)


@pytest.mark.parametrize("law", [*RESTITUTION, "hertz", "kelvin-voigt", "hertz-viscous"])
def test_chaotic_scene_impact_times_agree_with_scipy(law):
    """The chaotic scene's forcing over 3 s from rest, each law: every impact within 1e-8 s of
    SciPy at rtol 1e-13 (its error is far below; the core runs at rtol 1e-12)."""
    params = law_params(law)
    run = simulate(40.86, 0.0, 3.0, params=params, rtol=1e-12, atol=1e-15, record=("impacts",))
    ref = solve_reference(40.86, 3.0, params=params, rtol=1e-13, atol=1e-16)
    t_core, t_ref = run.events["impacts"]["t"], ref["impacts_t"]
    assert t_core.size == t_ref.size > 10
    assert np.max(np.abs(t_core - t_ref)) < 1e-8


def kelvin_voigt_restitution(m, kI, cI):
    """Closed form: the contact is the damped oscillator h'' = -(kI h + cI h') / m from h = 0,
    h' = v0 until the cut kI h + cI h' = 0; past it no force acts, so v_exit is v at the cut."""
    s = cI / (2.0 * m)
    wd = math.sqrt(kI / m - s * s)

    def bracket(t):  # (kI h + cI h') / v0
        return kI * math.sin(wd * t) / wd + cI * (math.cos(wd * t) - s / wd * math.sin(wd * t))

    t = brentq(bracket, math.pi / (2.0 * wd), math.pi / wd, xtol=1e-300, rtol=9e-16)
    return -math.exp(-s * t) * (math.cos(wd * t) - s / wd * math.sin(wd * t))


@pytest.mark.parametrize("cI", [20.0, 500.0, 2000.0])
def test_kelvin_voigt_restitution_is_its_closed_form(cI):
    # 1e-9: at rtol 1e-12 the free impact's global error is about 10 rtol (measured up to 1.4e-11
    # over cI 20-2000 N s/m and v0 0.05-1 m/s, scaling with rtol from 1e-6 down)
    params = law_params("kelvin-voigt", cI=cI, **FREE)
    assert core_restitution(params, 0.2) == pytest.approx(kelvin_voigt_restitution(params.m, params.kI, cI), abs=1e-9)


def test_kelvin_voigt_cut_is_located_on_its_line():
    """The cut kI h + cI v = 0 is an event of x and v together: the step that crosses it ends on
    it (to the bisection's last bit of the step), and the piece past it has no force."""
    params = law_params("kelvin-voigt", cI=500.0, **FREE)
    p = params.as_array(10.0)
    st = initial_state(p, 0.0, -1e-6, 0.2, 2.0 * math.pi / 10.0, math.inf)
    rs = run_settings(0.02, math.inf, 1e-10, 1e-12, 0, 2.0 * math.pi / 10.0)
    ws = workspace()
    cnt = np.zeros(N_COUNT, dtype=np.int64)
    ev, win = np.empty((16, 4)), np.empty(0)
    resume(p, st, cnt, ws[3])
    fields = []
    while st[S_FIELD] != CUT and len(fields) < 10_000:
        fields.append(int(st[S_FIELD]))
        ev, _ = step_piece(p, st, cnt, rs, ws, ev, 0, win, win, math.inf)
    assert CONTACT in fields and st[S_FIELD] == CUT
    h, v = st[S_X] - params.xI, st[S_V]
    # on the line to a step's share of rounding: |kI h + cI v| against kI h's size (h ~ 1e-5 m)
    assert abs(params.kI * h + params.cI * v) <= 1e-9 * params.kI * h
    assert h > 0 and v < 0


def test_model_bc_is_the_default_law_and_its_array_unchanged():
    bc = ModelParams()
    assert bc.law == "bc" and bc.as_array(40.86)[7] == bc.b  # P_B: model BC's own b


@pytest.mark.parametrize("law", list(LAWS))
def test_a_model_file_names_its_law_and_reads_back(tmp_path, law):
    params = law_params(law, k=1500.0)
    path = write_model_file(tmp_path / "m.yaml", params, stderr={"e": 0.02} if "e" in LAWS[law].own else None)
    doc = yaml.safe_load(path.read_text())
    if law == "bc":
        assert "contact" not in doc and "b" in doc["parameters"]
    else:
        assert doc["contact"]["law"] == law and not {"b", "n2", "n3"} & set(doc["parameters"])
    with warnings.catch_warnings():  # the linear law's n1 and kI lie outside model BC's tested ranges
        warnings.simplefilter("ignore", UntestedParameterWarning)
        model = read_model_file(path)
    assert model.params == params
    assert not {"b", "n2", "n3"} & set(model.defaulted) or law == "bc"
    if "e" in LAWS[law].own:
        assert model.stderr == {"e": 0.02}


@pytest.mark.parametrize(
    ("contact", "parameters", "expected"),
    [
        ("{law: flores}", "", "contact.e: missing: the flores law needs it"),
        ("{law: hertz, e: 0.5}", "", "contact.e: the hertz law takes nothing beside law"),
        ("{law: floris, e: 0.5}", "", "contact.law: contact law 'floris' is not one of"),
        ("{e: 0.5}", "", "contact: a mapping with the law's name"),
        ("{law: flores, e: 1.5}", "", "model parameter e must be in (0, 1]"),
        ("{law: flores, e: 0.7}", "b: 0.5", "parameters.b: the flores law has no b"),
        ("{law: kelvin-voigt, cI: 50}", "n1: 1.5", "the kelvin-voigt law is linear in the penetration: n1 = 1"),
        ("{law: kelvin-voigt, cI: 50}", "kI: {value: 2.0e+6, unit: N/m^1.5}", "kI is in 'N/m'"),
    ],
)
def test_a_bad_contact_block_is_named(tmp_path, contact, parameters, expected):
    path = tmp_path / "bad.yaml"
    path.write_text(f"format: {FORMAT}\ncontact: {contact}\nparameters: {{{parameters}}}\n")
    with pytest.raises(ValueError) as err:
        read_model_file(path)
    assert expected in str(err.value), str(err.value)


def test_kelvin_voigt_reads_kI_in_newtons_per_metre(tmp_path):
    path = tmp_path / "kv.yaml"
    path.write_text(
        f"format: {FORMAT}\ncontact: {{law: kelvin-voigt, cI: 50}}\nparameters: {{kI: {{value: 2.0e+6, unit: N/m}}}}\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UntestedParameterWarning)
        params = read_model_file(path).params
    assert (params.law, params.n1, params.kI, params.cI) == ("kelvin-voigt", 1.0, 2.0e6, 50.0)


def test_e_is_set_where_the_law_has_one():
    flores = law_params("flores")
    assert apply_overrides(flores, ["e=0.55"]).e == 0.55
    with pytest.raises(ValueError, match="the bc law has no e"):
        apply_overrides(ModelParams(), ["e=0.55"])
    with pytest.raises(ValueError, match="the flores law has no b"):
        apply_overrides(flores, ["b=0.5"])


@pytest.fixture()
def config():
    return yaml.safe_load(CONFIG.read_text())


def test_the_config_names_the_law(config):
    config["model"] = {"contact": {"law": "flores", "e": 0.6}, "k": 1500.0}
    model = validate_config(config, SCHEMA)["model"]
    assert ModelParams(**model) == dataclasses.replace(ModelParams(k=1500.0), law="flores", e=0.6)
    config["model"] = {}
    assert ModelParams(**validate_config(config, SCHEMA)["model"]) == ModelParams()


@pytest.mark.parametrize(
    ("model", "expected"),
    [
        ({"contact": {"law": "flores"}}, "model.contact.e: missing"),
        ({"contact": {"law": "hertz", "e": 0.5}}, "model.contact.e: the hertz law takes nothing"),
        ({"contact": {"law": "flores", "e": 0.5}, "b": 0.3}, "the flores law has no b"),
        ({"contact": {"law": "floris"}}, "model.contact.law"),
    ],
)
def test_a_bad_contact_in_the_config_is_named(config, model, expected):
    config["model"] = model
    with pytest.raises(ConfigError, match=expected.replace(".", r"\.")):
        validate_config(config, SCHEMA)


def test_restitution_chi_is_the_published_one():
    # Flores et al. (2011): at e = 1 every law is Hertz's (no damping); chi scales as 1 / v0
    for chi in RESTITUTION_CHI.values():
        assert chi(1.0, 0.3) == 0.0 and math.isclose(chi(0.5, 0.1), 2 * chi(0.5, 0.2))


def test_a_run_continues_inside_a_restitution_contact_with_its_onset_velocity():
    """A free impact split inside its contact: the second run, started from the first's end state
    with its contact_v0, leaves with the whole impact's velocity (without it, it is refused)."""
    params = law_params("flores", **FREE)
    whole = core_restitution(params)
    first = simulate(10.0, 0.0, 5e-6 + 2e-4, x0=-1e-6, v0=0.2, params=params, rtol=1e-12, atol=1e-15)
    x, v = first.final_state[S_X], first.final_state[S_V]
    assert x > params.xI and first.attrs["contact_v0"] == pytest.approx(0.2, rel=1e-12)
    with pytest.raises(ValueError, match="needs that contact's onset velocity, contact_v0"):
        simulate(10.0, 0.0, 0.02, x0=x, v0=v, params=params)
    rest = simulate(10.0, 0.0, 0.02, x0=x, v0=v, params=params, rtol=1e-12, atol=1e-15,
                    contact_v0=first.attrs["contact_v0"], window=Window(0.019, 0.02, 0.001))  # fmt: skip
    assert -rest.trajectory["v"][-1] / 0.2 == pytest.approx(whole, abs=1e-9)
    assert math.isnan(simulate(10.0, 0.0, 0.02, x0=-1e-6, v0=0.2, params=params).attrs["contact_v0"])  # ended free


def test_a_sweep_of_a_restitution_law_runs_through_the_chaotic_band():
    """Each w starts from the last one's end state (inside a contact with that contact's onset
    velocity, as the split run above checks): every w of the band runs."""
    from impactosc.dynamics.sweep import OK, SweepSettings, continuation

    settings = SweepSettings(n_transient=20, n_record=6, n_initial=50, params=law_params("flores"))
    res = continuation(np.linspace(40.0, 41.0, 6), settings)
    assert (res.status == OK).all() and np.isfinite(res.poincare_x).all()


def test_identification_refuses_to_fix_what_the_law_does_not_have():
    from impactosc.identification.staged_fit import identify

    with pytest.raises(ValueError, match="unknown parameter 'b' to fix for the flores law"):
        identify([object()], base=law_params("flores"), fixed={"b": 0.0})


@pytest.mark.parametrize("law", RESTITUTION)
def test_the_restitution_table_is_the_free_impact_of_scipy(law):
    """impactosc.dynamics.restitution (the restitution table's numbers) against SciPy at rtol 1e-13
    on the law's published form, within 1e-6 (the table prints 4 decimals)."""
    from impactosc.dynamics.restitution import effective_restitution

    params = law_params(law, e=0.6)
    assert effective_restitution(params, 0.05) == pytest.approx(
        scipy_restitution(law_params(law, e=0.6, **FREE), 0.05), abs=1e-6
    )


def test_a_matched_restitution_law_dissipates_what_model_bc_does():
    """The laws study's Flores: its e is the root of e_eff(e) = model BC's e_eff at 0.2 m/s. The
    core's e_eff at that e equals model BC's within 1e-8 (the root finder stops within 1e-10 in e,
    and de_eff/de is about 1; the core's own error at rtol 1e-12 is smaller still), and SciPy's free
    impact on the published form delivers it within 1e-6 (as the restitution table is checked).
    The restitution table brackets it: Flores delivers 0.470 at e = 0.5 and 0.577 at 0.6."""
    from impactosc.dynamics.restitution import effective_restitution, matched_e

    bc = ModelParams()
    target = effective_restitution(bc, 0.2)
    e = matched_e(bc, "flores", 0.2)
    assert 0.5 < e < 0.6 and 0.5 < target < 0.6
    assert effective_restitution(law_params("flores", e=e), 0.2) == pytest.approx(target, abs=1e-8)
    assert scipy_restitution(law_params("flores", e=e, **FREE), 0.2) == pytest.approx(target, abs=1e-6)


def test_the_laws_models_match_only_the_restitution_laws():
    """Hertz has no e to match and dissipates nothing at the contact (e_eff = 1 up to the core's
    tolerance, 1e-9 being far above it); model BC's row is the reference itself."""
    from impactosc.dynamics.restitution import matched_e, matched_models

    rows = {r["law"]: r for r in matched_models(ModelParams(), ["bc", "hertz", "flores"], 0.2)}
    assert rows["bc"]["e"] is None and rows["bc"]["e_eff"] == rows["bc"]["reference"]
    assert rows["hertz"]["e"] is None and rows["hertz"]["e_eff"] == pytest.approx(1.0, abs=1e-9)
    assert rows["flores"]["params"].law == "flores" and rows["flores"]["params"].e == rows["flores"]["e"]
    assert rows["flores"]["e_eff"] == pytest.approx(rows["flores"]["reference"], abs=1e-8)
    with pytest.raises(ValueError, match="the hertz law takes no e"):
        matched_e(ModelParams(), "hertz", 0.2)
    # Lankarani-Nikravesh's chi stays bounded as e -> 0: it never dissipates model BC's share (its
    # e_eff is 0.665 at e = 0.1, the restitution table), and says so rather than return a bracket end
    with pytest.raises(ValueError, match=r"no e in .* of the lankarani-nikravesh law delivers"):
        matched_e(ModelParams(), "lankarani-nikravesh", 0.2)
