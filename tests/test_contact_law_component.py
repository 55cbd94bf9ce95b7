"""A contact law is one component: every consumer asks it, none tests a law by its name or code.

Run alone: .venv/bin/python -m pytest tests/test_contact_law_component.py (docs/development.md).
"""

import ast
import dataclasses
import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.explorer.view import shown_parameters, with_law
from impactosc.identification.fitted_parameters import QUANTITIES, law_quantities, quantity_unit
from impactosc.model.contact_laws import LAWS, OWN_PARAMETERS, law_of
from impactosc.model.model_file import apply_overrides, read_model_file, write_model_file
from impactosc.model.parameters import N_PARAMS, ModelParams, UntestedParameterWarning, unit_of
from impactosc_study.config import load_schema

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
#: Where a law may be named: its own package, and the SciPy reference that writes each law from
#: its published form (the independent check).
OWN_PLACES = (
    ROOT / "src" / "impactosc" / "model" / "contact_laws",
    ROOT / "src" / "impactosc_bench" / "scipy_reference.py",
)
#: The names of the laws' codes before they were components: no code may use them (p[P_LAW], the
#: law's index in the array, may be written and read by the laws' accessor, never compared).
CODE_NAMES = {"RESTITUTION_FIRST", "KELVIN_VOIGT", "HERTZ", "HUNT_CROSSLEY", "LAW_CODES", "BC_ONLY"}


def _is_law(node) -> bool:
    if isinstance(node, ast.Constant):
        return node.value in LAWS
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return any(_is_law(e) for e in node.elts)
    return False


def _law_tests(tree: ast.AST) -> list[tuple[int, str]]:
    """(line, what) of each place in `tree` that tests a law by its name or code."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare) and any(_is_law(n) for n in (node.left, *node.comparators)):
            found.append((node.lineno, "compares with a law's name"))
        elif isinstance(node, ast.Compare) and any(getattr(n, "id", "") == "P_LAW" for n in ast.walk(node)):
            found.append((node.lineno, "compares the law's index"))
        elif isinstance(node, ast.Subscript) and _is_law(node.slice):
            found.append((node.lineno, "looks a law up by its name"))
        elif isinstance(node, ast.Call) and any(_is_law(a) for a in node.args):
            if getattr(node.func, "id", getattr(node.func, "attr", "")) in ("law_of", "get"):
                found.append((node.lineno, "looks a law up by its name"))
        elif isinstance(node, ast.Name) and node.id in CODE_NAMES:
            found.append((node.lineno, f"uses {node.id}"))
        elif isinstance(node, ast.Attribute) and node.attr == "code" and getattr(node.value, "id", "") == "law":
            found.append((node.lineno, "reads a law's code"))
    return found


def _own_place(path: Path) -> bool:
    return any(path == place or place in path.parents for place in OWN_PLACES)


def test_no_code_outside_the_laws_tests_a_law_by_its_name_or_code():
    """The check: every Python file of src/ and workflow/ (outside the laws' package and the SciPy
    reference), parsed, and every rules file, read: no comparison with a law's name, no look-up of
    one by name, no law code. Consumers ask the law's component instead."""
    bad = []
    for path in sorted([*(ROOT / "src").rglob("*.py"), *(ROOT / "workflow").rglob("*.py")]):
        if not _own_place(path):
            bad += [
                f"{path.relative_to(ROOT)}:{line}: {what}" for line, what in _law_tests(ast.parse(path.read_text()))
            ]
    names = "|".join(re.escape(n) for n in LAWS)
    pattern = re.compile(
        rf"""(==|!=)\s*["']({names})["']|["']({names})["']\s*(==|!=)|(law_of|LAWS)\s*[\[(]\s*["']({names})["']"""
    )
    for path in [ROOT / "Snakefile", *sorted((ROOT / "workflow" / "rules").glob("*.smk"))]:
        for i, line in enumerate(path.read_text().splitlines(), 1):
            if pattern.search(line) or any(re.search(rf"\b{c}\b", line) for c in CODE_NAMES):
                bad.append(f"{path.relative_to(ROOT)}:{i}: tests a law by its name or code")
    assert not bad, "\n".join(bad)


def test_the_check_finds_what_it_looks_for():
    """The scan itself: each kind of test by name or code is found (else the check above could not fail)."""
    code = 'if p.law == "kelvin-voigt": pass\nx = LAWS["flores"]\ny = law_of("bc")\nz = p[P_LAW] >= RESTITUTION_FIRST\n'
    found = _law_tests(ast.parse(code + "w = p[P_LAW] == 6\n"))
    assert [line for line, _ in found].count(1) == 1 and {2, 3, 4, 5} <= {line for line, _ in found}
    assert not _law_tests(ast.parse('law = law_of(name)\nif "e" in law.own: pass\n'))


