"""The workflow config validates, bad configs fail with a message naming the key, and
config/README.md is the schema rendered."""

import copy
import dataclasses
import json
from pathlib import Path

import pytest
import yaml

from impactosc.model.contact_laws import OWN_PARAMETERS
from impactosc.model.parameters import ModelParams
from impactosc_study.config import ConfigError, load_config, validate_config
from impactosc_study.config_docs import main as config_docs_main
from impactosc_study.config_docs import render_file

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
CONFIG = ROOT / "config" / "config.yaml"
README = ROOT / "config" / "README.md"


@pytest.fixture()
def config():
    return yaml.safe_load(CONFIG.read_text())


def alias_bomb(levels: int, indent: str = "  ") -> list:
    """YAML lines anchoring l0 .. l<levels - 1>, each a list of nine aliases of the one before (a
    'billion laughs'): a few lines of text, 9**levels values once its aliases are expanded."""
    lines = [f"{indent}l0: &l0 [x, x, x, x, x, x, x, x, x]"]
    lines += [f"{indent}l{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 9)}]" for i in range(1, levels)]
    return lines


def test_default_config_is_valid_and_is_model_bc():
    cfg = load_config(CONFIG, SCHEMA)
    assert ModelParams(**cfg["model"]) == ModelParams()
    assert cfg["scenes"]["period4"]["omega"] == 23.03


def test_schema_documents_every_model_key():
    model = yaml.safe_load(SCHEMA.read_text())["properties"]["model"]["properties"]
    # the law and its own numbers come as one mapping, model.contact
    own = set(OWN_PARAMETERS)  # the laws' own numbers: model.contact's, filled in from the laws
    assert set(model) == {f.name for f in dataclasses.fields(ModelParams)} - {"law", *own} | {"file", "contact"}
    for key, sub in model.items():
        assert "description" in sub and ("default" in sub or key in ("file", "contact")), key


def test_model_keys_change_model_bc_one_by_one(config):
    config["model"] = {"k": 1500.0}
    assert ModelParams(**validate_config(config, SCHEMA)["model"]) == ModelParams(k=1500.0)


@pytest.mark.parametrize(
    "mutate, key",
    [
        (lambda c: c["model"].__setitem__("m", -1.0), "model.m"),
        (lambda c: c["model"].__setitem__("mass", 1.0), "model.mass"),
        (lambda c: c["model"].__setitem__("k", "stiff"), "model.k"),
        (lambda c: c["solver"].__setitem__("rtol", -1e-9), "solver.rtol"),
        (lambda c: c["scenes"]["chaos"].__setitem__("duration", -400), "scenes.chaos.duration"),
        (lambda c: c["scenes"]["chaos"].__setitem__("omgea", 4), "scenes.chaos.omgea"),
        (lambda c: c["scenes"]["chaos"].__setitem__("events", ["impacts", "sparks"]), "scenes.chaos.events.1"),
        (lambda c: c["scenes"]["chaos"]["window"].__setitem__("stop", 1e4), "scenes.chaos.window"),
    ],
)
def test_bad_config_names_the_key(config, mutate, key):
    bad = copy.deepcopy(config)
    mutate(bad)
    with pytest.raises(ConfigError) as err:
        validate_config(bad, SCHEMA)
    assert f"  {key}:" in str(err.value), str(err.value)


def test_missing_config_file(tmp_path):
    with pytest.raises(ConfigError, match="does not exist"):
        load_config(tmp_path / "none.yaml", SCHEMA)


def _errors(cfg) -> str:
    with pytest.raises(ConfigError) as err:
        validate_config(cfg, SCHEMA)
    return str(err.value)


def test_typo_is_an_unknown_key_with_a_suggestion(config):
    config["model"] = ModelParams().to_dict()  # every parameter listed, one misspelt
    config["model"]["kl"] = config["model"].pop("kI")
    config["periodic"] = {"branch": {"strat": 40.0}}
    config["chaotic"] = {"second_train": {"evnets": "a.h5", "label": "x"}}
    msg = _errors(config)
    assert "  model.kl: unknown key (did you mean 'kI'?)" in msg, msg
    assert "  periodic.branch.strat: unknown key (did you mean 'start'?)" in msg, msg
    assert "  chaotic.second_train.evnets: unknown key (did you mean 'events'?)" in msg, msg
    assert "is a required property" not in msg, msg  # the suggested key is not reported missing too


def test_unknown_key_without_close_match_lists_the_valid_keys(config):
    config["solver"]["zzz"] = 1
    msg = _errors(config)
    assert "  solver.zzz: unknown key; valid keys: rtol, atol" in msg, msg


