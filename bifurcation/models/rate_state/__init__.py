"""The rate-and-state spring-slider (docs/rate-state.md): model, Hopf analysis, cycles, peer suite.

Public names are imported on first use, so naming the model does not load heyoka.
"""

from __future__ import annotations

from ..._lazy import lazy_names

_LAZY = {
    "CycleResult": "cycle",
    "LoadHistory": "spec",
    "RateStateResult": "simulate",
    "STATE_LAWS": "laws",
    "SliderSpec": "spec",
    "limit_cycle": "cycle",
    "load_history": "spec",
    "rate_state": "simulate",
    "resolve_state_law": "laws",
    "state_law_names": "laws",
}

__all__ = sorted(_LAZY)

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
