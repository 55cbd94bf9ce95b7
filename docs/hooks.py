"""MkDocs hooks: generated tables and figures in the pages, math as MathML, and checks.

* ``{{ generated: results/paper/tables/X.md }}`` is replaced by that file when the workflow has
  written it (headings demoted below the page's), else by a note naming the target that makes
  it: numbers on these pages come from the workflow's own tables, never copied by hand.
* ``{{ figure: GROUP/NAME.png by COMMAND }}`` shows a figure of the study's figures directory,
  ``{{ gallery }}`` every figure with its caption (``workflow/report/NAME.rst``, the captions of
  ``snakemake --report``); the PNGs are copied into the site at build time, none is committed.
  Before a build the page says which command makes them.
* ``{{ screenshot: tests/artifacts/NAME.png by COMMAND }}`` shows a screenshot a test saved
  (the explorer's browser test); copied into the site at build time when it exists, else the page
  names the command that makes it.
* ``{{ include: PATH }}`` inserts a file of the repository (the changelog, the config reference).
* ``{{ contact_laws }}`` is the table of the contact laws, read from their components
  (:mod:`impactosc.model.contact_laws`): a new law appears without an edit here.
* ``$...$`` and ``$$...$$`` (found by pymdownx.arithmatex) become MathML at build time: no
  JavaScript, no CDN. A ``$`` left in a page's text outside code fails the build.
* A list right after a paragraph line renders as one paragraph ("text - a - b") in
  Python-Markdown, and a nested list indented by less than 4 spaces renders flat: both fail the
  build, with the line.
* Every public function and class of a module the API page documents (``::: module``) must have
  a docstring; a missing one is logged as a warning, which ``mkdocs build --strict`` turns into a
  failed build.
"""

from __future__ import annotations

import html
import importlib
import inspect
import logging
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
log = logging.getLogger("mkdocs.plugins.impactosc")
GENERATED = re.compile(r"\{\{\s*generated:\s*(\S+?)(?:\s+by\s+(.+?))?\s*\}\}")
INCLUDE = re.compile(r"\{\{\s*include:\s*(\S+?)\s*\}\}")
FIGURE = re.compile(r"\{\{\s*figure:\s*(\S+?)(?:\s+by\s+(.+?))?\s*\}\}")
SCREENSHOT = re.compile(r"\{\{\s*screenshot:\s*(\S+?)(?:\s+by\s+(.+?))?\s*\}\}")
ARTIFACTS = Path("tests") / "artifacts"  # what the tests save (git-ignored), under ROOT
GALLERY_MARK = re.compile(r"\{\{\s*gallery\s*\}\}")
LAWS_MARK = re.compile(r"\{\{\s*contact_laws\s*\}\}")
API = re.compile(r"^::: ([\w.]+)", re.M)

STUDY = "paper"
CAPTIONS = ROOT / "workflow" / "report"
# The gallery's order: each caption workflow/report/NAME.rst belongs to the figure NAME.png of
# the study's figures directory (top level or a group's folder). Captions that are no figure of
# the paper's gallery (compare_studies: its files are named after the other study, opt-in;
# two_parameter_bands: a model with a covariance only, which the paper's model BC is not):
NOT_FIGURES = {"workflow", "paper_vs_replication", "compare_studies", "two_parameter_bands"}
GALLERY = [
    (
        "The paper's figures",
        ["fig01", "fig02", "fig03", "fig03a", "fig03b", *(f"fig{n:02d}" for n in range(4, 12))],
    ),
    (
        "Periodic orbits, grazing and basins",
        ["grazing", "bifurcation_overlay", "fig02_orbits", "fig03b_orbits", "basins", "basins_fine"],
    ),
    ("Attractors along w", ["attractors"]),
    ("Lyapunov exponents", ["lyapunov_chaos", "fig02_lyapunov", "fig03b_lyapunov"]),
    ("Contact laws", ["restitution", "fig02_laws", "fig03b_laws"]),
    ("Two parameters (opt-in)", ["map2d", "map2d_curves"]),
    ("Records and identification", ["measured_noise_study", "identify"]),
    ("Noise in the dynamics", ["dynamic_noise_study"]),
    ("Speed against accuracy", ["work_precision"]),
]
# The Snakemake target that draws a figure, and its caption, where they are not the figure's name
TARGETS = {
    "measured_noise_study": "measured_noise_figure",
    "identify": "identify_figure",
    "fig02_laws": "laws_study",
    "fig03b_laws": "laws_study",
}
# Figures of a study of their own (opt-in, config/<study>.yaml), not the paper's: results/<study>/figures
OTHER_STUDIES = {"fig02_laws": "laws", "fig03b_laws": "laws"}
CAPTION_OF = {"basins_fine": "basins"}
SITE_FIGURES = "figures"  # where the PNGs go in the site
SITE_SCREENSHOTS = "screenshots"  # where the tests' screenshots go in the site


