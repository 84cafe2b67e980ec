"""Shared by the store tests: a store equals a reference bit for bit (imported as ``_store_helpers``).

pytest's default ``prepend`` import mode puts this directory (no ``__init__.py``) on ``sys.path``
before it imports the test modules, so ``from _store_helpers import ...`` works from any rootdir.
"""

from __future__ import annotations

import contextlib
import logging

import numpy as np

from bifurcation.store import open_store
from bifurcation.run.tiles import OUTPUTS

__all__ = ["Recorder", "assert_bitwise_equal", "assert_store_equals", "local_cluster"]


class Recorder:
    """A runner's ``Checkpoints`` in memory (the chain and rs-chain checkpoint tests): keeps every save (and can hand one back as ``load`` would)."""

    def __init__(self, every, resume_from=None):
        self.every, self.saves, self.resume_from = every, [], resume_from

    def load(self, i):
        return self.resume_from

    def save(self, i, state, catalog, *, steps, first=0):
        self.saves.append({"state": {k: np.ascontiguousarray(v).tobytes() for k, v in state.items()},
                           "catalog": {k: np.array(v, copy=True) for k, v in catalog.items()},
                           "first": first, "steps": steps})


def assert_bitwise_equal(ds, reference: dict) -> None:
    """Every output of ``ds`` has the dtype and the bits of ``reference`` (NaN payloads included)."""
    for name in OUTPUTS:
        stored, expected = np.asarray(ds[name].values), reference[name]
        assert stored.dtype == expected.dtype, name
        if stored.dtype.kind == "f":   # bit for bit, NaN included
            stored, expected = stored.view(np.int64), expected.view(np.int64)
        np.testing.assert_array_equal(stored, expected, err_msg=name)


def assert_store_equals(path, reference: dict) -> None:
    """The store at ``path`` equals ``reference`` (e.g. ``compute_serial``) bit for bit."""
    assert_bitwise_equal(open_store(path), reference)


@contextlib.contextmanager
def local_cluster(n_workers: int):
    """A local cluster of ``n_workers`` single-threaded processes and a client that keeps them warm;
    yields the scheduler address (what ``submit(scheduler=...)`` takes)."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=logging.ERROR)
    client = Client(cluster, set_as_default=False)
    try:
        yield cluster.scheduler_address
    finally:
        client.close()
        cluster.close()
