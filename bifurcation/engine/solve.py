"""One entry point for every model: ``solve(model, label, points)`` → the model's outputs per point.

The tiles, the serial reference and the analysis call this, never a model's own function, so a new
model reaches workflows, the store and reports through its declaration alone.
"""

from __future__ import annotations

import numpy as np

from .result import DEFAULT_MAX_STEPS, DEFAULT_T_MAX

__all__ = ["solve"]


def solve(model, label: str, points: dict, *, precision: str = "double", t_max: float = DEFAULT_T_MAX,
          max_steps: int = DEFAULT_MAX_STEPS, batch: int = 1, checkpoints=None) -> dict:
    """Run ``model`` (a ``bifurcation.models.Model``: the engine never looks one up) for ``label`` at every point.

    ``points`` maps each axis of the model to an array of values (all of one shape; an axis with a
    default may be left out). Returns a dict
    of the model's outputs (arrays of that shape) and ``messages`` (flat index → text).
    ``checkpoints`` (a runner model that checkpoints, ``bifurcation.store.catalog.Checkpoints``) is
    handed to the runner; per-event outputs are object arrays of per-point arrays.
    """
    from ._integrator import _declared
    from .cycle import run_model

    spec = _declared(model)
    if spec.written_by:
        raise TypeError(f"model {spec.name}: its points are written by `bifurcation {spec.written_by}`, not solved "
                        "one by one")
    # an axis with a default (as in a workflow without its [grid] table) takes it
    points = {**{a.name: a.default for a in spec.axes if a.default is not None and a.name not in points}, **points}
    missing = [a.name for a in spec.axes if a.name not in points]
    if missing:
        raise KeyError(f"solve({spec.name}): no values for the axes {missing}")
    arrays = np.broadcast_arrays(*(np.asarray(points[a.name], dtype=float) for a in spec.axes))
    shape = arrays[0].shape
    flat = {a.name: np.ascontiguousarray(v).ravel() for a, v in zip(spec.axes, arrays)}
    run = spec.runner if spec.runner is not None else run_model
    extra = {"checkpoints": checkpoints} if checkpoints is not None else {}
    fields, messages = run(spec, label, flat, precision=precision, t_max=t_max, max_steps=max_steps,
                           batch=batch, **extra)
    out = {name: np.asarray(value).reshape(shape) for name, value in fields.items()}
    out["messages"] = messages
    return out