def figures_dir(root: Path | None = None) -> Path:
    """The study's figures directory: results/<study>/figures, or results/figures of older builds."""
    root = root or ROOT
    new = root / "results" / STUDY / "figures"
    return new if new.is_dir() else root / "results" / "figures"


def _resolve(path: str, root: Path = ROOT) -> Path:
    """A results path as the build wrote it: under results/<study>/ or, for older builds, results/."""
    parts = Path(path).parts
    candidates = [Path(path)]
    if parts[:1] == ("results",) and parts[1:2] != (STUDY,):
        candidates.insert(0, Path("results", STUDY, *parts[1:]))
    elif parts[:2] == ("results", STUDY):
        candidates.append(Path("results", *parts[2:]))
    for candidate in candidates:
        if (root / candidate).exists():
            return root / candidate
    return root / candidates[0]


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


def _not_built(what: str, how: str) -> str:
    return f'!!! note "Not built yet"\n    {what} is written {how}; build it and rebuild the docs to see it here.\n'


def _generated(match: re.Match) -> str:
    path, target = match.group(1), match.group(2)
    file = _resolve(path)
    if file.is_file():
        return _csv_table(file) if file.suffix == ".csv" else _demote(file.read_text(encoding="utf-8"))
    return _not_built(f"`{path}`", f"by `{target}`" if target else "by the workflow")


def _include(match: re.Match) -> str:
    file = ROOT / match.group(1)
    if not file.is_file():
        log.warning(f"include: {match.group(1)} does not exist")
        return ""
    return _demote(file.read_text(encoding="utf-8"))


# --- figures -----------------------------------------------------------------------------


def find_figure(name: str, directory: Path) -> Path | None:
    """NAME.png at the top of the figures directory or in one of its groups' folders."""
    for png in [directory / f"{name}.png", *sorted(directory.glob(f"*/{name}.png"))]:
        if png.is_file():
            return png
    return None


def caption_html(name: str) -> str:
    """The caption workflow/report/NAME.rst (reStructuredText) as an HTML fragment."""
    import docutils.core

    text = (CAPTIONS / f"{CAPTION_OF.get(name, name)}.rst").read_text(encoding="utf-8")
    parts = docutils.core.publish_parts(text, writer="html5", settings_overrides={"report_level": 5})
    return re.sub(r'<span class="docutils literal">(.*?)</span>', r"<code>\1</code>", parts["fragment"], flags=re.S)


def _title(name: str) -> str:
    match = re.fullmatch(r"fig(\d\d)([ab]?)", name)
    return f"Fig. {int(match.group(1))}{match.group(2)} (`{name}`)" if match else f"`{name}`"


def other_study_figures(directory: Path, study: str) -> Path:
    """The figures directory of another study, beside the paper's: results/<study>/figures
    (``directory`` is results/paper/figures, or results/figures of older builds)."""
    results = directory.parent if directory.parent.name == "results" else directory.parents[1]
    return results / study / "figures"


def _site_path(name: str, png: Path, directory: Path) -> str:
    """Where a gallery figure goes in the site: figures/<path> (the paper's), figures/studies/<study>/<path>."""
    study = OTHER_STUDIES.get(name)
    if study is None:
        return png.relative_to(directory).as_posix()
    return f"studies/{study}/{png.relative_to(other_study_figures(directory, study)).as_posix()}"


def _command(name: str) -> str:
    study = OTHER_STUDIES.get(name)
    return TARGETS.get(name, name) + (f" --configfile config/{study}.yaml" if study else "")


