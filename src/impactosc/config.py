"""Load and validate the workflow configuration against its JSON schema.

Errors name the offending key as a dotted path (``model.m: -1 is less than or equal to
the minimum of 0``) so a user sees at once what to fix; defaults from the schema are
filled in so scripts can rely on every key being present.
"""

from __future__ import annotations

import copy
from pathlib import Path

import jsonschema
import yaml


class ConfigError(ValueError):
    """The configuration does not match its schema."""


def _path(error) -> str:
    return ".".join(str(p) for p in error.absolute_path) or "(top level)"


def _fill_defaults(schema: dict, instance):
    if not isinstance(instance, dict):
        return
    for key, sub in schema.get("properties", {}).items():
        if key not in instance and "default" in sub:
            instance[key] = copy.deepcopy(sub["default"])
        if key in instance:
            _fill_defaults(sub, instance[key])
    extra = schema.get("additionalProperties")
    if isinstance(extra, dict):
        for key in instance:
            if key not in schema.get("properties", {}):
                _fill_defaults(extra, instance[key])


def validate_config(config: dict, schema_path) -> dict:
    """Return a validated copy of `config` with schema defaults filled in."""
    schema = yaml.safe_load(Path(schema_path).read_text())
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        lines = [f"  {_path(e)}: {e.message}" for e in errors]
        raise ConfigError("invalid configuration:\n" + "\n".join(lines))
    config = copy.deepcopy(config)
    _fill_defaults(schema, config)
    for name, scene in config["scenes"].items():
        win = scene.get("window")
        end = scene["transient"] + scene["duration"]
        if win and not (win["start"] <= win["stop"] <= end):
            raise ConfigError(f"invalid configuration:\n  scenes.{name}.window: [start, stop] must satisfy "
                              f"start <= stop <= transient + duration = {end}")
    return config


def load_config(path, schema_path) -> dict:
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"configuration file {path} does not exist")
    return validate_config(yaml.safe_load(path.read_text()) or {}, schema_path)
