"""The finalize task of a detached submit (run/detach.py) sums the tiles' status counts whatever their length:
tiles send one count per int8 code (128) since rs-chain declared ``steady`` = 8, and a tally sized by
``Status`` raised IndexError on the worker, so the lock was never released (CI, 2026-11-26: the detached
test timed out after 300 s). In process, without a cluster."""
from __future__ import annotations

import json
import time

from bifurcation.models import get_model
from bifurcation.run import detach


def test_finalize_sums_counts_of_any_length_and_releases_the_lock(tmp_path, monkeypatch):
    from bifurcation.store.lock import lock_path

    store = tmp_path / "s.zarr"
    store.mkdir()
    lock_path(store).write_text(json.dumps({"token": "t"}), encoding="utf-8")
    recorded = []
    monkeypatch.setattr("bifurcation.store.record_submit", lambda path, entry: recorded.append(entry))
    steady = [0] * 128
    steady[8], steady[0] = 3, 1
    results = [{"points": 4, "counts": steady}, {"points": 2, "counts": [2]}, {"points": 5, "error": "tile x: boom"}]
    entry = detach._finalize(str(store), "t", {"model": "rs-chain", "started": time.time()}, *results)
    assert (entry["computed"], entry["failed"], entry["errors"]) == (6, 5, ["tile x: boom"])
    assert entry["statuses"] == {"steady": 3, get_model("rs-chain").status_name(0): 3}
    assert recorded == [entry] and not lock_path(store).exists()
