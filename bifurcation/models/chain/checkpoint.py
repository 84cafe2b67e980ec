"""Snapshot and restore of a chain run between events (all blocks stuck), for checkpoints.

Between two events every block is stuck (V = 0), so the state of a run is the stress σ_j, the
displacements U_j, the time t, and the per-block friction piece (reset when a block starts, kept so
that the restored loop is the same object bit for bit). The window integrators are rebuilt from
scratch at every segment (state, time, parameters and cooldowns are all set before each
``propagate_until``), so nothing else carries over from one event to the next: a loop restored from
a snapshot computes the same next events, bit for bit, as the loop the snapshot was taken from
(tests/test_chain_store.py).

A snapshot is a dict of numpy arrays in the loop's own dtype (float64, or real128 in quad
precision) plus the time as a 0-d array; ``to_bytes``/``from_bytes`` keep every bit.
"""

from __future__ import annotations

import numpy as np

__all__ = ["STATE", "restore", "snapshot"]

#: The loop attributes a snapshot holds (arrays over the blocks, and the time).
STATE = ("sigma", "u", "vel", "slipping", "piece", "t")


def snapshot(loop) -> dict[str, np.ndarray]:
    """The state of ``loop`` (a ``ChainLoop`` between events) as arrays that own their data."""
    if loop.slipping.any():
        raise RuntimeError("a chain run can only be checkpointed between events (all blocks stuck)")
    out = {name: np.array(getattr(loop, name), copy=True) for name in STATE if name != "t"}
    out["t"] = np.array([loop.t], dtype=loop.dtype)
    return out


def restore(loop, state: dict) -> None:
    """Put ``state`` (from ``snapshot``, or its arrays' bytes) back into ``loop``."""
    for name in STATE:
        if name == "t":
            t = state["t"]
            t = np.frombuffer(t, dtype=loop.dtype) if isinstance(t, bytes) else np.asarray(t)
            loop.t = t.reshape(-1)[0].copy()
            continue
        current = getattr(loop, name)
        value = state[name]
        value = np.frombuffer(value, dtype=current.dtype) if isinstance(value, bytes) else np.asarray(value)
        if value.shape != current.shape:
            raise ValueError(f"checkpoint {name} has shape {value.shape}, the run needs {current.shape}")
        setattr(loop, name, value.astype(current.dtype, copy=True))
