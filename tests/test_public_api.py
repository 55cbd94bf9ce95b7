"""The public API: ``from impactosc import simulate`` and each subpackage's listed names resolve,
and ``import impactosc`` stays cheap (no numba, SciPy or matplotlib until a name needs them)."""

import importlib
import pkgutil
import subprocess
import sys
import types

import pytest

import impactosc

PACKAGES = ["impactosc", *(f"impactosc.{m.name}" for m in pkgutil.iter_modules(impactosc.__path__) if m.ispkg)]


@pytest.mark.parametrize("package", PACKAGES)
def test_every_listed_name_resolves(package):
    pkg = importlib.import_module(package)
    names = getattr(pkg, "__all__", [])
    if package != "impactosc.cli":
        assert names, f"{package} lists no public names"
    for name in names:
        value = getattr(pkg, name)
        assert not isinstance(value, types.ModuleType), f"{package}.{name} is a module, not a public name"
        assert name in dir(pkg)


@pytest.mark.parametrize("package", PACKAGES)
def test_no_public_name_shadows_a_submodule(package):
    # importing a submodule binds its name in the package: a public name of the same spelling would
    # turn into the module as soon as anyone imported it
    pkg = importlib.import_module(package)
    modules = {m.name for m in pkgutil.iter_modules(pkg.__path__)}
    assert not modules & set(getattr(pkg, "__all__", [])), f"{package}: {modules & set(pkg.__all__)}"


def test_top_level_names_are_the_subpackages_own():
    from impactosc import ModelParams, extract_events, simulate
    from impactosc.core import simulate as core_simulate
    from impactosc.model import ModelParams as model_params
    from impactosc.records import extract_events as records_extract

    assert simulate is core_simulate and ModelParams is model_params and extract_events is records_extract


def test_unknown_name_is_an_attribute_error_naming_it():
    with pytest.raises(AttributeError, match="'impactosc' has no attribute 'simulat'"):
        impactosc.simulat  # noqa: B018
    with pytest.raises(ImportError):
        exec("from impactosc.dynamics import no_such_name", {})


@pytest.mark.parametrize("package", ["impactosc", "impactosc.statistics", "impactosc.io", "impactosc.dynamics"])
def test_import_is_cheap(package):
    code = f"import sys, {package}; print(sorted(m for m in ('numba', 'scipy', 'matplotlib') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", f"import {package} loaded {out.strip()}"


def test_one_version():
    """impactosc.__version__ is the one source: the installed metadata reads it (pyproject's dynamic
    version) and CITATION.cff states the same."""
    import importlib.metadata
    import re
    from pathlib import Path

    import impactosc

    citation = (Path(__file__).resolve().parents[1] / "CITATION.cff").read_text()
    assert importlib.metadata.version("impactosc") == impactosc.__version__
    assert re.search(r"^version: (\S+)$", citation, flags=re.M)[1] == impactosc.__version__