def gallery_markdown(directory: Path, prefix: str = "") -> str:
    """Every figure with its caption; a figure not built names the command that builds it."""
    listed = [CAPTION_OF.get(name, name) for _, names in GALLERY for name in names]
    others = sorted(p.stem for p in CAPTIONS.glob("*.rst") if p.stem not in listed and p.stem not in NOT_FIGURES)
    sections = GALLERY + ([("Other figures", others)] if others else [])
    built = {
        name: find_figure(
            name, other_study_figures(directory, OTHER_STUDIES[name]) if name in OTHER_STUDIES else directory
        )
        for _, names in sections
        for name in names
    }
    out = []
    if not any(built.values()):
        out.append(
            '!!! note "No figure is built yet"\n'
            f"    The figures appear here after `make` (the whole workflow; `results/{STUDY}/figures/` has none yet)\n"
            "    and a rebuild of these pages with `make docs`. One figure alone, e.g. Fig. 4:\n"
            "    `.venv/bin/snakemake -j2 fig04`. The captions below say what each figure will show.\n"
        )
    for title, names in sections:
        out.append(f"## {title}\n")
        for name in names:
            out.append(f"### {_title(name)}\n")
            png = built[name]
            if png is None:
                out.append(f"*Not built yet:* `.venv/bin/snakemake -j2 {_command(name)}`\n")
            else:
                out.append(f"![{name}]({prefix}{SITE_FIGURES}/{_site_path(name, png, directory)})\n")
            out.append(f'<div class="figure-caption">\n{caption_html(name)}\n</div>\n')
    return "\n".join(out)


def _figure(match: re.Match, prefix: str) -> str:
    path, command = match.group(1), match.group(2)
    if (figures_dir() / path).is_file():
        return f"![{Path(path).stem}]({prefix}{SITE_FIGURES}/{path})"
    return _not_built(f"The figure `{path}`", f"by `{command}`" if command else "by the workflow")


def _screenshot(match: re.Match, prefix: str) -> str:
    path, command = match.group(1), match.group(2)
    if (ROOT / path).is_file():
        return f"![{Path(path).stem}]({prefix}{SITE_SCREENSHOTS}/{Path(path).name})"
    return _not_built(f"The screenshot `{path}`", f"by `{command}`" if command else "by the tests")


def on_files(files, config):
    """The built PNGs of the study into the site, under figures/ (the gallery's figures of other
    studies under figures/studies/<study>/), and the tests' screenshots under screenshots/
    (copied at build time)."""
    from mkdocs.structure.files import File

    artifacts = ROOT / ARTIFACTS
    for png in sorted(artifacts.glob("*.png")) if artifacts.is_dir() else []:
        files.append(File.generated(config, f"{SITE_SCREENSHOTS}/{png.name}", abs_src_path=str(png)))

    directory = figures_dir()
    for png in sorted(directory.rglob("*.png")) if directory.is_dir() else []:
        uri = f"{SITE_FIGURES}/{png.relative_to(directory).as_posix()}"
        files.append(File.generated(config, uri, abs_src_path=str(png)))
    for name, study in OTHER_STUDIES.items():  # the other studies' gallery figures, those built
        png = find_figure(name, other_study_figures(directory, study))
        if png is not None:
            uri = f"{SITE_FIGURES}/{_site_path(name, png, directory)}"
            files.append(File.generated(config, uri, abs_src_path=str(png)))
    return files


# --- math --------------------------------------------------------------------------------

MATH = re.compile(r'<(span|div) class="arithmatex">\\[(\[](.*?)\\[)\]]</\1>', re.S)
CODE = re.compile(r"<(pre|code)\b.*?</\1>", re.S)


def mathml(page_html: str) -> str:
    """The math pymdownx.arithmatex marked (generic mode) as MathML: inline and display."""
    from latex2mathml.converter import convert

    def one(match: re.Match) -> str:
        display = "block" if match.group(1) == "div" else "inline"
        return convert(html.unescape(match.group(2)).strip(), display=display)

    return MATH.sub(one, page_html)


def raw_dollars(page_html: str) -> list[str]:
    """Text with a ``$`` outside code and math: math the conversion did not catch."""
    text = re.sub(r"<math\b.*?</math>", "", CODE.sub("", page_html), flags=re.S)
    text = re.sub(r"<[^>]+>", " ", text)
    return [line.strip() for line in text.splitlines() if "$" in line]


