"""Models beside the single block of the paper, one package each, behind a name registry.

Minimal registry (the model layer reconciles it with its own contract): a model name maps to the
module that implements it; the module is imported on first use so ``bifurcation --help`` stays light.
"""

from __future__ import annotations

import importlib

__all__ = ["MODELS", "model_module"]

#: Model name → implementing module (relative to this package).
MODELS = {"chain": ".chain", "rate-state": ".rate_state"}


def model_module(name: str):
    """The module implementing model ``name`` (imported on first use)."""
    from ..errors import InputError

    if name not in MODELS:
        raise InputError("model", name, "is not a known model", f"use one of {sorted(MODELS)}")
    return importlib.import_module(MODELS[name], __name__)
