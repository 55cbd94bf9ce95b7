"""The documentation site's build hook (docs/hooks.py): math as MathML, lists that render as
lists, and the gallery of every figure with its caption, built or not. In-process and fast: the
pages go through Python-Markdown with the site's own extensions, no full site build (make docs
does that, strictly)."""

import importlib.util
from pathlib import Path

import markdown
import pytest
import yaml
from mkdocs.config.defaults import MkDocsConfig

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SPEC = importlib.util.spec_from_file_location("docs_hooks", DOCS / "hooks.py")
hooks = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(hooks)

# pages whose Markdown is the authors' own (api.md is mkdocstrings', the tutorials run as tests)
PAGES = sorted(p for p in DOCS.glob("*.md") if p.name != "api.md")


def _render(text: str) -> str:
    """A page as the site renders it: the extensions of mkdocs.yml, then the hook's content step."""
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text())
    names, configs = [], {}
    for ext in config["markdown_extensions"]:
        name, options = next(iter(ext.items())) if isinstance(ext, dict) else (ext, {})
        names.append(name)
        configs[name] = options or {}
    return hooks.mathml(markdown.Markdown(extensions=names, extension_configs=configs).convert(text))


def test_the_model_equation_is_mathml():
    page = _render((DOCS / "index.md").read_text())
    assert page.count('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">') >= 2
    assert "arithmatex" not in page and hooks.raw_dollars(page) == []
    # the forcing term and the contact exponent of eq. (1) arrive as MathML elements
    assert "<mi>sin</mi>" in page and "<msub><mi>n</mi><mn>3</mn></msub>" in page


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_no_math_left_raw(page):
    html = _render(page.read_text())
    assert hooks.raw_dollars(html) == []
    assert "arithmatex" not in html


def test_math_in_a_heading_is_caught():
    assert len(hooks.math_in_headings("## Chaos at $\\omega = 40.86$\n\n```\n# $HOME\n```\n")) == 1
    assert all(hooks.math_in_headings(page.read_text()) == [] for page in PAGES)


def test_raw_dollar_is_caught():
    # an unclosed $ is no math for arithmatex: the build must see it
    html = _render("The cost is $x + 1 dollars.\n\nIn code `$HOME` it is fine.")
    assert hooks.raw_dollars(html) == ["The cost is $x + 1 dollars."]


def test_list_after_a_paragraph_is_caught():
    bad = "Results:\n- one\n- two\n"
    assert len(hooks.list_problems(bad)) == 1
    assert hooks.list_problems("Results:\n\n- one\n- two\n") == []
    nested = "- **Tests:**\n  - flat in Python-Markdown\n"
    assert "4 spaces" in hooks.list_problems(nested)[0]
    assert hooks.list_problems("- **Tests:**\n    - nested\n") == []
    assert hooks.list_problems("```\ntext\n- in code\n```\n") == []
    assert hooks.list_problems("$$\nx\n+ y\n$$\n") == []
    # a list item's second paragraph swallows the next item too
    second = "- a\n\n    more on a\n- b\n"
    assert len(hooks.list_problems(second)) == 1 and markdown.markdown(second).count("<li>") == 1
    # and Python-Markdown really renders the flagged form as one paragraph
    assert "<ul>" not in markdown.markdown(bad) and "<ul>" in markdown.markdown("Results:\n\n- one\n")


@pytest.mark.parametrize("page", [*PAGES, ROOT / "README.md", ROOT / "CHANGELOG.md"], ids=lambda p: p.name)
def test_lists_render_as_lists(page):
    assert hooks.list_problems(page.read_text()) == []


def test_every_caption_has_a_place_in_the_gallery():
    listed = {hooks.CAPTION_OF.get(name, name) for _, names in hooks.GALLERY for name in names}
    captions = {p.stem for p in hooks.CAPTIONS.glob("*.rst")}
    assert captions - hooks.NOT_FIGURES == listed, "add the new caption to GALLERY in docs/hooks.py"


