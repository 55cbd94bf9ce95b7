"""The workflow config validates, and bad configs fail with a message naming the key."""

import copy
from pathlib import Path

import pytest
import yaml

from impactosc.config import ConfigError, load_config, validate_config
from impactosc.integration.model import ModelParams

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
CONFIG = ROOT / "config" / "config.yaml"


@pytest.fixture()
def config():
    return yaml.safe_load(CONFIG.read_text())


def test_default_config_is_valid_and_is_model_bc():
    cfg = load_config(CONFIG, SCHEMA)
    assert ModelParams(**cfg["model"]) == ModelParams()
    assert cfg["scenes"]["period4"]["omega"] == 23.03


def test_schema_documents_every_model_key():
    schema = yaml.safe_load(SCHEMA.read_text())
    for key, sub in schema["properties"]["model"]["properties"].items():
        assert "description" in sub and "default" in sub, key


@pytest.mark.parametrize("mutate, key", [
    (lambda c: c["model"].__setitem__("m", -1.0), "model.m"),
    (lambda c: c["model"].__setitem__("mass", 1.0), "model"),
    (lambda c: c["model"].__setitem__("k", "stiff"), "model.k"),
    (lambda c: c["solver"].__setitem__("rtol", -1e-9), "solver.rtol"),
    (lambda c: c["scenes"]["chaos"].__setitem__("duration", -400), "scenes.chaos.duration"),
    (lambda c: c["scenes"]["chaos"].__setitem__("omgea", 4), "scenes.chaos"),
    (lambda c: c["scenes"]["chaos"].__setitem__("events", ["impacts", "sparks"]), "scenes.chaos.events.1"),
    (lambda c: c["scenes"]["chaos"]["window"].__setitem__("stop", 1e4), "scenes.chaos.window"),
])
def test_bad_config_names_the_key(config, mutate, key):
    bad = copy.deepcopy(config)
    mutate(bad)
    with pytest.raises(ConfigError) as err:
        validate_config(bad, SCHEMA)
    assert f"  {key}:" in str(err.value), str(err.value)


def test_missing_config_file(tmp_path):
    with pytest.raises(ConfigError, match="does not exist"):
        load_config(tmp_path / "none.yaml", SCHEMA)
