"""Load and validate the workflow configuration against its JSON schema.

Errors name the offending key as a dotted path (``model.m: -1 is less than or equal to
the minimum of 0``) so a user sees at once what to fix; a misspelt key is named as unknown
with the closest valid key (``model.kl: unknown key (did you mean 'kI'?)``) rather than as
the required key it hides. Defaults from the schema are filled in so scripts can rely on
every key being present.

``study`` names the folder of the study's results (results/<study>/); ``{study}`` in the two
keys that name an events file for a panel (chaotic.second_train.events,
bifurcation.fig02.experimental.file) becomes that name.

The model section either sets parameters of model BC one by one or names a model file
(``model: {file: rig.yaml}``, :mod:`impactosc.model.model_file`) whose parameters replace it; either
way ``config["model"]`` ends up holding exactly the ModelParams fields, and
``config["model_source"]`` says where they came from, for figures and tables to name.
"""

from __future__ import annotations

import copy
import json
import math
import re
from pathlib import Path

import jsonschema
import yaml

from impactosc.io.names import SHOWN_LIMIT, closest_name, shown
from impactosc.io.yaml_text import AliasError, DuplicateKeyError, load_yaml, number_as_string_hint, yaml_problem


class ConfigError(ValueError):
    """The configuration does not match its schema."""


def _path(error) -> str:
    return ".".join(str(p) for p in error.absolute_path) or "(top level)"


def _unknown_keys(error):
    """(dotted key, message, suggestion) per key an ``additionalProperties: false`` forbids."""
    props = error.schema.get("properties", {})
    patterns = error.schema.get("patternProperties", {})
    names = list(props)
    absent = [n for n in names if n not in error.instance]
    prefix = ".".join(str(p) for p in error.absolute_path)
    out = []
    for key in error.instance:
        if key in props or any(re.search(p, str(key)) for p in patterns):
            continue
        guess = closest_name(str(key), names, absent)
        hint = f" (did you mean {guess!r}?)" if guess else f"; valid keys: {', '.join(names) or '(none)'}"
        out.append((f"{prefix}.{key}" if prefix else str(key), "unknown key" + hint, guess))
    return out


def _flatten(error):
    """Replace a oneOf/anyOf error by its branch's errors when only one branch fits the value's
    type and that branch has unknown keys, so a typo inside an optional object is named too."""
    if error.validator not in ("oneOf", "anyOf") or not error.context:
        return [error]
    branches = {}
    for sub in error.context:
        branches.setdefault(sub.relative_schema_path[0], []).append(sub)
    fitting = [
        errs for errs in branches.values() if not any(e.validator == "type" and not e.relative_path for e in errs)
    ]
    if len(fitting) == 1 and any(
        e.validator == "additionalProperties" and e.validator_value is False for e in fitting[0]
    ):
        return [f for e in fitting[0] for f in _flatten(e)]
    return [error]


def _messages(errors) -> list:
    """One ``path: message`` line per error, unknown keys named with a suggestion."""
    unknown = {
        id(e): _unknown_keys(e) for e in errors if e.validator == "additionalProperties" and e.validator_value is False
    }
    suggested = {(tuple(e.absolute_path), guess) for e in errors for _, _, guess in unknown.get(id(e), ()) if guess}
    lines = []
    for error in errors:
        if id(error) in unknown:
            lines += [f"  {key}: {msg}" for key, msg, _ in unknown[id(error)]]
            continue
        if error.validator == "required":
            # the missing key was named as the suggestion for a misspelt one: say it once
            missing = [k for k in error.validator_value if error.message == f"{k!r} is a required property"]
            if missing and (tuple(error.absolute_path), missing[0]) in suggested:
                continue
        lines.append(f"  {_path(error)}: {_said(error)}{number_as_string_hint(error.instance)}")
    return lines


def _said(error) -> str:
    """jsonschema's message with the value it echoes cut (:func:`impactosc.io.names.shown`): most
    of its messages are repr(value) and the rule, e.g. "[[...], ...] is not of type 'number'"."""
    message = error.message
    if len(message) > 2 * SHOWN_LIMIT:
        echoed = repr(error.instance)
        if message.startswith(echoed):
            return shown(error.instance) + message[len(echoed) :]
    return message