def test_missing_required_key_is_reported(config):
    del config["scenes"]["chaos"]["omega"]
    assert "  scenes.chaos: 'omega' is a required property" in _errors(config)
    config["scenes"]["chaos"]["speed"] = 1.0  # an unknown key not close to omega does not hide it
    msg = _errors(config)
    assert "  scenes.chaos: 'omega' is a required property" in msg and "  scenes.chaos.speed: unknown key" in msg, msg


def test_config_readme_is_the_schema_rendered():
    assert README.read_text(encoding="utf-8") == render_file(SCHEMA), (
        "config/README.md is out of date with the schema; regenerate it with `make config-docs` "
        "(from the repository root)"
    )


def test_config_docs_lists_nested_and_map_keys(tmp_path, capsys):
    text = render_file(SCHEMA)
    for row in (
        "| `model.kI` | number |",
        "| `scenes.<name>.omega` | number | required | > 0 |",
        "| `scenes.<name>.window.dt` |",
        "| `bifurcation.sweeps.<name>.step` |",
        "| `measured.surrogate.mismatch.<name>` | number |",
        "| `chaotic.second_train.events` |",
        "| `chaotic.analysis.kde_bandwidth` | string or number |",
    ):
        assert row in text, row
    out = tmp_path / "README.md"
    out.write_text("stale\n")
    assert config_docs_main(["--schema", str(SCHEMA), "--output", str(out), "--check"]) == 1
    assert config_docs_main(["--schema", str(SCHEMA), "--output", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == text
    assert config_docs_main(["--schema", str(SCHEMA), "--output", str(out), "--check"]) == 0
    capsys.readouterr()


@pytest.mark.parametrize(
    "segment, message",
    [
        ({"doubling_of": {"segment": "nowhere", "near": 37.3}, "w_range": [37.0, 45.0]}, "no segment named 'nowhere'"),
        ({"seed": {"omega": 50.0, "n_periods": 1}, "w_range": [19.0, 45.0]}, "lies outside w_range"),
        ({"seed": {"omega": 30.0, "n_periods": 1}, "w_range": [45.0, 19.0]}, "lo < hi"),
    ],
)
def test_bad_orbit_segment_is_named(config, segment, message):
    config["periodic_orbits"]["segments"]["extra"] = segment
    with pytest.raises(ConfigError, match=message) as err:
        validate_config(config, SCHEMA)
    assert "periodic_orbits.segments.extra" in str(err.value)


def test_orbit_segments_whose_parents_form_a_cycle_are_refused(config):
    segs = config["periodic_orbits"]["segments"]
    segs["a"] = {"doubling_of": {"segment": "b", "near": 38.0}, "w_range": [37.0, 45.0]}
    segs["b"] = {"doubling_of": {"segment": "a", "near": 38.0}, "w_range": [37.0, 45.0]}
    with pytest.raises(ConfigError, match="comes back to"):
        validate_config(config, SCHEMA)


def test_orbit_segment_needs_exactly_one_start(config):
    config["periodic_orbits"]["segments"]["both"] = {
        "seed": {"omega": 38.0, "n_periods": 2},
        "doubling_of": {"segment": "period1", "near": 37.28},
        "w_range": [37.0, 45.0],
    }
    with pytest.raises(ConfigError, match=r"periodic_orbits\.segments\.both"):
        validate_config(config, SCHEMA)


def test_x_impact_noise_must_be_a_study_level(config):
    config["measured"]["noise_study"]["x_impact_noise"] = [3e-6]
    with pytest.raises(ConfigError, match=r"measured.noise_study.x_impact_noise: \[3e-06\] not among"):
        validate_config(config, SCHEMA)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"values": [-1.0e-3, -3.0e-3]}, r"two_parameter\.values: must be \[lo, hi\] with lo < hi"),
        ({"values": [-3.0e-3, -2.5e-3]}, r"two_parameter\.values: .* must contain the model's xI = -0.002086"),
        ({"w_range": [45.0, 17.0]}, r"two_parameter\.w_range: must be \[lo, hi\]"),
        ({"ds": 1.0e-5}, r"two_parameter\.ds: must exceed ds_min"),
        ({"parameter": "m0e", "values": [0.01, 0.03]}, r"two_parameter\.parameter: m0e differs from bifurcation\.map2d"),
        ({"curves": {"c": {"segment": "nowhere", "kind": "fold", "near": 19.5}}},
         r"two_parameter\.curves\.c\.segment: no segment named 'nowhere'"),
        ({"curves": {"c": {"segment": "period1", "kind": "flip", "near": 19.5}}}, r"two_parameter\.curves\.c\.kind"),
    ],
)  # fmt: skip
def test_bad_two_parameter_section_is_named(config, change, message):
    config.setdefault("two_parameter", {}).update(change)
    with pytest.raises(ConfigError, match=message):
        validate_config(config, SCHEMA)


