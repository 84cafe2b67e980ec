"""Models: declarations that the engine, workflows, store, queries and reports read (docs/models.md).

``get_model("single-block")`` returns a frozen ``Model``: its axes, state, equations, events, outputs
and statuses. Adding a model means one module here and one line in ``_REGISTRY``, or
``register(model)`` at run time (for a model that lives elsewhere, e.g. in a test).

``MODELS`` / ``model_module`` name the model *packages* that are not declarations yet: they are
listed, imported on first use, and served by their own commands. (The rate-and-state slider is a
declaration, ``rate-state``; its package ``rate_state`` also keeps its own ``hopf`` and ``continue``
commands. The chain is a declaration too, ``chain``; its package keeps its ``chain`` command.)
"""

from __future__ import annotations

import importlib

from ..errors import InputError
from ._base import ACTIONS, Axis, Event, Hooks, Labels, Model, Output, Slots, StateVar, System

__all__ = ["ACTIONS", "Axis", "DEFAULT_MODEL", "Event", "Hooks", "Labels", "MODELS", "Model", "Output", "Slots",
           "StateVar", "System", "get_model", "model_module", "model_names", "register"]

#: Model packages that are not declarations yet: name → implementing module (relative to this package).
MODELS = {"chain": ".chain"}


def model_module(name: str):
    """The package implementing the (undeclared) model ``name`` (imported on first use)."""
    if name not in MODELS:
        raise InputError("model", name, "is not a known model", f"use one of {sorted(MODELS)}")
    return importlib.import_module(MODELS[name], __name__)

#: The model of a workflow without a ``[model]`` table, and of every store written before models.
DEFAULT_MODEL = "single-block"

#: name → "module:attribute" (imported on first use).
_REGISTRY = {
    "single-block": "single_block:SINGLE_BLOCK",
    "damped-block": "damped_block:DAMPED_BLOCK",
    "rate-state": "rate_state.model:RATE_STATE",
    "rate-state-branches": "rate_state.branches:RATE_STATE_BRANCHES",
    "chain": "chain.model:CHAIN",
    "rs-chain": "rs_chain.model:RS_CHAIN",
}
_LOADED: dict[str, Model] = {}


def model_names() -> list[str]:
    """Names of the registered models, the default first."""
    return sorted(set(_REGISTRY) | set(_LOADED), key=lambda n: (n != DEFAULT_MODEL, n))


def register(model: Model, *, replace: bool = False) -> Model:
    """Add ``model`` to the registry (by ``model.name``); refuses a name taken by another model."""
    if not isinstance(model, Model):
        raise TypeError(f"register() takes a Model, not {type(model).__name__}")
    taken = model.name in _REGISTRY or model.name in _LOADED
    if taken and not replace and get_model(model.name) is not model:
        raise ValueError(f"a model named {model.name!r} is already registered")
    _LOADED[model.name] = model
    return model


def get_model(name: str | Model | None = None) -> Model:
    """The registered model called ``name`` (None: ``DEFAULT_MODEL``)."""
    if isinstance(name, Model):
        return name
    name = DEFAULT_MODEL if name is None else name
    hit = _LOADED.get(name)
    if hit is not None:
        return hit
    where = _REGISTRY.get(name) if isinstance(name, str) else None
    if where is None:
        raise InputError("model", name, "is not a known model", f"use one of {', '.join(model_names())}")
    module, attribute = where.split(":")
    model = _LOADED[name] = getattr(importlib.import_module(f".{module}", __name__), attribute)
    return model