def _model(law, **changes):
    component = law_of(law)
    values = {"n1": component.n1} if component.n1 is not None else {}
    with warnings.catch_warnings():  # a linear law's n1 = 1 lies outside model BC's tested exponents
        warnings.simplefilter("ignore", UntestedParameterWarning)
        return ModelParams(law=law, **{**values, **changes})


@pytest.mark.parametrize("law", list(LAWS))
def test_every_law_is_one_component_that_every_consumer_reads(law, tmp_path):
    component = LAWS[law]
    params = _model(law)
    # its own parameters: a unit, a meaning, a valid default, a range that refuses what lies outside
    for prm in component.parameters:
        assert OWN_PARAMETERS[prm.name] == prm and prm.unit and prm.meaning
        assert prm.problem(prm.default) is None
        below = prm.low - 1.0 if prm.low > -math.inf else None
        if below is not None:
            with pytest.raises(ValueError, match=f"parameter {prm.name}"):
                dataclasses.replace(params, **{prm.name: below})
        assert unit_of(prm.name, params.n1)
    # the core's array: the law's place in the family, and nothing else of its name
    p = params.as_array(40.0)
    assert p.shape == (N_PARAMS,) and np.all(np.isfinite(p[:12]))
    onset, turn = component.exponents(params)
    assert onset == params.n1 and 0 < turn <= 1
    # the schema's law list, the explorer's fields, identification's quantities, model files
    assert law in load_schema(SCHEMA)["properties"]["model"]["properties"]["contact"]["properties"]["law"]["enum"]
    assert shown_parameters(law) == component.fields and set(component.own) <= set(component.fields)
    assert with_law(ModelParams(), law).n1 == (component.n1 if component.n1 is not None else ModelParams().n1)
    quantities = law_quantities(law)
    assert set(component.quantities) <= set(quantities) <= set(QUANTITIES)
    assert all(quantity_unit(q, params.n1) for q in quantities)
    path = write_model_file(tmp_path / "m.yaml", params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UntestedParameterWarning)
        assert read_model_file(path).params == params


@pytest.mark.parametrize(
    ("law", "items", "expected"),
    [("hertz-viscous", ["cI=400"], {"cI": 400.0}), ("two-stage", ["h1=5e-5", "k2=2e9"], {"h1": 5e-5, "k2": 2e9})],
)
def test_the_new_laws_are_named_as_the_others(law, items, expected, tmp_path):
    """Model files, --param and the config's model.contact name the laws added by their definition alone."""
    import yaml

    from impactosc_study.config import validate_config

    params = apply_overrides(_model(law), items)
    assert all(getattr(params, k) == v for k, v in expected.items())
    own = ", ".join(f"{k}: {v!r}" for k, v in expected.items())
    path = tmp_path / "rig.yaml"
    path.write_text(f"format: impactosc-model/1\ncontact: {{law: {law}, {own}}}\nparameters: {{}}\n")
    assert read_model_file(path).params == params
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    config["model"] = {"contact": {"law": law, **expected}}
    checked = validate_config(config, SCHEMA)
    assert checked["model"]["law"] == law and all(checked["model"][k] == v for k, v in expected.items())
    with pytest.raises(ValueError, match="has no"):
        apply_overrides(_model("hertz"), items)


def test_other_laws_keep_their_impact_times():
    """Each law's impacts over the chaotic scene's first 1.5 s from rest, within 2.5e-9 s (the
    core's accuracy against SciPy, which tests/test_contact_laws.py checks law by law) of the core
    before the laws were components (tests/data/make_law_impacts_reference.py): the generic
    location of the cut finds Kelvin-Voigt's where its own code did (measured: 2.2e-15 s at most
    with the same steps; free flight in closed form and the onset's first step move the
    impacts by up to 3.8e-10 s, Flores's last, as the chaos grows a step's truncation error)."""
    data = json.loads((ROOT / "tests" / "data" / "law_impacts_before_components.json").read_text())
    for law, ref in data["laws"].items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UntestedParameterWarning)
            params = ModelParams(**ref["params"])
        t = simulate(data["omega"], 0.0, data["horizon"], params=params, record=("impacts",)).events["impacts"]["t"]
        assert t.size == len(ref["impacts_t"]) > 4, law
        assert np.max(np.abs(t - ref["impacts_t"])) < 2.5e-9, law