# --- lists -------------------------------------------------------------------------------

LIST_ITEM = re.compile(r"^( *)(?:[-*+]|\d+\.) +\S")
FENCE = re.compile(r"^ *(```|~~~|\$\$ *$)")  # code, and display math


def list_problems(markdown: str) -> list[str]:
    """Lists that Python-Markdown does not render as lists.

    A list item right after a paragraph line (no blank line between) continues the paragraph,
    also inside a list, after a list item's second paragraph; a nested item indented by 1-3
    spaces is a sibling, not a sub-list.
    """
    problems = []
    in_fence, in_list, block = False, False, None  # block: None (after a blank), item, paragraph, other
    for number, line in enumerate(markdown.splitlines(), 1):
        if FENCE.match(line) or in_fence:
            in_fence = in_fence != bool(FENCE.match(line))
            block = "other"
            continue
        item = LIST_ITEM.match(line)
        if item:
            if block == "paragraph":
                problems.append(f"line {number}: a list right after a paragraph needs a blank line: {line.strip()}")
            if in_list and 0 < len(item.group(1)) < 4:
                problems.append(f"line {number}: a nested list needs 4 spaces of indentation: {line.strip()}")
            in_list, block = True, "item"
        elif not line.strip():
            block = None
        elif line.lstrip().startswith(("#", "!!!", "<", "{{")):
            block = "other"
        elif block in (None, "other"):
            in_list = in_list and line.startswith(" ")
            block = "paragraph"
    return problems


def math_in_headings(markdown: str) -> list[str]:
    """Headings with math: the table of contents would show the LaTeX source."""
    text = re.sub(r"^ *(```|~~~).*?^ *\1", "", markdown, flags=re.M | re.S)
    return [
        f"math in a heading (the table of contents shows it raw): {h}" for h in re.findall(r"^#+ .*\$.*$", text, re.M)
    ]


# --- API docstrings ----------------------------------------------------------------------


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


def contact_laws_table() -> str:
    """The contact laws as a Markdown table, from their components: force, own parameters with
    units and ranges, switching surfaces inside the contact, per-contact state, fitted quantities."""
    from impactosc.model.contact_laws import LAWS

    rows = [
        "| law | force (h = x - xI > 0) | its own parameters | surfaces beyond onset and exit | "
        "state per contact | identification fits |",
        "|---|---|---|---|---|---|",
    ]
    for law in LAWS.values():
        own = ", ".join(f"{p.name} ({p.unit}, {p.range_text})" for p in law.parameters) or "-"
        surfaces = "; ".join(f"{s.name}: {s.residual} = 0" for s in law.surfaces) or "-"
        fitted = ", ".join(law.quantities) or "-"
        cells = [f"`{law.name}`", law.force, own, surfaces, law.contact_state or "-", fitted]
        rows.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(rows) + "\n"


def on_page_markdown(markdown, page, config, files):
    """Insert generated tables, figures and included files; check lists and API docstrings."""
    for module_name in API.findall(markdown):
        for name in undocumented(module_name):
            log.warning(f"{page.file.src_path}: {name} has no docstring")
    markdown = INCLUDE.sub(_include, markdown)
    markdown = LAWS_MARK.sub(lambda m: contact_laws_table(), markdown)
    for problem in list_problems(markdown) + math_in_headings(markdown):
        log.warning(f"{page.file.src_path}: {problem}")
    prefix = "../" * page.file.src_uri.count("/")
    markdown = GALLERY_MARK.sub(lambda m: gallery_markdown(figures_dir(), prefix), markdown)
    markdown = FIGURE.sub(lambda m: _figure(m, prefix), markdown)
    markdown = SCREENSHOT.sub(lambda m: _screenshot(m, prefix), markdown)
    return GENERATED.sub(_generated, markdown)


def on_page_content(html_text, page, config, files):
    """Math as MathML; a ``$`` left in the text fails the build."""
    html_text = mathml(html_text)
    for line in raw_dollars(html_text):
        log.warning(f"{page.file.src_path}: unconverted $ in: {line[:120]}")
    return html_text
