"""Public names of a package, imported from their modules on first use (PEP 562).

Why: ``import impactosc`` must stay cheap. The plotting and table jobs of the workflow import
the package but need neither numba nor SciPy (about 1 s per job), so a package lists its
public names with the module that defines each, and a name's module is imported only when the
name is first read. Each name is then cached in the package, so later reads cost nothing.
"""

from __future__ import annotations

import importlib

__all__ = ["export"]


def export(namespace: dict, names: dict[str, str]) -> None:
    """Give the package whose globals are ``namespace`` the public ``names`` (name -> module).

    Sets ``__all__`` (the names, in the order given), ``__getattr__`` and ``__dir__``.
    """
    package = namespace["__name__"]

    def __getattr__(name: str):
        module = names.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        namespace[name] = value
        return value

    def __dir__():
        return sorted(set(namespace) | set(names))

    namespace.update(__all__=list(names), __getattr__=__getattr__, __dir__=__dir__)
