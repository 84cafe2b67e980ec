"""The engine: slip cycles at finite ν and the direct ν → 0 limit.

Names are imported on first use (PEP 562): the store, queries and workflows import the light
``engine.result`` without loading heyoka. No submodule may share a name with a public function
(importing a submodule binds its name on the package, so ``engine.limit`` would become a module):
the ν → 0 limit lives in ``direct``.
"""

from __future__ import annotations

import importlib

_LAZY = {
    "FIELDS": "result",
    "LIMIT_FIELDS": "direct",
    "LimitResult": "direct",
    "SlipResult": "result",
    "Status": "result",
    "limit": "direct",
    "slip": "cycle",
}

__all__ = sorted(_LAZY)


def __getattr__(name: str):
    if name in _LAZY:
        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'bifurcation.engine' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
