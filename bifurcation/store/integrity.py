"""Integrity of a store: every chunk checked, ``done`` consistent with the data, damaged tiles found.

A tile (one chunk of every data variable) is *sound* when

1. every chunk of it that exists decodes: zstd and the CRC-32C of each chunk (``chunk_codecs``) catch
   any flipped bit and any truncation;
2. it is written in all of its variables or in none: a tile writer rewrites every chunk of its tile
   (empty chunks included), so a chunk missing beside written ones was deleted;
3. ``done`` agrees with the data: a point marked done does not hold the *not computed* mark (a
   variable whose fill value means "not-computed", e.g. ``status`` 0), and a point not marked done
   holds the fill value in every variable.

Anything else is *damage*, reported per chunk (``Damage``); ``clear_tiles`` deletes the damaged tiles'
chunks (``done`` first), after which a resume recomputes exactly those tiles. Coordinate arrays are
checked too. Everything here iterates over the arrays the store has (the data variables are the arrays
shaped like ``done``), not over a fixed list of names.
"""

from __future__ import annotations

import itertools
import json
import os
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from ..errors import InputError, shown_path

__all__ = ["DONE", "Damage", "StoreDamagedError", "TileReader", "broken_metadata", "clear_tiles", "damaged_tiles",
           "missing_chunks", "repair_command", "repair_fix", "restore_metadata", "scan", "workflow_record_fix",
           "workflow_record_problem"]

#: The resume mask: True where a point's values are written.
DONE = "done"


@dataclass(frozen=True)
class Damage:
    """One damaged chunk: ``chunk`` is its key in the store (``delta/c/0/1/2``), ``tile`` its index."""

    chunk: str
    tile: tuple
    problem: str
    #: "unfinished" (a tile a killed writer left half written: data without ``done``, or values where
    #: ``done`` is False; a resume rewrites it anyway), or "damaged" (anything a resume would not see)
    kind: str = "damaged"

    def __str__(self) -> str:
        return f"{self.chunk}: {self.problem}"


def repair_command(path) -> str:
    """The command that makes a damaged store whole again: ``verify --repair`` (it recomputes the damaged
    tiles), or, for a store that its model's command writes whole (``Model.written_by``: no point of it can
    be recomputed alone), that command."""
    written_by = _written_by(path)
    if written_by:
        return f"bifurcation {written_by} WORKFLOW --out {shown_path(Path(path).parent)}"
    return f"bifurcation verify --store {shown_path(path)} --repair"


def repair_fix(path) -> str:
    """What to do about damage in the store at ``path``: the fix of an error message."""
    if _written_by(path):
        return (f"run `{repair_command(path)}` to write it again (its workflow is the store's attribute "
                "workflow_toml)")
    return f"run `{repair_command(path)}` to recompute the damaged tiles"


def workflow_record_problem(attrs: dict) -> str | None:
    """What is wrong with the store's record of its workflow (None if nothing): ``workflow_toml`` against the
    ``workflow_sha256`` stored with it. A store whose workflow text was edited, cut or removed was accepted by
    every command, and ``report`` printed the edited text as the store's workflow (walk 6)."""
    import hashlib

    text, sha = attrs.get("workflow_toml"), attrs.get("workflow_sha256")
    if not isinstance(text, str):
        return "has no record of its workflow (workflow_toml is missing from its zarr.json)"
    if not isinstance(sha, str) or hashlib.sha256(text.encode()).hexdigest() != sha:
        return ("has a record of its workflow that does not match its checksum (workflow_toml or workflow_sha256 "
                "edited or cut in its zarr.json)")
    return None


def workflow_record_fix(path) -> str:
    """The fix for a damaged workflow record. The record is the one copy (the consolidated metadata keeps the
    arrays', not the root's attributes), and the workflow cannot be recomputed from the results: the study is
    computed again from the user's workflow file."""
    written_by = _written_by(path)
    if written_by:
        return f"run `bifurcation {written_by} WORKFLOW --out DIR` with the workflow file to write the store again"
    return ("submit the workflow file again into a new store (--store NEW.zarr, or --new-store): this store's "
            "results cannot be tied to a workflow")


