"""Render the config schema as Markdown (config/README.md), so users read every key, its type,
default, range and meaning in one place while the schema stays the single source of truth.

``python -m impactosc_study.config_docs`` (or ``make config-docs``) writes the file; with
``--check`` (and in a test) it fails when the file no longer matches the schema. The command
belongs to the study, not to the library's ``impactosc`` command: the schema is the workflow's.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from impactosc_study.config import load_schema

SCHEMA = "workflow/schemas/config.schema.yaml"
OUTPUT = "config/README.md"
COMMAND = "python -m impactosc_study.config_docs"
NAME = "<name>"  # placeholder of a user-chosen key in a map (scenes, sweeps, ...)


def _scalar(value) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        short = f"{value:g}"
        return short if float(short) == value else repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(_scalar(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_scalar(v)}" for k, v in value.items()) + "}"
    return str(value)


def _code(value) -> str:
    return f"`{_scalar(value)}`"


def _cell(text: str) -> str:
    """One table cell: one line, pipes escaped, and '<name>' kept visible (not taken for an HTML tag)."""
    return re.sub(r"<(?=[A-Za-z/!])", "&lt;", " ".join(str(text).split()).replace("|", "\\|"))


def _branches(schema: dict) -> list:
    return schema.get("oneOf") or schema.get("anyOf") or []


def _type(schema: dict) -> str:
    if _branches(schema):
        names = []
        for b in _branches(schema):
            if _type(b) not in names:
                names.append(_type(b))
        return " or ".join(names)
    if "enum" in schema and "type" not in schema:
        kinds = {type(v) for v in schema["enum"]}
        return "string" if kinds == {str} else "enum"
    kind = schema.get("type", "")
    kind = " or ".join(kind) if isinstance(kind, list) else kind
    if kind == "array" and "items" in schema:
        return f"array of {_type(schema['items'])}"
    if _is_map(schema):
        return "map"
    return kind


def _bounds(schema: dict) -> list:
    parts = []
    for key, sign in (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<")):
        if key in schema:
            parts.append(f"{sign} {_scalar(schema[key])}")
    if "enum" in schema:
        parts.append("one of " + ", ".join(_code(v) for v in schema["enum"]))
    if schema.get("minLength") == 1:
        parts.append("non-empty")
    elif "minLength" in schema:
        parts.append(f"length >= {schema['minLength']}")
    return parts


def _allowed(schema: dict) -> str:
    """Bounds, enum and size limits in words; a oneOf lists each constrained branch."""
    branches = _branches(schema)
    if branches:
        parts = [(b, _allowed(b)) for b in branches]
        parts = [(b, a) for b, a in parts if a]
        if len(parts) == 1:
            return parts[0][1]
        return "; ".join(f"{_type(b)}: {a}" for b, a in parts)
    parts = _bounds(schema)
    lo, hi = schema.get("minItems"), schema.get("maxItems")
    if lo is not None and lo == hi:
        parts.append(f"exactly {lo} items")
    else:
        if lo:
            parts.append(f"at least {lo} item{'s' * (lo != 1)}")
        if hi is not None:
            parts.append(f"at most {hi} items")
    if schema.get("uniqueItems"):
        parts.append("no repeats")
    if "minProperties" in schema:
        n = schema["minProperties"]
        parts.append(f"at least {n} entr{'y' if n == 1 else 'ies'}")
    items = schema.get("items")
    if isinstance(items, dict) and _bounds(items):
        parts.append("each " + ", ".join(_bounds(items)))
    return ", ".join(parts)


def _is_map(schema: dict) -> bool:
    return isinstance(schema.get("additionalProperties"), dict) and not schema.get("properties")


def _object(schema: dict):
    """The object schema whose keys are documented below this one (itself or its object branch)."""
    if "properties" in schema or _is_map(schema):
        return schema
    for b in _branches(schema):
        if "properties" in b or _is_map(b):
            return b
    return None


def _default(schema: dict, required: bool) -> str:
    if "default" in schema:
        value = schema["default"]
        text = "see below" if value == {} and _object(schema) else _code(value)
        return f"{text} (required)" if required else text
    return "required" if required else "—"


def _rows(schema: dict, prefix: str):
    """(key, type, default, allowed, description) of every key under `schema`, depth first."""
    obj = _object(schema)
    if obj is None:
        return
    if _is_map(obj):
        value = obj["additionalProperties"]
        key = f"{prefix}.{NAME}"
        if _object(value):
            yield from _rows(value, key)
        else:
            yield key, _type(value), "—", _allowed(value), value.get("description", "")
        return
    required = set(obj.get("required", ()))
    for name, sub in obj.get("properties", {}).items():
        key = f"{prefix}.{name}" if prefix else name
        yield key, _type(sub), _default(sub, name in required), _allowed(sub), sub.get("description", "")
        yield from _rows(sub, key)


def _table(rows) -> list:
    lines = ["| Key | Type | Default | Allowed | Description |", "|---|---|---|---|---|"]
    for key, kind, default, allowed, text in rows:
        lines.append(f"| `{key}` | {_cell(kind)} | {_cell(default)} | {_cell(allowed) or '—'} | {_cell(text)} |")
    return lines


def render(schema: dict, source: str = SCHEMA) -> str:
    """Markdown reference of the config: one section (and table) per top-level key."""
    props = schema.get("properties", {})
    required = schema.get("required", [])
    sections = [n for n, s in props.items() if _object(s)]
    loose = [n for n in props if n not in sections]
    out = [
        f"<!-- Generated from {source} by `{COMMAND}`; edit the schema, then run it again. -->",
        "",
        "# Configuration reference",
        "",
        _cell(schema.get("description", "")),
        "",
        (
            "Every key of `config/config.yaml` with its type, default, allowed values and meaning. A key left "
            "out takes its default; a key marked required must be given (a value shown with it is the reference "
            "value, e.g. model BC of the paper). A key the schema does not know stops the workflow with a message "
            "naming it and the closest valid key, e.g. `model.kl: unknown key (did you mean 'kI'?)`. "
            f"`{NAME}` stands for a name you choose (a scene, a sweep, ...)."
        ),
        "",
        "Sections: " + ", ".join(f"[{n}](#{n.lower()})" for n in sections) + ".",
    ]
    if required:
        out += ["", "Required sections: " + ", ".join(f"`{n}`" for n in required) + "."]
    if loose:
        out += ["", "## Top level", ""]
        out += _table(
            (n, _type(props[n]), _default(props[n], n in required), _allowed(props[n]), props[n].get("description", ""))
            for n in loose
        )
    for name in sections:
        sub = props[name]
        out += ["", f"## {name}", ""]
        text = _cell(sub.get("description", ""))
        if _is_map(sub):
            extra = (
                f"A map of entries you name ({_allowed(sub) or 'any number'}); "
                f"each `{name}.{NAME}` takes the keys below."
            )
            text = f"{text} {extra}".strip()
        if name in required:
            text = f"{text} Required.".strip()
        elif "default" in sub:
            text = f"{text} Optional (defaults {'below' if sub['default'] == {} else _code(sub['default'])}).".strip()
        if text:
            out += [text, ""]
        out += _table(_rows(sub, name))
    return "\n".join(out) + "\n"


def render_file(schema_path=SCHEMA) -> str:
    return render(load_schema(schema_path))


def write(schema_path=SCHEMA, output=OUTPUT, check: bool = False) -> bool:
    """Write `output` from the schema (or with `check`, only compare); True when it was up to date."""
    text = render_file(schema_path)
    path = Path(output)
    current = path.read_text(encoding="utf-8") if path.is_file() else None
    if current == text or check:
        return current == text
    path.write_text(text, encoding="utf-8")
    return False


def _parser() -> argparse.ArgumentParser:
    """The command's parser: the config reference from the schema."""
    doc = argparse.ArgumentParser(
        prog=COMMAND,
        description="Render the JSON schema of the workflow config as a Markdown reference: per section a "
        "table of dotted key, type, default, allowed values and description. Run from the repository root.",
        epilog=f"Example:\n  {COMMAND} --check   # exit 1 if config/README.md is out of date",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    doc.add_argument("--schema", default=SCHEMA, help=f"config schema (default {SCHEMA})")
    doc.add_argument("--output", default=OUTPUT, help=f"Markdown file to write (default {OUTPUT})")
    doc.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 if OUTPUT differs from the schema's rendering"
    )
    return doc


def main(argv=None) -> int:
    """Write (or with --check, compare) config/README.md; the exit status says whether it was current."""
    args = _parser().parse_args(argv)
    if write(args.schema, args.output, check=args.check):
        print(f"{args.output}: up to date with {args.schema}")
        return 0
    if args.check:
        print(
            f"{COMMAND}: {args.output} is out of date with {args.schema}; run `{COMMAND}` to regenerate it",
            file=sys.stderr,
        )
        return 1
    print(f"{args.output}: written from {args.schema}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