def _check_finite(node, where: str = "") -> None:
    """No NaN or infinity anywhere (YAML's .nan and .inf pass a schema's type: number): a figure
    or a run of them has no meaning."""
    if isinstance(node, dict):
        items = [(f"{where}.{key}" if where else str(key), value) for key, value in node.items()]
    elif isinstance(node, list):
        items = [(f"{where}[{i}]", value) for i, value in enumerate(node)]
    else:
        return
    for path, value in items:
        if isinstance(value, float) and not math.isfinite(value):
            raise ConfigError(f"invalid configuration:\n  {path}: {value} is not a finite number")
        _check_finite(value, path)


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


def nest_dotted_keys(config: dict) -> dict:
    """A copy of `config` with each dotted top-level key nested (``{"a.b": 1}`` ->
    ``{"a": {"b": 1}}``), as a config file or the Snakemake API may give an override; the
    dotted key wins over a nested one of the same name."""
    out = copy.deepcopy(config)
    for key in [k for k in out if isinstance(k, str) and "." in k]:
        value = out.pop(key)
        *parents, last = key.split(".")
        node = out
        for i, part in enumerate(parents):
            if not isinstance(node.get(part), dict):
                if part in node:
                    where = ".".join(parents[: i + 1])
                    raise ConfigError(
                        f"invalid configuration:\n  {key}: {where} is not a section (it is {shown(node[part])})"
                    )
                node[part] = {}
            node = node[part]
        node[last] = value
    return out


def _contact_fields(model: dict) -> None:
    """model.contact ({law, its own numbers}) as the ModelParams fields law, e, cI, ... (model BC's
    law and their defaults without it); a law given a number it does not take, or missing one, is named."""
    from impactosc.model.contact_laws import LAWS, OWN_PARAMETERS  # no numba: the plotting jobs import it too

    contact = model.pop("contact", None)
    if contact is None:
        return
    law = LAWS[contact["law"]]
    where = "invalid configuration:\n  model.contact"
    for key in OWN_PARAMETERS:
        if key in contact and key not in law.own:
            raise ConfigError(f"{where}.{key}: the {law.name} law takes {', '.join(law.own) or 'nothing'} beside law")
        if key in law.own and key not in contact:
            raise ConfigError(f"{where}.{key}: missing: the {law.name} law needs it ({law.force})")
    stray = [k for k in ("b", "n2", "n3") if k in model and k not in law.family]
    if stray:
        raise ConfigError(
            f"{where}: the {law.name} law has no {stray[0]} (model BC's damping); remove model.{stray[0]}"
        )
    model["law"] = law.name
    model.update({k: float(contact[k]) for k in law.own})
    if law.n1 is not None:  # a law of its own elastic exponent (Kelvin-Voigt's linear)
        model.setdefault("n1", law.n1)


def _model_from_file(model: dict) -> dict:
    """config["model_source"], and config["model"] replaced by the parameters of the model file
    `model["file"]` when one is named (other keys beside it must equal the file's values)."""
    _contact_fields(model)
    if model.get("file") is None:
        model.pop("file", None)
        from impactosc.model.contact_laws import DEFAULT_LAW, OWN_PARAMETERS

        model.setdefault("law", DEFAULT_LAW)  # the ModelParams fields the schema has not
        for prm in OWN_PARAMETERS.values():
            model.setdefault(prm.name, prm.default)
        # model BC is stated exactly: no covariance, no error bars
        return {"file": None, "description": "model BC (paper)", "covariance": False}  # model_file.BC_DESCRIPTION
    from impactosc.model.model_file import (  # only here: they import numba, which the plotting jobs do without
        read_model_file,
        resolve_model,
    )

    path = model.pop("file")
    try:
        params, description = resolve_model(path)
        stated = read_model_file(path)
        # a covariance, or each parameter's stderr (independent errors): an uncertainty to propagate
        covariance = stated.covariance is not None or any(se > 0 for se in stated.stderr.values())
    except (ValueError, OSError) as exc:
        raise ConfigError(f"invalid configuration:\n  model.file: {exc}") from None
    values = params.to_dict()
    clash = [f"{k} = {v!r} (the file: {values[k]!r})" for k, v in model.items() if v != values[k]]
    if clash:
        raise ConfigError(
            f"invalid configuration:\n  model.file: the parameters of {path} replace model's, but model also sets "
            f"{'; '.join(clash)}: it is ambiguous which should win; remove them, or change the file"
        )
    model.clear()
    model.update(values)
    noise = stated.noise.to_dict() if stated.noise.active else None
    return {"file": str(path), "description": description, "covariance": covariance, "noise": noise}