def _written_by(path) -> str:
    from ..models import get_model
    from .layout import store_model
    from .zarr_store import read_attrs

    try:
        return get_model(store_model(read_attrs(path))).written_by
    except Exception:  # noqa: BLE001 — unreadable attributes or an unknown model: the usual repair
        return ""


class StoreDamagedError(InputError):
    """A read met a damaged chunk: one line naming the chunk and the repair command."""

    def __init__(self, path, damage: Damage) -> None:
        super().__init__("--store", str(path), f"chunk {damage} (no value of it is shown)", repair_fix(path))
        self.damage = damage


def _not_computed_fill(array) -> object | None:
    """The fill value of ``array`` if it means "not computed" (its flag meaning), else None."""
    attrs = dict(array.attrs)
    values, meanings = attrs.get("flag_values"), str(attrs.get("flag_meanings", "")).split()
    fill = array.metadata.fill_value
    if values and len(values) == len(meanings):
        for value, meaning in zip(values, meanings):
            if meaning == "not-computed" and value == fill:
                return fill
    return None


def _is_fill(values: np.ndarray, fill) -> np.ndarray:
    if values.dtype.kind == "f" and isinstance(fill, float) and np.isnan(fill):
        return np.isnan(values)
    return values == np.asarray(fill, dtype=values.dtype)


