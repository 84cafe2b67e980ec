"""The engine: slip cycles at finite ν and the direct ν → 0 limit.

Names are imported on first use (PEP 562): the store, queries and workflows import the light
``engine.result`` without loading heyoka.
"""

from __future__ import annotations

import importlib

_LAZY = {
    "FIELDS": "result",
    "LIMIT_FIELDS": "limit",
    "LimitResult": "limit",
    "SlipResult": "result",
    "Status": "result",
    "limit": "limit",
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
