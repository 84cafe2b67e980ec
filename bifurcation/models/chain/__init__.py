"""The Burridge–Knopoff chain, event-exact (issue 10; docs/chain.md).

Names are imported on first use: the result types do not load heyoka.
"""

from __future__ import annotations

from ..._lazy import lazy_names

_LAZY = {
    "CATALOG_FIELDS": "result",
    "ChainResult": "result",
    "ChainStatus": "result",
    "chain": "simulate",
}

__all__ = sorted(_LAZY)

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