class TileReader:
    """Checked reads of the tiles of the store at ``path`` (chunk by chunk, never the whole store).

    ``in_progress`` tolerates tiles a writer is writing or left unfinished (data written, ``done`` not
    yet): their points read as not computed instead of as damage (``query``: never a number that
    ``done`` does not vouch for, and no error for a store a run is filling or was killed while filling).
    """

    def __init__(self, path, *, in_progress: bool = False) -> None:
        import zarr

        from .zarr_store import _quiet

        self.path = Path(path)
        self.in_progress = in_progress
        broken = broken_metadata(path)
        if broken:
            raise StoreDamagedError(path, broken[0])
        with _quiet():
            group = zarr.open_group(str(path), mode="r", use_consolidated=False)
            members = dict(group.arrays())
        if DONE not in members:
            raise StoreDamagedError(path, Damage(f"{DONE}/zarr.json", (), "array metadata missing"))
        self.done = members[DONE]
        self.shape, self.chunks = self.done.shape, self.done.chunks
        self.variables = {name: a for name, a in members.items() if a.shape == self.shape}
        self.coordinates = {name: a for name, a in members.items() if name not in self.variables}
        self.marks = {name: fill for name, a in self.variables.items()
                      if (fill := _not_computed_fill(a)) is not None}
        self.grid = tuple(-(-n // c) for n, c in zip(self.shape, self.chunks))

    # -- chunks ---------------------------------------------------------------------------------
    def key(self, name: str, tile: tuple) -> str:
        array = self.variables.get(name) or self.coordinates[name]
        return f"{name}/{array.metadata.encode_chunk_key(tuple(tile))}"

    def exists(self, name: str, tile: tuple) -> bool:
        return (self.path / self.key(name, tile)).is_file()

    def region(self, tile: tuple) -> tuple:
        return tuple(slice(k * c, min((k + 1) * c, n)) for k, c, n in zip(tile, self.chunks, self.shape))

    def tiles(self) -> Iterator[tuple]:
        return itertools.product(*(range(g) for g in self.grid))

    def _decode(self, array, name: str, tile: tuple, region: tuple) -> np.ndarray:
        from .zarr_store import _quiet

        try:
            with _quiet():
                return np.asarray(array[region])
        except Exception as exc:  # noqa: BLE001 — any failure to decode a chunk is damage, named
            problem = "checksum mismatch" if "checksum" in str(exc).lower() else \
                f"cannot be decoded ({type(exc).__name__})"
            raise StoreDamagedError(self.path, Damage(self.key(name, tile), tile, problem)) from None

    def read(self, tile: tuple) -> dict[str, np.ndarray]:
        """Every variable of ``tile``, checked (``StoreDamagedError`` naming the first damaged chunk).

        Points that are not done read as the fill values (with ``in_progress``, whatever a live
        writer has put there so far is not shown).
        """
        damage = self.check(tile)
        if damage:
            raise StoreDamagedError(self.path, damage[0])
        return self._values

    def check(self, tile: tuple) -> list[Damage]:
        """The damage of ``tile`` (empty if sound); its values are kept for ``read``."""
        tile = tuple(tile)
        region = self.region(tile)
        present = {name: self.exists(name, tile) for name in self.variables}
        self._values = values = {}
        odd = self.not_files(tile, present)
        if odd:
            return odd
        if not any(present.values()):   # never written: fill values (the store's reading of it)
            for name, array in self.variables.items():
                shape = tuple(s.stop - s.start for s in region)
                values[name] = np.full(shape, array.metadata.fill_value, dtype=array.dtype)
            return []
        damage = []
        if not present[DONE]:
            if self.in_progress:
                return self._as_not_computed(region)
            return [Damage(self.key(DONE, tile), tile, "missing beside written data chunks", "unfinished")]
        damage += [Damage(self.key(name, tile), tile, "missing (deleted?) in a written tile")
                   for name, ok in present.items() if not ok]
        for name, array in self.variables.items():
            if present[name]:
                try:
                    values[name] = self._decode(array, name, tile, region)
                except StoreDamagedError as exc:
                    damage.append(exc.damage)
        if damage:
            return damage
        done = values[DONE].astype(bool)
        for name, fill in self.marks.items():
            if (values[name][done] == fill).any():
                return [Damage(self.key(name, tile), tile, "marks a point not computed where done is True")]
        for name, array in self.variables.items():
            if name != DONE and not _is_fill(values[name][~done], array.metadata.fill_value).all():
                if self.in_progress:
                    return self._as_not_computed(region, values[DONE])
                return [Damage(self.key(name, tile), tile, "holds a value where done is False", "unfinished")]
        return []

    def not_files(self, tile: tuple, present: dict | None = None) -> list[Damage]:
        """Chunk paths of ``tile`` that exist but are not files (a directory, a link that loops or leads nowhere):
        a submit failed on them with "Is a directory", exit 1, and a directory at ``done``'s chunk read as a tile
        never written (walk 6)."""
        present = present if present is not None else {name: self.exists(name, tile) for name in self.variables}
        return [Damage(self.key(name, tile), tile, "is not a chunk file (a directory, or a link to nothing)")
                for name, ok in present.items() if not ok and os.path.lexists(self.path / self.key(name, tile))]

    def _as_not_computed(self, region, done=None) -> list:
        """A tile a live writer is writing: the points already done are kept, the rest read as fill."""
        values = self._values
        shape = tuple(s.stop - s.start for s in region)
        keep = np.zeros(shape, dtype=bool) if done is None else done.astype(bool)
        for name, array in self.variables.items():
            fill = np.full(shape, array.metadata.fill_value, dtype=array.dtype)
            values[name] = np.where(keep, values[name], fill) if name in values and done is not None else fill
        return []

    def check_coordinates(self) -> tuple[list[Damage], int]:
        """Damage of the coordinate arrays' chunks, and how many chunks were checked."""
        damage, n_chunks = [], 0
        for name, array in self.coordinates.items():
            for k in range(-(-array.shape[0] // array.chunks[0]) if array.ndim else 1):
                tile = (k,) if array.ndim else ()
                region = (slice(k * array.chunks[0], (k + 1) * array.chunks[0]),) if array.ndim else ()
                key = self.key(name, tile)
                n_chunks += 1
                if not (self.path / key).is_file():
                    damage.append(Damage(key, tile, "missing coordinate chunk"))
                    continue
                try:
                    self._decode(array, name, tile, region)
                except StoreDamagedError as exc:
                    damage.append(exc.damage)
        return damage, n_chunks


def _consolidated(path) -> dict:
    root = json.loads((Path(path) / "zarr.json").read_text(encoding="utf-8"))
    return (root.get("consolidated_metadata") or {}).get("metadata") or {}


def broken_metadata(path) -> list[Damage]:
    """Arrays of the store (as its consolidated metadata lists them) whose ``zarr.json`` is missing or
    unreadable (a deleted ``done/``)."""
    damage = []
    for name, record in _consolidated(path).items():
        problem = _metadata_problem(Path(path) / name / "zarr.json", record)
        if problem:
            damage.append(Damage(f"{name}/zarr.json", (), problem))
    return damage


#: The keys of an array's zarr.json that say how its chunks are read (its attributes may change).
_LAYOUT = ("shape", "data_type", "chunk_grid", "chunk_key_encoding", "fill_value", "codecs", "dimension_names")


def _metadata_problem(file: Path, record) -> str | None:
    """What is wrong with the array metadata ``file`` against its ``record`` in the consolidated metadata (None
    if nothing). A zarr.json edited to another shape or data type was a KeyError or TypeError traceback from
    query, export, report, verify and submit (walk 6)."""
    try:
        meta = json.loads(file.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return "array metadata missing or unreadable"
    if not isinstance(meta, dict) or not isinstance(record, dict) or meta.get("node_type") != record.get("node_type"):
        return "array metadata unreadable"
    if record.get("node_type") != "array":
        return None
    changed = [key for key in _LAYOUT if meta.get(key) != record.get(key)]
    if changed:
        return f"array metadata differs from the store's record of it ({', '.join(changed)})"
    return None


def scan(path) -> tuple[list[Damage], int, int]:
    """``(damage, tiles checked, chunks checked)`` of the store at ``path`` (the whole store).

    Array metadata comes first: with an array's metadata missing, its chunks cannot be read, so only
    that is reported (``restore_metadata``, then scan again).
    """
    damage = broken_metadata(path)
    if damage:
        return damage, 0, 0
    reader = TileReader(path)
    damage, n_chunks = reader.check_coordinates()
    n_tiles = 0
    for tile in reader.tiles():
        damage += reader.check(tile)
        n_tiles += 1
        n_chunks += sum(reader.exists(name, tile) for name in reader.variables)
    from .catalog import catalog_damage, has_catalog

    if has_catalog(path):   # per-event catalogs: every chunk decoded, every done run's chunks present
        more, n_more = catalog_damage(path, reader)
        damage += more
        n_chunks += n_more
    return damage, n_tiles, n_chunks


def missing_chunks(path) -> list[Damage]:
    """The damage ``scan`` finds by file names alone: array metadata missing, or a data chunk missing
    beside a written tile's ``done``. Reads no chunk (milliseconds on any store), for the commands that
    load a whole store: zarr reads a missing chunk as its fill value, so a deleted ``delta`` chunk was a
    log-scale ValueError traceback from ``report`` and a silent "0 points" from ``fit-period``."""
    damage = broken_metadata(path)
    if damage:
        return damage
    reader = TileReader(path)
    for tile in reader.tiles():
        damage += reader.not_files(tile)
        if reader.exists(DONE, tile):
            damage += [Damage(reader.key(name, tile), tile, "missing (deleted?) in a written tile")
                       for name in reader.variables if not reader.exists(name, tile)]
    return damage


def damaged_tiles(damage: list[Damage], kinds=("damaged", "unfinished")) -> list[tuple]:
    """The tiles to recompute: those of data-chunk damage of ``kinds`` (coordinates are rewritten, not
    recomputed)."""
    return sorted({d.tile for d in damage if d.tile and len(d.tile) > 1 and d.kind in kinds})


def clear_tiles(path, tiles: list[tuple]) -> None:
    """Delete every chunk of ``tiles`` (``done`` first), so that a resume recomputes exactly them."""
    from .catalog import clear_catalogs, has_catalog

    reader = TileReader(path)
    catalogs = has_catalog(path)
    for tile in tiles:
        for name in [DONE, *(n for n in reader.variables if n != DONE)]:
            chunk = reader.path / reader.key(name, tuple(tile))
            if chunk.is_dir() and not chunk.is_symlink():   # a directory where a chunk goes (not_files)
                shutil.rmtree(chunk)
            else:
                chunk.unlink(missing_ok=True)
        if catalogs:   # after done: the runs' catalogs and checkpoints go with their tile
            clear_catalogs(path, reader.shape, reader.region(tuple(tile)))


def restore_metadata(path) -> list[str]:
    """Rewrite the ``zarr.json`` of arrays whose metadata is missing or unreadable from the copy in the
    store's consolidated metadata; returns the names restored."""
    restored = []
    for name, meta in _consolidated(path).items():
        file = Path(path) / name / "zarr.json"
        if _metadata_problem(file, meta) is None:
            continue
        if file.is_dir() and not file.is_symlink():
            shutil.rmtree(file)
        file.parent.mkdir(parents=True, exist_ok=True)
        file.write_text(json.dumps(meta, indent=2), encoding="utf-8")
        restored.append(name)
    return restored