def test_two_parameter_in_m0e_with_its_map(config):
    config["two_parameter"].update(parameter="m0e", values=[0.012, 0.024])
    config["bifurcation"]["map2d"]["parameter"] = "m0e"
    assert validate_config(config, SCHEMA)["two_parameter"]["parameter"] == "m0e"


@pytest.mark.parametrize(
    "override, message",
    [
        ({"study": "my rig"}, "study: 'my rig' is not a safe directory name"),
        ({"study": "../paper"}, "study: '../paper' is not a safe directory name"),
        ({"study": ""}, "study: '' is not a safe directory name"),
        ({"study": 2024}, "study: 2024 is not a string"),
        ({"compare": {"study": "a/b"}}, "compare.study: 'a/b' is not a safe directory name"),
        ({"compare": {"study": "paper"}}, "compare.study: 'paper' is this study"),
    ],
)
def test_bad_study_name_is_named(config, override, message):
    with pytest.raises(ConfigError, match="invalid configuration") as err:
        validate_config({**config, **override}, SCHEMA)
    assert message in str(err.value), str(err.value)


def test_study_names_the_results_folder_of_a_panels_file(config):
    paper = validate_config(config, SCHEMA)
    assert paper["study"] == "paper" and paper["compare"] == {"study": None}
    assert paper["chaotic"]["second_train"] is True and paper["bifurcation"]["fig02"]["experimental"] is True
    made_elsewhere = {"events": "results/{study}/rig_events.h5", "label": "rig"}
    rig = validate_config(
        {**config, "study": "my_rig-2", "compare": {"study": "paper"}, "chaotic": {"second_train": made_elsewhere}},
        SCHEMA,
    )
    assert rig["chaotic"]["second_train"]["events"] == "results/my_rig-2/rig_events.h5"
    assert rig["compare"]["study"] == "paper"


@pytest.mark.parametrize("key", ["chaos", "fig02"])
def test_a_label_without_a_record_is_refused(config, key):
    """The surrogate is always labelled as the surrogate: a label names a record."""
    measured = copy.deepcopy(config["measured"])
    measured[key]["label"] = "rig 3"
    with pytest.raises(ConfigError, match=rf"measured\.{key}\.label: 'rig 3' names a record, but none is configured"):
        validate_config({**config, "measured": measured}, SCHEMA)


def test_analysis_defaults_have_one_value():
    """chaotic.analysis: AnalysisOptions' defaults (the library's home of them), the schema's defaults
    (what a config without the key gets) and the paper's config.yaml say the same, key for key."""
    from impactosc.statistics.impact_train import AnalysisOptions

    library = {f.name: f.default for f in dataclasses.fields(AnalysisOptions)}
    library = {k: list(v) if isinstance(v, tuple) else v for k, v in library.items()}
    schema = yaml.safe_load(SCHEMA.read_text())["properties"]["chaotic"]["properties"]["analysis"]["properties"]
    assert set(schema) == set(library), set(schema) ^ set(library)
    assert {k: s["default"] for k, s in schema.items()} == library
    paper = yaml.safe_load(CONFIG.read_text())["chaotic"]["analysis"]
    assert paper == {k: library[k] for k in paper}
    assert AnalysisOptions.from_config(load_config(CONFIG, SCHEMA)["chaotic"]["analysis"]) == AnalysisOptions()


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_nan_and_infinity_are_refused(config, value):
    # a schema's type: number lets YAML's .nan and .inf through (and nan passes every minimum)
    config["model"] = {"k": value}
    with pytest.raises(ConfigError, match=r"  model\.k: .* is not a finite number"):
        validate_config(config, SCHEMA)
    bad = copy.deepcopy(config)
    bad["model"] = {}
    bad["two_parameter"]["values"] = [-3.0e-3, value]
    with pytest.raises(ConfigError, match=r"  two_parameter\.values\[1\]: .* is not a finite number"):
        validate_config(bad, SCHEMA)


@pytest.mark.parametrize(
    ("text", "fix"),
    [("1e-12", "1.0e-12"), ("1e16", "1.0e+16"), ("1.5e5", "1.5e+5")],
)
def test_a_number_yaml_reads_as_a_string_is_named_with_its_rule(config, text, fix):
    config["model"] = yaml.safe_load(f"eps: {text}")
    assert config["model"]["eps"] == text  # YAML 1.1: no dot or no exponent sign, a string
    with pytest.raises(ConfigError) as err:
        validate_config(config, SCHEMA)
    assert f"model.eps: '{text}' is not of type 'number' (YAML 1.1 reads" in str(err.value), str(err.value)
    assert f"write {fix}" in str(err.value)
    config["model"] = yaml.safe_load(f"eps: {fix}")  # the written fix reads as the number
    assert validate_config(config, SCHEMA)["model"]["eps"] == float(text)