def test_every_gallery_target_is_a_rule():
    """Every figure the gallery names is a rule of the workflow (as Snakemake parses it: the rules
    made by a function, such as Figs 2 and 3b of each layer, count too)."""
    spec = importlib.util.spec_from_file_location(
        "workflow_script_start", ROOT / "workflow" / "scripts" / "_logging.py"
    )
    start = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(start)
    with start.open_workflow() as workflow:
        rules = {r.name for r in workflow.rules}
    targets = {hooks.TARGETS.get(name, name) for _, names in hooks.GALLERY for name in names}
    assert targets - rules == set()


def _png(path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"\x89PNG\r\n\x1a\n")


def test_gallery_before_a_build(tmp_path):
    page = hooks.gallery_markdown(tmp_path / "results" / "paper" / "figures")
    assert "No figure is built yet" in page and "`make`" in page and "snakemake -j2 fig04" in page
    assert "![" not in page
    # the captions are there all the same, from workflow/report
    assert "489 impacts" in page and "Not built yet:* `.venv/bin/snakemake -j2 measured_noise_figure`" in page


def test_gallery_after_a_build(tmp_path, monkeypatch):
    figures = tmp_path / "results" / "paper" / "figures"
    _png(figures / "fig04.png")
    _png(figures / "periodic" / "grazing.png")
    page = hooks.gallery_markdown(figures, prefix="")
    assert "![fig04](figures/fig04.png)" in page and "![grazing](figures/periodic/grazing.png)" in page
    assert "No figure is built yet" not in page and "Not built yet:* `.venv/bin/snakemake -j2 fig05`" in page
    # the PNGs go into the site at build time
    monkeypatch.setattr(hooks, "ROOT", tmp_path)

    config = MkDocsConfig()
    config.load_dict({"site_name": "test", "docs_dir": str(DOCS), "site_dir": str(tmp_path / "site")})
    assert config.validate() == ([], [])
    config.plugins._current_plugin = None  # what MkDocs sets while it runs a hook
    files = hooks.on_files([], config)
    assert sorted(f.src_uri for f in files) == ["figures/fig04.png", "figures/periodic/grazing.png"]


def test_figures_of_an_older_build(tmp_path):
    _png(tmp_path / "results" / "figures" / "fig04.png")
    assert hooks.figures_dir(tmp_path) == tmp_path / "results" / "figures"
    _png(tmp_path / "results" / "paper" / "figures" / "fig04.png")
    assert hooks.figures_dir(tmp_path) == tmp_path / "results" / "paper" / "figures"


def test_gallery_shows_the_figures_of_a_study_of_their_own(tmp_path, monkeypatch):
    """The laws study's figures live in results/laws/, beside the paper's: the gallery links them
    under figures/studies/laws/ and the site gets them there; unbuilt, it names the study's config."""
    figures = tmp_path / "results" / "paper" / "figures"
    page = hooks.gallery_markdown(figures, prefix="")
    assert "Not built yet:* `.venv/bin/snakemake -j2 laws_study --configfile config/laws.yaml`" in page
    _png(tmp_path / "results" / "laws" / "figures" / "laws" / "fig02_laws.png")
    page = hooks.gallery_markdown(figures, prefix="")
    assert "![fig02_laws](figures/studies/laws/laws/fig02_laws.png)" in page
    monkeypatch.setattr(hooks, "ROOT", tmp_path)
    config = MkDocsConfig()
    config.load_dict({"site_name": "test", "docs_dir": str(DOCS), "site_dir": str(tmp_path / "site")})
    assert config.validate() == ([], [])
    config.plugins._current_plugin = None  # what MkDocs sets while it runs a hook
    assert [f.src_uri for f in hooks.on_files([], config)] == ["figures/studies/laws/laws/fig02_laws.png"]
