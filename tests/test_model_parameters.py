"""Model BC's values are written once (ModelParams' defaults): the parameter table, the
core's array, the workflow schema and the command line's help all follow them."""

import dataclasses
import warnings
from pathlib import Path

import yaml

from impactosc.cli.parser import EPILOG
from impactosc.model import parameters
from impactosc.model.contact_laws import OWN_PARAMETERS
from impactosc.model.parameters import (
    LAW_PARAMETERS,
    N_PARAMS,
    OWN_SLOTS,
    P_LAW,
    P_OMEGA,
    P_OWN,
    PARAM_UNITS,
    PARAMETERS,
    ModelParams,
    UntestedParameterWarning,
    model_bc_summary,
)

SCHEMA = Path(__file__).resolve().parents[1] / "workflow" / "schemas" / "config.schema.yaml"


def test_the_parameter_table_names_every_field_in_the_order_of_the_array():
    family = [name for name, _, _ in PARAMETERS]
    own = [name for name, _, _ in LAW_PARAMETERS]
    # the laws' own numbers are fields after law, made from the laws' definitions
    assert [*family, "law", *own] == [f.name for f in dataclasses.fields(ModelParams)]
    assert own == list(OWN_PARAMETERS) and {"e", "cI"} <= set(own)
    names = family + own
    assert list(PARAM_UNITS) == names and all(unit and meaning for _, unit, meaning in PARAMETERS + LAW_PARAMETERS)
    assert len(family) == P_LAW and P_OMEGA < P_OWN and P_OWN + len(own) == N_PARAMS
    assert sorted(OWN_SLOTS.values()) == list(range(P_OWN, N_PARAMS))
    # each P_<NAME> indexes its own parameter: distinct values show a swapped index
    bc = ModelParams()
    with warnings.catch_warnings():  # n1 = n2 = 1.5 is the only tested value
        warnings.simplefilter("ignore", UntestedParameterWarning)
        distinct = ModelParams(
            **{name: getattr(bc, name) * (1.0 + 1e-3 * i) for i, name in enumerate(family)}, e=0.5, cI=3.0
        )
    p = distinct.as_array(40.86)
    for name in family:
        assert p[getattr(parameters, f"P_{name.upper()}")] == getattr(distinct, name), name
    for name in own:
        assert p[OWN_SLOTS[name]] == getattr(distinct, name), name
    assert p[P_OMEGA] == 40.86 and p[P_LAW] == 0  # model BC's law


def test_the_workflow_schema_defaults_are_model_bc():
    model = yaml.safe_load(SCHEMA.read_text())["properties"]["model"]["properties"]
    bc = ModelParams()
    for name, _, _ in PARAMETERS:
        assert float(model[name]["default"]) == getattr(bc, name), f"schema default of model.{name}"


def test_the_command_line_help_quotes_model_bc_from_modelparams():
    bc = ModelParams()
    summary = model_bc_summary()
    assert f"m={bc.m:g} kg" in summary and f"xI={bc.xI:g} m" in summary
    assert summary in EPILOG
