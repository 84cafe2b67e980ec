"""The engine: slip cycles at finite ν and the direct ν → 0 limit.

Names are imported on first use (PEP 562): the store, queries and workflows import the light
``engine.result`` without loading heyoka. No submodule may share a name with a public function
(importing a submodule binds its name on the package, so ``engine.limit`` would become a module):
the ν → 0 limit lives in ``direct``.
"""

from __future__ import annotations

from .._lazy import lazy_names

_LAZY = {
    "FIELDS": "result",
    "LIMIT_FIELDS": "direct",
    "LimitResult": "direct",
    "SlipResult": "result",
    "Status": "result",
    "limit": "direct",
    "slip": "cycle",
}

__all__ = ["FIELDS", "LIMIT_FIELDS", "LimitResult", "SlipResult", "Status", "limit", "slip"]

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
