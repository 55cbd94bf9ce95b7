"""YAML a user writes: read so that a silent mistake is refused, and the rule that turns numbers into strings named.

Why: PyYAML keeps the last of two equal keys without a word (``k: 1500`` written twice, the
first forgotten), and YAML 1.1 reads ``1e-5`` (no dot before the exponent) as the string
'1e-5'. A model file or a workflow config that means a number and holds a string, or that holds
a key twice, is refused with the file, the key and the line.

And aliases: YAML repeats an anchored value wherever an alias (``*name``) names it, so nine aliases
of a list of nine aliases, six levels deep, are half a million values written in seven lines (a
"billion laughs"); any code that prints or serialises them (an error message, a job's params, a
JSON dump) spends memory and time in proportion. A document whose aliases add more than
:data:`ALIAS_LIMIT` values, or whose alias sits inside the value it names, is refused.
"""

from __future__ import annotations

import math
import sys

import yaml

from impactosc.io.names import SHOWN_LIMIT, shown

__all__ = ["ALIAS_LIMIT", "AliasError", "DuplicateKeyError", "load_yaml", "number_as_string_hint", "yaml_problem"]

#: Most values YAML aliases may add to a document: a model file or a workflow config is a few
#: hundred values, its aliases (a shared window, a merge key) a few dozen more.
ALIAS_LIMIT = 100_000


class DuplicateKeyError(yaml.YAMLError):
    """A mapping states a key twice (PyYAML would keep the last one silently)."""


class AliasError(yaml.YAMLError):
    """Aliases expand the document beyond ALIAS_LIMIT values, or an alias names a value that holds it."""


def _check_aliases(root) -> None:
    """AliasError when the aliases of the composed document `root` (a node graph in which an
    alias is the node it names, met again) expand it by more than ALIAS_LIMIT values, or when a
    node holds itself. One pass over the distinct nodes, not over the expansion."""
    size, ancestors, written = {}, set(), 0
    stack = [(root, False)]
    while stack:
        node, done = stack.pop()
        children = [] if isinstance(node, yaml.ScalarNode) else node.value
        if isinstance(node, yaml.MappingNode):
            children = [part for pair in children for part in pair]
        if done:
            ancestors.discard(id(node))
            size[id(node)] = 1 + sum(size[id(child)] for child in children)
            continue
        if id(node) in ancestors:
            raise AliasError(
                f"the value at line {node.start_mark.line + 1} holds an alias of itself: a value without end"
            )
        if id(node) in size:
            continue
        written += 1
        ancestors.add(id(node))
        stack.append((node, True))
        stack.extend((child, False) for child in children)
    added = size[id(root)] - written
    if added > ALIAS_LIMIT:
        many = f"{added:,}" if added < 10**12 else f"about 10^{len(str(added)) - 1}"
        raise AliasError(
            f"its aliases (*name) add {many} values to the {written:,} it writes, more than the "
            f"{ALIAS_LIMIT:,} allowed (aliases nested in aliases multiply: write the values out)"
        )


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

    def construct_yaml_int(self, node):
        try:
            return super().construct_yaml_int(node)
        except ValueError:  # more digits than Python converts (sys.get_int_max_str_digits)
            raise yaml.constructor.ConstructorError(
                None,
                None,
                f"an integer of {len(node.value)} characters, more than the {sys.get_int_max_str_digits()} "
                "digits Python reads",
                node.start_mark,
            ) from None

    def construct_document(self, node):
        _check_aliases(node)  # before any value is built
        return super().construct_document(node)


def load_yaml(text: str):
    """The YAML document in `text`, as yaml.safe_load reads it, but a DuplicateKeyError for a key
    given twice in one mapping and an AliasError for aliases that expand it beyond ALIAS_LIMIT values."""
    try:
        return yaml.load(text, Loader=_UniqueKeyLoader)  # a SafeLoader: no arbitrary objects
    except RecursionError:  # PyYAML composes and builds nested collections recursively
        raise yaml.YAMLError(
            "collections nested too deep to read (hundreds of levels, a [ or { inside another)"
        ) from None


_UniqueKeyLoader.add_constructor("tag:yaml.org,2002:int", _UniqueKeyLoader.construct_yaml_int)


def yaml_problem(exc: yaml.YAMLError) -> str:
    """What a YAML error says is wrong, on one line with its line and column: "found character
    '\\t' that cannot start any token (line 3, column 1)"; and where the construct it was reading
    began, when that is another line ("..., while parsing a flow sequence from line 1, column 4")."""
    if not isinstance(exc, yaml.MarkedYAMLError):
        return " ".join(str(exc).split()) or type(exc).__name__

    def where(mark) -> str:
        return f"line {mark.line + 1}, column {mark.column + 1}"

    problem, mark, context = exc.problem, exc.problem_mark, exc.context
    if problem is None:
        problem, mark, context = context, exc.context_mark, None
    text = " ".join(str(problem or type(exc).__name__).split())
    if mark is not None:
        text += f" ({where(mark)})"
    if context and exc.context_mark is not None and (mark is None or exc.context_mark.line != mark.line):
        text += f", {' '.join(context.split())} from {where(exc.context_mark)}"
    return text


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
