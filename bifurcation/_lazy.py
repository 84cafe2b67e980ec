"""Lazy public names for a package (PEP 562): imported on first use, then cached in the package.

Keeps ``bifurcation --help`` and the light modules (store, query, workflow) from loading heyoka,
dask or matplotlib until a name that needs them is used.
"""

from __future__ import annotations

import importlib

__all__ = ["lazy_names"]


def lazy_names(package: str, namespace: dict, where: dict[str, str]):
    """``(__getattr__, __dir__)`` for ``package`` whose public ``name`` lives in submodule ``where[name]``."""

    def __getattr__(name: str):
        if name in where:
            value = getattr(importlib.import_module(f".{where[name]}", package), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(where))

    return __getattr__, __dir__