def _dynamic_noise(block, from_file) -> dict | None:
    """The noise in the dynamics of every scene: the config's ``noise`` block, else the model file's,
    else none; refused as the model refuses it (:class:`impactosc.model.noise.Noise`), naming the key."""
    block = block if block is not None else from_file
    if block is None:
        return None
    from impactosc.model.noise import Noise
    from impactosc.model.parameters import ParameterError

    try:
        noise = Noise.from_dict(block)
    except ParameterError as exc:
        raise ConfigError(f"invalid configuration:\n  {exc.name}: {exc}") from None
    return noise.to_dict() if noise.active else None


def _check_model(model: dict) -> None:
    """The model section built once, as every job builds it (ModelParams): a value the schema lets
    through but the model refuses (an e of 1e-200, beyond what the model evaluates; n1 = 1.5 with
    the kelvin-voigt law) is refused here, named by its config key, rather than by every job.
    Warnings of values outside the tested ranges stay with the jobs, in their logs."""
    import warnings

    from impactosc.model.parameters import LAW_PARAMETERS, ModelParams, ParameterError, UntestedParameterWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UntestedParameterWarning)
        try:
            ModelParams(**model)
        except ParameterError as exc:
            contact = {name for name, _, _ in LAW_PARAMETERS}  # given in model.contact
            key = f"contact.{exc.name}" if exc.name in contact else exc.name
            raise ConfigError(f"invalid configuration:\n  model.{key}: {exc}") from None


def check_config_files(paths) -> None:
    """Each config file read again as a user's YAML (:func:`impactosc.io.yaml_text.load_yaml`):
    a key given twice, which Snakemake's reader keeps the last of silently, and aliases that expand
    the file beyond reason, which Snakemake's reader expands, are refused; so is text that is
    neither YAML nor JSON (Snakemake reads JSON first: a JSON file indented with tabs is no YAML)."""
    for path in paths:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise ConfigError(
                f"invalid configuration:\n  {path}: not UTF-8 text (byte {exc.start} cannot be decoded)"
            ) from None
        try:
            load_yaml(text)
        except (DuplicateKeyError, AliasError) as exc:
            raise ConfigError(f"invalid configuration:\n  {path}: {exc}") from None
        except yaml.YAMLError as exc:
            try:
                json.loads(text)
            except (ValueError, RecursionError):
                raise ConfigError(f"invalid configuration:\n  {path}: not YAML: {yaml_problem(exc)}") from None


def contact_schema() -> dict:
    """The JSON schema of model.contact, from the contact laws' components: the law's name, and each
    law's own numbers with their ranges (which law takes which is checked after, with a message
    naming the law)."""
    from impactosc.model.contact_laws import LAWS, OWN_PARAMETERS

    def number(prm):
        node = {"type": "number", "description": f"{prm.meaning}, {prm.unit} (the {', '.join(users(prm))} law)"}
        if prm.low > -math.inf:
            node["exclusiveMinimum" if prm.low_open else "minimum"] = prm.low
        if prm.high < math.inf:
            node["exclusiveMaximum" if prm.high_open else "maximum"] = prm.high
        return node

    def users(prm):
        return [law.name for law in LAWS.values() if prm.name in law.own]

    laws = "; ".join(
        f"{law.name}: {law.force}" + (f" (keys {', '.join(law.own)})" if law.own else "") for law in LAWS.values()
    )
    return {
        "type": "object",
        "additionalProperties": False,
        "required": ["law"],
        "description": "the contact law, model BC's own when absent; b, n2 and n3 only for a law that reads them "
        f"(impactosc.model.contact_laws). {laws}. E.g. {{law: flores, e: 0.7}}",
        "properties": {
            "law": {"type": "string", "enum": list(LAWS), "description": "the law's name"},
            **{name: number(prm) for name, prm in OWN_PARAMETERS.items()},
        },
    }


