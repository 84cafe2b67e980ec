"""``verify``: check every chunk of a store and, with ``repair``, recompute exactly the damaged tiles.

The check is ``bifurcation.store.integrity.scan``. The repair, under the store's one-writer lock:
array metadata lost (a deleted ``done/``) is restored from the copy in the store's consolidated
metadata, damaged coordinate chunks are rewritten from the store's own workflow, every chunk of each
damaged tile is deleted (``done`` first), and a resume of the store's workflow restricted to those
tiles recomputes them (``submit(only=...)``). Each point is computed by the same pure function as in
the first run, so the repaired store equals a clean run bit for bit. A last scan confirms it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..errors import shown_path

__all__ = ["VerifyReport", "clear_damage", "verify"]


@dataclass(frozen=True)
class VerifyReport:
    """What ``verify`` found (and repaired)."""

    store: str
    tiles: int
    chunks: int
    damage: tuple = ()
    repaired_tiles: int = 0
    restored: tuple = ()
    after: tuple = ()           # damage left after the repair (empty when it worked)
    submit: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not (self.after if self.repaired_tiles or self.restored else self.damage)

    def to_dict(self) -> dict:
        return {"store": self.store, "tiles": self.tiles, "chunks": self.chunks, "ok": self.ok,
                "damage": [str(d) for d in self.damage], "repaired_tiles": self.repaired_tiles,
                "restored_metadata": list(self.restored), "damage_after_repair": [str(d) for d in self.after],
                "submit": self.submit}

    def __str__(self) -> str:
        from ..store.integrity import repair_command

        lines = [f"store {shown_path(self.store)}: {self.tiles} tiles, {self.chunks} chunks checked, "
                 f"{len(self.damage)} damaged"]
        lines += [f"damaged: {d}" for d in self.damage[:20]]
        if len(self.damage) > 20:
            lines.append(f"... and {len(self.damage) - 20} more")
        if self.restored:
            lines.append(f"restored array metadata: {', '.join(self.restored)}")
        if self.repaired_tiles:
            lines.append(f"repaired: {self.repaired_tiles} tiles recomputed")
        if self.repaired_tiles or self.restored:
            lines.append("after repair: " + ("sound" if not self.after else f"{len(self.after)} damaged chunks left"))
        elif any(d.chunk == "zarr.json" for d in self.damage):   # the workflow record: --repair cannot help
            from ..store.integrity import workflow_record_fix

            lines.append(f"fix: {workflow_record_fix(self.store)}")
        elif self.damage:
            lines.append(f"repair with: {repair_command(self.store)}")
        return "\n".join(lines)


def _check_free(path: Path) -> None:
    from ..errors import InputError
    from ..store.lock import holder

    found = holder(path)
    if found is not None:
        raise InputError("--store", str(path), f"is being written by {found.describe()}",
                         "verify it when that run has ended (its tiles in progress are not damage)")


def verify(store, *, repair: bool = False, scheduler=None, workers=None, progress=None) -> VerifyReport:
    """Check every chunk of ``store``; with ``repair``, recompute the damaged tiles (see the module)."""
    from ..store import check_store
    from ..store.integrity import Damage, scan, workflow_record_problem

    from ..errors import InputError
    from .cluster import check_scheduler, check_workers

    path = Path(store)
    attrs = check_store(path, record=False)
    if repair:
        from ..store.integrity import workflow_record_fix, workflow_record_problem

        if problem := workflow_record_problem(attrs):   # a repair recomputes from that record: none to trust
            raise InputError("--repair", str(path), f"cannot repair a store that {problem}",
                             workflow_record_fix(path))
        from ..models import get_model
        from ..store.layout import store_model

        written_by = get_model(store_model(attrs)).written_by
        if written_by:   # no point of it can be recomputed alone: each is continued from the one before
            from ..store.integrity import repair_fix

            raise InputError("--repair", str(path), f"cannot recompute points of a store that `bifurcation "
                             f"{written_by}` writes whole (each point is continued from the one before)",
                             repair_fix(path))
    target = check_scheduler(scheduler)   # checked with or without damage to repair
    check_workers(workers, embedded=target is None)
    if not repair and (scheduler is not None or workers is not None):
        raise InputError("--scheduler" if scheduler is not None else "--workers",
                         scheduler if scheduler is not None else workers,
                         "is only used to recompute damaged tiles", "add --repair, or leave it out")
    _check_free(path)
    damage, n_tiles, n_chunks = scan(path)
    if problem := workflow_record_problem(attrs):   # without repair (refused above): reported as damage
        damage = [Damage("zarr.json", (), problem.removeprefix("has "), kind="damaged"), *damage]
    if not repair or not (damage or _pending(path)):
        return VerifyReport(str(path), n_tiles, n_chunks, tuple(damage))
    return _repair(path, damage, n_tiles, n_chunks, scheduler, workers, progress)


#: The tiles a repair cleared and has not yet recomputed, in the store (a repair killed after clearing them
#: left them not computed, and the next ``verify --repair`` found "0 damaged" and did nothing).
PENDING = ".bifurcation.repair.json"


def _pending(path: Path) -> list[tuple]:
    import json

    try:
        return [tuple(t) for t in json.loads((path / PENDING).read_text(encoding="utf-8"))["tiles"]]
    except (OSError, ValueError, KeyError, TypeError):
        return []


def _repair(path: Path, first, n_tiles, n_chunks, scheduler, workers, progress) -> VerifyReport:
    from ..store import read_attrs
    from ..store.integrity import scan
    from ..store.lock import StoreLock
    from ..workflow import parse_workflow
    from .submission import submit

    workflow = parse_workflow(read_attrs(path)["workflow_toml"], source=f"{path} (workflow_toml)")
    with StoreLock(path).acquire(command="bifurcation verify --repair"):
        restored, _, tiles = _clear(path, workflow, pending=path / PENDING)
    tiles = sorted(set(tiles) | set(_pending(path)))   # with those an earlier repair left undone
    regions = [tuple(slice(k * c, (k + 1) * c) for k, c in zip(tile, (1, *workflow.tiles))) for tile in tiles]
    summary = {}
    if regions:
        summary = submit(workflow, store=path, scheduler=scheduler, workers=workers, progress=progress,
                         only=regions, command="bifurcation verify --repair").to_dict()
    after, _, _ = scan(path)
    if not after and not summary.get("failed"):
        (path / PENDING).unlink(missing_ok=True)
    return VerifyReport(str(path), n_tiles, n_chunks, tuple(first), len(tiles), restored, tuple(after), summary)


def _clear(path: Path, workflow, kinds=("damaged", "unfinished"), pending: Path | None = None) -> tuple[tuple, list, list]:
    """Under the lock: restore metadata, rewrite coordinates, delete the chunks of the tiles with damage of
    ``kinds`` (first listed in ``pending``, if given, with those it lists already)."""
    import json

    from ..store.integrity import clear_tiles, damaged_tiles, restore_metadata, scan

    restored = tuple(restore_metadata(path))
    damage, _, _ = scan(path)
    _rewrite_coordinates(path, workflow, damage)
    tiles = damaged_tiles(damage, kinds)
    if pending is not None and tiles:
        todo = sorted(set(tiles) | set(_pending(path)))
        part = pending.with_name(pending.name + ".part")
        part.write_text(json.dumps({"tiles": [list(map(int, t)) for t in todo]}), encoding="utf-8")
        part.replace(pending)
    clear_tiles(path, tiles)
    return restored, damage, tiles


def clear_damage(path, workflow) -> int:
    """For a resume (the caller holds the lock): make every damaged tile not done; returns how many.

    Unfinished tiles (a killed run's) are left alone: the resume rewrites them whole anyway, and only
    their missing points are computed.
    """
    return len(_clear(Path(path), workflow, ("damaged",))[2])


def _rewrite_coordinates(path: Path, workflow, damage) -> None:
    """Rewrite damaged coordinate chunks from the workflow (a coordinate is the workflow's axis of that name)."""
    import numpy as np
    import zarr

    from ..store.zarr_store import _quiet

    names = {d.chunk.split("/")[0] for d in damage if len(d.tile) == 1}
    if not names:
        return
    with _quiet():
        group = zarr.open_group(str(path), mode="r+", use_consolidated=False)
        for name in names:
            values = getattr(workflow, name)
            array = group[name].with_config({"write_empty_chunks": True})
            array[...] = np.asarray(values, dtype=object if array.dtype.kind in "OTU" else array.dtype)