def test_a_config_file_with_a_key_twice_is_refused(tmp_path):
    path = tmp_path / "twice.yaml"
    path.write_text(Path(CONFIG).read_text() + "\nstudy: other\nstudy: again\n")
    with pytest.raises(ConfigError, match=r"twice\.yaml: key 'study' given twice"):
        load_config(path, SCHEMA)


def test_a_value_far_larger_than_its_text_is_echoed_cut(config):
    # six levels of aliases: 531441 values (a repr of 2.6 MB) from seven lines of YAML
    huge = yaml.safe_load("\n".join(["anchors:", *alias_bomb(6)]))["anchors"]["l5"]
    for key, mutate in [
        ("model.k", lambda c: c["model"].__setitem__("k", huge)),
        ("study", lambda c: c.__setitem__("study", huge)),
        ("measured.chaos.label", lambda c: c["measured"]["chaos"].__setitem__("label", "a" * 10**6)),
    ]:
        bad = copy.deepcopy(config)
        mutate(bad)
        msg = _errors(bad)
        assert f"  {key}: " in msg and len(msg) < 600, msg[:1000]
        assert max(len(line) for line in msg.splitlines()) < 300, msg[:1000]
    assert "  model.k: [[[[[...], [...]," in _errors({**config, "model": {"k": huge}})


def test_a_config_file_not_yaml_is_named_with_its_line(tmp_path):
    path = tmp_path / "tab.yaml"
    path.write_text("study: paper\nmodel:\n\tk: 1500.0\n")
    with pytest.raises(ConfigError) as err:
        load_config(path, SCHEMA)
    assert str(err.value) == (
        f"invalid configuration:\n  {path}: not YAML: found character '\\t' that cannot start any token "
        "(line 3, column 1)"
    )
    path.write_text(f"study: {'[' * 10**4}{']' * 10**4}\n")
    with pytest.raises(ConfigError, match="not YAML: collections nested too deep to read"):
        load_config(path, SCHEMA)
    # JSON indented with tabs is no YAML, but a config file Snakemake reads (JSON first): as is ours
    path = tmp_path / "tabs.json"
    path.write_text(json.dumps(yaml.safe_load(CONFIG.read_text()), indent="\t"))
    assert load_config(path, SCHEMA) == load_config(CONFIG, SCHEMA)


def test_a_config_file_whose_aliases_expand_beyond_reason_is_refused(tmp_path):
    path = tmp_path / "laughs.yaml"
    path.write_text("\n".join(["bomb:", *alias_bomb(7), "model: {k: *l6}", ""]))
    with pytest.raises(ConfigError) as err:
        load_config(path, SCHEMA)
    msg = str(err.value)
    assert msg == (
        f"invalid configuration:\n  {path}: its aliases (*name) add 11,434,267 values to the 29 it writes, more "
        "than the 100,000 allowed (aliases nested in aliases multiply: write the values out)"
    ), msg[:1000]


#: Models the schema lets through but the model refuses: the config check builds the model once
REFUSED_MODELS = [
    (
        {"contact": {"law": "flores", "e": 1.0e-200}},
        "model.contact.e: model parameter e = 1e-200 is beyond what the model evaluates (|e| from 1e-100 to 1e+100, "
        "or 0 where allowed)",
    ),
    (
        {"n1": 1.5, "contact": {"law": "kelvin-voigt", "cI": 100}},
        "model.n1: the kelvin-voigt law is linear in the penetration: n1 = 1, got 1.5",
    ),
]


@pytest.mark.parametrize(("model", "expected"), REFUSED_MODELS, ids=["flores-e", "kelvin-voigt-n1"])
def test_a_model_every_job_would_refuse_is_refused_by_the_check(config, model, expected):
    config["model"] = model
    with pytest.raises(ConfigError) as err:
        validate_config(config, SCHEMA)
    assert str(err.value) == f"invalid configuration:\n  {expected}"


def test_a_model_outside_the_tested_ranges_passes_the_check(config):
    config["model"] = {"k": 1.0e5, "contact": {"law": "kelvin-voigt", "cI": 100}}  # k and n1 = 1 untested
    model = validate_config(config, SCHEMA)["model"]  # pytest makes a warning an error: none is raised
    assert (model["k"], model["n1"], model["law"]) == (1.0e5, 1.0, "kelvin-voigt")