def load_schema(schema_path) -> dict:
    """The config's JSON schema, with what the contact laws define filled in (model.contact, the
    laws study's law list): read from the laws' components, never listed twice by hand."""
    from impactosc.model.contact_laws import LAWS

    schema = yaml.safe_load(Path(schema_path).read_text())
    schema["properties"]["model"]["properties"]["contact"] = contact_schema()
    items = schema["properties"]["laws"]["properties"]["laws"]["items"]
    items["enum"] = [name for name, law in LAWS.items() if law.n1 is None]
    return schema


def validate_config(config: dict, schema_path, config_files=()) -> dict:
    """Return a validated copy of `config` with schema defaults filled in, dotted top-level
    keys nested, and the model of ``model.file`` (if any) in place of the model section;
    `config_files`, the files it was read from, are checked for keys given twice."""
    check_config_files(config_files)
    schema = load_schema(schema_path)
    config = nest_dotted_keys(config)
    if "model_file" in config:  # the command line's spelling: --config model_file=rig.yaml
        config.setdefault("model", {})["file"] = config.pop("model_file")
    _check_study_names(config, schema)
    _check_finite(config)
    validator = jsonschema.Draft202012Validator(schema)
    errors = [f for e in validator.iter_errors(config) for f in _flatten(e)]
    errors.sort(key=lambda e: list(e.absolute_path))
    if errors:
        raise ConfigError("invalid configuration:\n" + "\n".join(_messages(errors)))
    config["model_source"] = _model_from_file(config.setdefault("model", {}))
    _check_model(config["model"])
    _fill_defaults(schema, config)
    config["noise"] = _dynamic_noise(config.get("noise"), config["model_source"].pop("noise", None))
    for name, scene in config["scenes"].items():
        win = scene.get("window")
        end = scene["transient"] + scene["duration"]
        if win and not (win["start"] <= win["stop"] <= end):
            raise ConfigError(
                f"invalid configuration:\n  scenes.{name}.window: [start, stop] must satisfy "
                f"start <= stop <= transient + duration = {end}"
            )
    _study_paths(config)
    _check_measured_labels(config.get("measured", {}))
    _check_orbit_segments(config.get("periodic_orbits", {}).get("segments", {}))
    _check_two_parameter(config)
    study = config.get("measured", {}).get("noise_study", {})
    stray = sorted(set(study.get("x_impact_noise", [])) - set(study.get("noise", [])))
    if stray:
        raise ConfigError(
            f"invalid configuration:\n  measured.noise_study.x_impact_noise: {stray} not among "
            f"measured.noise_study.noise {study['noise']}"
        )
    return config


def _check_study_names(config: dict, schema: dict) -> None:
    """study and compare.study name folders under results/: a safe directory name (the schema's
    pattern), said in words rather than as the pattern a plain schema error would quote."""
    pattern = schema["properties"]["study"]["pattern"]
    study = config.get("study", schema["properties"]["study"]["default"])
    compare = config.get("compare")
    other = compare.get("study") if isinstance(compare, dict) else None
    for key, name in (("study", study), ("compare.study", other)):
        if key == "compare.study" and name is None:
            continue
        if not isinstance(name, str):
            raise ConfigError(
                f"invalid configuration:\n  {key}: {shown(name)} is not a string (a name made of digits only must be "
                f"quoted, on the command line too: --config '{key.split('.')[-1]}=\"{shown(name)}\"')"
            )
        if not re.fullmatch(pattern, name):
            raise ConfigError(
                f"invalid configuration:\n  {key}: {shown(name)} is not a safe directory name (letters, digits, _ and - "
                f"only): the study's results go to results/<study>/"
            )
    if other == study:
        raise ConfigError(
            f"invalid configuration:\n  compare.study: {shown(other)} is this study (study): name another one to compare with"
        )


