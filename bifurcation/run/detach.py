"""Detached studies: submit to a running Dask scheduler, let the client go, let the workers finish.

``submit(..., detach=True)`` (``bifurcation submit --detach``) hands every missing tile and one last
*finalize* task to an existing scheduler with ``distributed.fire_and_forget`` and returns as soon as the
scheduler holds them: the submitting process may then exit or be killed. The workers compute and write
the tiles into the store as in an attached run (the store must be on a filesystem they share); the
finalize task, which depends on every tile, records the run in the store's history and releases the
store's lock. ``bifurcation status --store S`` shows the progress meanwhile.

The one-writer lock (``bifurcation.store.lock``) passes from the submitting process to the detached
run: its file then names the scheduler and the finalize task's key. The run counts as alive while the
scheduler still holds that task; once the task is gone (run finished, scheduler restarted or gone) the
lock is stale and the next ``submit`` takes it and resumes whatever is left. A ``submit`` that finds a
detached run alive *joins* it: it waits, showing the progress, until the run ends, then resumes.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

from ..store.lock import detached_alive

__all__ = ["detached_alive", "finalize_key", "run_detached", "wait_for_detached"]

#: Attempts per tile in a detached run (a tile task must not raise: the finalize task depends on all).
_ATTEMPTS = 3


def finalize_key(run_token: str) -> str:
    return f"bifurcation-finalize-{run_token}"


def _tile_task(tile, store: str, run_id: str) -> dict:
    """Worker task of a detached run: the tile's status counts, or its error after ``_ATTEMPTS`` tries."""
    from .submission import run_tile

    last = ""
    for _ in range(_ATTEMPTS):
        try:
            return {"points": tile.n_todo, "counts": run_tile(tile, store, run_id)}
        except Exception as exc:  # noqa: BLE001 — reported by the finalize task, never raised
            last = f"tile {tile.name}: {type(exc).__name__}: {exc}".splitlines()[0]
    return {"points": tile.n_todo, "error": last}


def _finalize(store: str, lock_token: str, entry: dict, *results) -> dict:
    """Worker task after every tile: the run's line in the store history, then the lock released."""
    from ..models import get_model
    from ..store import record_submit
    from ..store.lock import lock_path

    computed = sum(r["points"] for r in results if "error" not in r)
    failed = sum(r["points"] for r in results if "error" in r)
    counts: list[int] = []   # as long as the longest tile's counts: a model may declare codes beyond Status
    for r in results:
        for i, n in enumerate(r.get("counts", ())):
            counts.extend([0] * (i + 1 - len(counts)))
            counts[i] += n
    errors = [r["error"] for r in results if "error" in r][:5]
    model = get_model(entry.pop("model", None))
    entry = {**entry, "computed": computed, "failed": failed,
             "wall_time": round(time.time() - entry.pop("started"), 3),
             "statuses": {model.status_name(i): n for i, n in enumerate(counts) if n}, "errors": errors}
    try:
        record_submit(store, entry)
    finally:
        file = lock_path(store)
        try:
            if json.loads(file.read_text(encoding="utf-8")).get("token") == lock_token:
                file.unlink()
        except (OSError, ValueError):
            pass
    return entry


def run_detached(client, workflow, path: Path, run_id: str, done, lock, command: str, skipped: int) -> dict:
    """Hand the missing tiles of ``workflow`` and the finalize task to ``client``'s scheduler and return.

    ``lock`` (held by this process) is handed over to the run: its file is rewritten to name the
    scheduler and the finalize key, and this process no longer releases it.
    """
    from distributed import fire_and_forget

    from ..store.lock import lock_path
    from .tiles import iter_tiles

    store = str(path.resolve())
    token = lock.token
    tiles = list(iter_tiles(workflow, done))
    futures = [client.submit(_tile_task, tile, store, run_id, key=f"bifurcation-tile-{tile.name}-{token[:8]}",
                             pure=False) for tile in tiles]
    entry = {"command": command, "skipped": skipped, "cluster": f"detached on {client.scheduler.address}",
             "started": time.time(), "model": workflow.model}
    key = finalize_key(token)
    # the lock names the run before the run exists: a submit that looks in between waits for it
    holder = json.loads(lock_path(path).read_text(encoding="utf-8"))
    holder.update(scheduler=client.scheduler.address, task=key, pid=-2)
    tmp = lock_path(path).with_name(lock_path(path).name + f".{token}")
    tmp.write_text(json.dumps(holder), encoding="utf-8")
    os.replace(tmp, lock_path(path))
    lock.held = False   # the run releases it (finalize), not this process
    final = client.submit(_finalize, store, token, entry, *futures, key=key, pure=False)
    fire_and_forget(final)
    # return only once the scheduler holds the run for nobody in particular: killing this process
    # right after must not cancel it
    deadline = time.monotonic() + 60
    while not client.run_on_scheduler(_held_for_nobody, key=key):
        if time.monotonic() > deadline:
            raise TimeoutError(f"the scheduler did not take the detached run {key} within 60 s")
        time.sleep(0.05)
    return {"tiles": len(tiles), "points": int(sum(t.n_todo for t in tiles)), "task": key,
            "scheduler": client.scheduler.address}


def _held_for_nobody(dask_scheduler=None, key: str = "") -> bool:
    state = dask_scheduler.tasks.get(key)
    return state is not None and any(c.client_key == "fire-and-forget" for c in state.who_wants)


def wait_for_detached(path, progress, poll: float = 2.0) -> bool:
    """Join a live detached run on the store at ``path``: wait until it ends. False if there is none."""
    from ..store.lock import holder

    found = holder(path)
    if found is None or not found.scheduler:
        return False
    progress.note(f"joining {found.describe()}: waiting for it to finish (Ctrl-C leaves it running)")
    while holder(path) is not None:
        time.sleep(poll)
    progress.note("the detached run has ended; resuming what is left")
    return True
