"""MkDocs hooks: generated tables in the pages, and public API without a docstring as an error.

* ``{{ generated: results/paper/tables/X.md }}`` is replaced by that file when the workflow has
  written it (headings demoted below the page's), else by a note naming the target that makes
  it: numbers on these pages come from the workflow's own tables, never copied by hand.
* ``{{ include: PATH }}`` inserts a file of the repository (the changelog, the config reference).
* Every public function and class of a module the API page documents (``::: module``) must have
  a docstring; a missing one is logged as a warning, which ``mkdocs build --strict`` turns into a
  failed build.
"""

from __future__ import annotations

import importlib
import inspect
import logging
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
log = logging.getLogger("mkdocs.plugins.impactosc")
GENERATED = re.compile(r"\{\{\s*generated:\s*(\S+?)(?:\s+by\s+(.+?))?\s*\}\}")
INCLUDE = re.compile(r"\{\{\s*include:\s*(\S+?)\s*\}\}")
API = re.compile(r"^::: ([\w.]+)", re.M)


def _demote(text: str) -> str:
    """Headings two levels down, so a table's title sits under the page's sections."""
    return re.sub(r"^(#{1,4}) ", lambda m: "#" * (len(m.group(1)) + 2) + " ", text, flags=re.M)


def _csv_table(file: Path) -> str:
    """A CSV table as a Markdown table."""
    import csv

    with open(file, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return ""
    lines = ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])]
    lines += ["| " + " | ".join(r) + " |" for r in rows[1:]]
    return "\n".join(lines) + "\n"


def _generated(match: re.Match) -> str:
    path, target = match.group(1), match.group(2)
    file = ROOT / path
    if file.is_file():
        return _csv_table(file) if file.suffix == ".csv" else _demote(file.read_text(encoding="utf-8"))
    how = f" by `{target}`" if target else " by the workflow"
    return f'!!! note "Not built yet"\n    `{path}` is written{how}; build it and rebuild the docs to see it here.\n'


def _include(match: re.Match) -> str:
    file = ROOT / match.group(1)
    if not file.is_file():
        log.warning(f"include: {match.group(1)} does not exist")
        return ""
    return _demote(file.read_text(encoding="utf-8"))


def undocumented(module_name: str) -> list[str]:
    """Public functions and classes defined in the module that have no docstring."""
    module = importlib.import_module(module_name)
    names = getattr(module, "__all__", None) or [n for n in vars(module) if not n.startswith("_")]
    missing = []
    for name in names:
        obj = getattr(module, name, None)
        defined_here = (inspect.isfunction(obj) or inspect.isclass(obj)) and obj.__module__ == module_name
        if defined_here and not inspect.getdoc(obj):
            missing.append(f"{module_name}.{name}")
    return missing


def on_page_markdown(markdown, page, config, files):
    """Insert generated tables and included files; check the API page's docstrings."""
    for module_name in API.findall(markdown):
        for name in undocumented(module_name):
            log.warning(f"{page.file.src_path}: {name} has no docstring")
    markdown = GENERATED.sub(_generated, markdown)
    return INCLUDE.sub(_include, markdown)
