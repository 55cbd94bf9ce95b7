"""YAML a user writes: read so that a silent mistake is refused, and the rule that turns numbers into strings named.

Why: PyYAML keeps the last of two equal keys without a word (``k: 1500`` written twice, the
first forgotten), and YAML 1.1 reads ``1e-5`` (no dot before the exponent) as the string
'1e-5'. A model file or a workflow config that means a number and holds a string, or that holds
a key twice, is refused with the file, the key and the line.
"""

from __future__ import annotations

import math

import yaml

from impactosc.io.names import SHOWN_LIMIT, shown

__all__ = ["DuplicateKeyError", "load_yaml", "number_as_string_hint"]


class DuplicateKeyError(yaml.YAMLError):
    """A mapping states a key twice (PyYAML would keep the last one silently)."""


class _UniqueKeyLoader(yaml.SafeLoader):
    """yaml.SafeLoader that refuses a key given twice in one mapping (merge keys ``<<`` aside)."""

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            seen = {}
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = self.construct_object(key_node, deep=deep)
                line = key_node.start_mark.line + 1
                try:
                    first = seen.get(key)
                except TypeError:  # an unhashable key: SafeLoader's own error names it
                    continue
                if first is not None:
                    where = f"line {line}" if first == line else f"lines {first} and {line}"
                    raise DuplicateKeyError(
                        f"key {shown(key)} given twice ({where}); YAML would keep only the last: remove one"
                    )
                seen[key] = line
        return super().construct_mapping(node, deep=deep)


def load_yaml(text: str):
    """The YAML document in `text`, as yaml.safe_load reads it, but a DuplicateKeyError for a key
    given twice in one mapping."""
    return yaml.load(text, Loader=_UniqueKeyLoader)  # a SafeLoader: no arbitrary objects


def number_as_string_hint(value) -> str:
    """' (YAML 1.1 ...)' when `value` is a string that reads as a finite number, as '1e-5' does:
    how to write it so that YAML reads a number; '' otherwise."""
    if not isinstance(value, str) or len(value) > SHOWN_LIMIT:
        return ""
    try:
        number = float(value)
    except ValueError:
        return ""
    if not math.isfinite(number):
        return ""
    text = value.strip().lower()
    if "e" in text:
        mantissa, exponent = text.split("e", 1)
        mantissa = mantissa if "." in mantissa else f"{mantissa}.0"
        exponent = exponent if exponent[:1] in "+-" else f"+{exponent}"
        fix = f"{mantissa}e{exponent}"
        if isinstance(yaml.safe_load(fix), float):
            return f" (YAML 1.1 reads {value!r} as a string: write {fix}, with a dot and a signed exponent)"
    return f" (a number in quotes is a string: write {value.strip()} without quotes)"