def _study_paths(config: dict) -> None:
    """{study} in the keys that name an events file for a panel becomes the study's name."""
    entries = [
        (config.get("chaotic", {}).get("second_train"), "events"),
        (config.get("bifurcation", {}).get("fig02", {}).get("experimental"), "file"),
    ]
    for entry, key in entries:
        if isinstance(entry, dict) and isinstance(entry.get(key), str):
            entry[key] = entry[key].replace("{study}", config["study"])


def _check_measured_labels(measured: dict) -> None:
    """A label names a record: the surrogate keeps its own label, so that it is never called measured."""
    for key, records in (("chaos", ("record",)), ("fig02", ("records", "sweep_record"))):
        entry = measured.get(key, {})
        if entry.get("label") and not any(entry.get(r) for r in records):
            raise ConfigError(
                f"invalid configuration:\n  measured.{key}.label: {shown(entry['label'])} names a record, but none is "
                f"configured (measured.{key}.{' or '.join(records)}): the surrogate's panels are always labelled "
                "'surrogate (model + noise)'"
            )


def _check_orbit_segments(segments: dict) -> None:
    """Each doubled segment names an existing parent, without a cycle; each w_range is ordered."""
    for name, seg in segments.items():
        where = f"invalid configuration:\n  periodic_orbits.segments.{name}"
        lo, hi = seg["w_range"]
        if not lo < hi:
            raise ConfigError(f"{where}.w_range: must be [lo, hi] with lo < hi, got {seg['w_range']}")
        if "seed" in seg and not lo <= seg["seed"]["omega"] <= hi:
            raise ConfigError(f"{where}.seed.omega: {seg['seed']['omega']} lies outside w_range {seg['w_range']}")
        seen, parent = {name}, seg.get("doubling_of", {}).get("segment")
        while parent is not None:
            if parent not in segments:
                raise ConfigError(
                    f"{where}.doubling_of.segment: no segment named {parent!r} (segments: {', '.join(segments)})"
                )
            if parent in seen:
                raise ConfigError(f"{where}.doubling_of: the chain of parents comes back to {parent!r}")
            seen.add(parent)
            parent = segments[parent].get("doubling_of", {}).get("segment")


def _check_two_parameter(config: dict) -> None:
    """The curves start at the model's value of the parameter, inside an ordered range; they are
    drawn over the 2-D map, so both use the same parameter; each names an existing segment."""
    two = config.get("two_parameter", {})
    where = "invalid configuration:\n  two_parameter"
    name, (lo, hi) = two["parameter"], two["values"]
    if not lo < hi:
        raise ConfigError(f"{where}.values: must be [lo, hi] with lo < hi, got {two['values']}")
    own = config["model"].get(name)
    if own is not None and not lo <= own <= hi:
        raise ConfigError(
            f"{where}.values: {two['values']} must contain the model's {name} = {own} (where every curve starts)"
        )
    if not two["w_range"][0] < two["w_range"][1]:
        raise ConfigError(f"{where}.w_range: must be [lo, hi] with lo < hi, got {two['w_range']}")
    if not two["ds"] > two["ds_min"]:
        raise ConfigError(f"{where}.ds: must exceed ds_min = {two['ds_min']}, got {two['ds']}")
    drawn_over = config["bifurcation"]["map2d"]["parameter"]
    if name != drawn_over:
        raise ConfigError(
            f"{where}.parameter: {name} differs from bifurcation.map2d.parameter {drawn_over} (the map the "
            "curves are drawn over); set both to the same parameter"
        )
    segments = config.get("periodic_orbits", {}).get("segments", {})
    for curve, spec in two["curves"].items():
        if spec["segment"] not in segments:
            raise ConfigError(
                f"{where}.curves.{curve}.segment: no segment named {spec['segment']!r} in periodic_orbits.segments "
                f"({', '.join(segments) or 'none'})"
            )


def load_config(path, schema_path) -> dict:
    path = Path(path)
    if not path.is_file():
        raise ConfigError(f"configuration file {path} does not exist")
    check_config_files([path])  # a key twice, aliases beyond reason, not YAML: one line, before reading it
    text = path.read_text(encoding="utf-8")
    try:  # JSON first, as Snakemake reads a config file
        config = json.loads(text)
    except ValueError:
        config = yaml.safe_load(text)
    return validate_config(config or {}, schema_path)
