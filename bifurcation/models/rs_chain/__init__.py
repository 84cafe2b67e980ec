"""The rate-and-state Burridge–Knopoff chain (docs/rs-chain.md): N sliders with the slider's friction,
coupled by neighbour springs, events by a slip-velocity threshold into the chain's catalog schema.

Public names are imported on first use, so naming the model does not load heyoka.
"""

from __future__ import annotations

from ..._lazy import lazy_names

_LAZY = {
    "RSChainResult": "simulate",
    "RSChainSpec": "simulate",
    "RSChainStatus": "result",
    "initial_state": "simulate",
    "rs_chain": "simulate",
    "run_batch": "batch",
}

__all__ = sorted(_LAZY)

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
