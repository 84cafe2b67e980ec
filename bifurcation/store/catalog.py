"""Ragged catalogs in the store: one value per event of a run, for models with ``per_event`` outputs.

Layout (docs/models.md, "Catalogs"). The store's group ``catalog`` holds one 1-D array per per-event
output (``catalog/potency``, …), dimension ``event``, of length ``runs × events_per_run``:

* ``runs`` is the number of grid points (runs), numbered in C order over the store's dimensions
  (label, *axes): run r is ``numpy.ravel_multi_index(index, shape)``;
* ``events_per_run`` (the *capacity*) is the model's ``catalog_size`` axis's largest value rounded up
  to a multiple of the chunk C (``[tiles] catalog``), so run r's events are the slice
  ``[r·capacity, r·capacity + count_r)``: its **offset** is r·capacity and its **count** the per-run
  output named by the model's ``catalog_count`` (``events_done`` of the chain);
* chunks hold C events and never straddle two runs, so a query for one run reads only the chunks of
  its own events (and its tile of per-run outputs), and each chunk has exactly one writer, the task
  that computes its run. Chunks past a run's count are never written (a Zarr chunk not written takes
  no space and reads as the fill value); every chunk carries zstd and a CRC-32C like every other.

Write order: a run's catalog chunks first, then its tile's per-run outputs, ``done`` last, so
``done`` never claims a catalog that is not there. A long run also writes its full chunks as it goes
(``Checkpoints``), with its state in ``checkpoints/<r>.npz`` (CRC-32 and the store's ``run_id``
inside; written to a temporary file and renamed, so a kill leaves the previous checkpoint whole):
a run recomputed after its worker died resumes from the last checkpoint.
"""

from __future__ import annotations

import io
import json
import os
import zlib
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["CATALOG", "CHECKPOINTS", "Checkpoints", "catalog_damage", "catalog_dataset", "catalog_layout",
           "clear_catalogs",
           "create_catalog", "drop_checkpoints", "has_catalog", "open_catalog", "read_catalog", "run_indices",
           "tile_checkpoints",
           "write_catalogs"]

#: The group of the catalog arrays, and the directory of the run checkpoints, in the store.
CATALOG = "catalog"
CHECKPOINTS = "checkpoints"


def catalog_layout(workflow) -> dict:
    """``{"runs", "chunk", "events_per_run"}`` of ``workflow``'s store (None-free: only for catalog models)."""
    spec = workflow.spec
    chunk = int(workflow.catalog_chunk)
    largest = int(max(workflow.axes[spec.catalog_size]))
    return {"runs": int(np.prod(workflow.shape)), "chunk": chunk,
            "events_per_run": -(-largest // chunk) * chunk, "count": spec.catalog_count,
            "order": "C order over (" + ", ".join(spec.dims) + ")"}


def create_catalog(path, workflow) -> None:
    """The empty catalog arrays of ``workflow``'s store (metadata only)."""
    import zarr

    from .zarr_store import _quiet, chunk_codecs

    spec = workflow.spec
    layout = catalog_layout(workflow)
    length = layout["runs"] * layout["events_per_run"]
    with _quiet():
        group = zarr.open_group(str(path), mode="r+", use_consolidated=False).require_group(CATALOG)
        group.attrs.update(layout)
        for output in spec.catalog_outputs:
            array = group.create_array(output.name, shape=(length,), chunks=(layout["chunk"],), dtype=output.dtype,
                                       fill_value=output.fill, compressors=chunk_codecs(),
                                       dimension_names=("event",))
            array.attrs.update({"long_name": output.long_name, "units": output.units})


class _Catalog:
    """The catalog arrays of the store at ``path`` (read or write), and its layout."""

    def __init__(self, path, mode: str = "r") -> None:
        import zarr

        from .zarr_store import _quiet

        self.path = Path(path)
        try:
            with _quiet():
                root = zarr.open_group(str(path), mode=mode, use_consolidated=False)
                self.group = root[CATALOG]
                self.grid = tuple(root["done"].shape)
                self.arrays = {name: a.with_config({"write_empty_chunks": True}) if mode != "r" else a
                               for name, a in self.group.arrays()}
        except (ValueError, KeyError, TypeError):   # a zarr.json cut mid-write: JSONDecodeError is a ValueError
            bad = self._unreadable_metadata()
            if bad is None:
                raise
            from .integrity import Damage, StoreDamagedError

            # (report read the catalog without the checks query makes: a 107-line traceback, issue 21 walk 3)
            raise StoreDamagedError(self.path, Damage(bad, (), "array metadata missing or unreadable")) from None
        attrs = dict(self.group.attrs)
        self.chunk, self.capacity, self.runs = int(attrs["chunk"]), int(attrs["events_per_run"]), int(attrs["runs"])
        self.count = str(attrs["count"])

    def _unreadable_metadata(self) -> str | None:
        """The key of the first ``zarr.json`` of the catalog (or the root, or ``done``) that is not JSON."""
        places = [self.path, self.path / "done", self.path / CATALOG]
        if (self.path / CATALOG).is_dir():
            places += sorted(p for p in (self.path / CATALOG).iterdir() if p.is_dir())
        for place in places:
            try:
                json.loads((place / "zarr.json").read_bytes())
            except (OSError, ValueError):
                return (place / "zarr.json").relative_to(self.path).as_posix()
        return None

    def chunks_of(self, run: int, count: int) -> range:
        """Chunk indices holding the first ``count`` events of ``run``."""
        first = run * self.capacity // self.chunk
        return range(first, first + -(-count // self.chunk))

    def key(self, name: str, chunk: int) -> str:
        return f"{CATALOG}/{name}/{self.arrays[name].metadata.encode_chunk_key((chunk,))}"

    def write(self, run: int, values: dict, start: int = 0, *, first: int = 0) -> None:
        """Events ``start`` … of ``run`` (``start`` a multiple of the chunk), whole chunks, padded with fill;
        ``values`` hold the events from ``first`` (≤ ``start``) on."""
        from .zarr_store import _quiet

        with _quiet():
            for name, array in self.arrays.items():
                data = np.asarray(values[name], dtype=array.dtype)[start - first:]
                if data.size == 0:
                    continue
                padded = -(-data.size // self.chunk) * self.chunk
                block = np.full(padded, array.metadata.fill_value, dtype=array.dtype)
                block[:data.size] = data
                offset = run * self.capacity + start
                array[offset:offset + padded] = block

    def read(self, run: int, count: int, names=None) -> dict:
        """The first ``count`` events of ``run``, chunk by chunk checked (``StoreDamagedError`` names one)."""
        from .integrity import Damage, StoreDamagedError
        from .zarr_store import _quiet

        out = {}
        offset = run * self.capacity
        for name in names or self.arrays:
            array = self.arrays[name]
            for chunk in self.chunks_of(run, count):
                if not (self.path / self.key(name, chunk)).is_file():
                    raise StoreDamagedError(self.path, Damage(self.key(name, chunk), (), "catalog chunk missing"))
            try:
                with _quiet():
                    out[name] = np.asarray(array[offset:offset + count])
            except Exception:
                for chunk in self.chunks_of(run, count):
                    try:
                        with _quiet():
                            array[chunk * self.chunk:(chunk + 1) * self.chunk]
                    except Exception as exc:  # noqa: BLE001
                        problem = "checksum mismatch" if "checksum" in str(exc).lower() else \
                            f"cannot be decoded ({type(exc).__name__})"
                        raise StoreDamagedError(self.path, Damage(self.key(name, chunk), (), problem)) from None
                raise
        return out


def open_catalog(path):
    """A reader of the catalog of the store at ``path``: ``.read(run, count, names)`` returns the first
    ``count`` events of run ``run`` (its flat C-order index over ``model.dims``) for the per-event
    outputs ``names``, chunk by chunk checked; ``.count`` names the per-run output that counts them."""
    return _Catalog(path)


def has_catalog(path) -> bool:
    return (Path(path) / CATALOG / "zarr.json").is_file()


def run_indices(shape, region) -> np.ndarray:
    """Flat run numbers (C order over ``shape``) of the points of ``region`` (slices), in C order."""
    grids = np.meshgrid(*(np.arange(s.start, s.stop) for s in region), indexing="ij")
    return np.ravel_multi_index(tuple(grids), shape)


_OPEN: dict = {}   # (path, run_id) → _Catalog opened for writing, per process (like zarr_store._WRITERS)


def _writer(path, run_id: str) -> _Catalog:
    key = (str(path), str(run_id))
    hit = _OPEN.get(key)
    if hit is None:
        if len(_OPEN) >= 4:
            _OPEN.pop(next(iter(_OPEN)))
        hit = _OPEN[key] = _Catalog(path, "r+")
    return hit


def write_catalogs(path, shape, tile, values: dict, model, run_id: str) -> None:
    """The catalogs of ``tile``'s computed runs (``values["done"]``), before its per-run outputs."""
    cat = _writer(path, run_id)
    runs = run_indices(shape, tile.region).reshape(tile.shape)
    done = np.asarray(values["done"], dtype=bool)
    names = [o.name for o in model.catalog_outputs]
    for index in zip(*np.nonzero(done)):
        cat.write(int(runs[index]), {name: values[name][index] for name in names})


def clear_catalogs(path, shape, region) -> None:
    """Delete the catalog chunks and checkpoints of the runs of ``region`` (a tile being recomputed)."""
    cat = _Catalog(path)
    per_run = cat.capacity // cat.chunk
    runs = {int(r) for r in run_indices(shape, region).ravel()}
    for name in cat.arrays:   # the chunk files that exist (a run's capacity may be 10^6 chunks, its count few)
        root = cat.path / CATALOG / name
        for file in root.rglob("*"):
            if file.is_file() and file.name.isdigit() and int(file.name) // per_run in runs:
                file.unlink(missing_ok=True)
    for run in runs:
        _checkpoint_file(path, run).unlink(missing_ok=True)


def catalog_damage(path, reader) -> tuple[list, int]:
    """Damage of the catalogs: every catalog chunk decoded (checksum), and every done run's chunks
    present. Each ``Damage`` names the tile of the run, so ``verify --repair`` recomputes it."""
    from .integrity import Damage, StoreDamagedError
    from .zarr_store import _quiet

    cat = _Catalog(path)
    damage, n_chunks = [], 0
    shape = reader.shape

    def tile_of(run: int) -> tuple:
        return tuple(int(i) // c for i, c in zip(np.unravel_index(run, shape), reader.chunks))
    for name, array in cat.arrays.items():
        root = cat.path / CATALOG / name
        for file in root.rglob("*"):
            if not file.is_file() or file.name == "zarr.json":
                continue
            try:
                chunk = int(file.relative_to(root).parts[-1])
            except ValueError:
                continue
            n_chunks += 1
            run = chunk * cat.chunk // cat.capacity
            try:
                with _quiet():
                    np.asarray(array[chunk * cat.chunk:(chunk + 1) * cat.chunk])
            except Exception as exc:  # noqa: BLE001
                problem = "checksum mismatch" if "checksum" in str(exc).lower() else \
                    f"cannot be decoded ({type(exc).__name__})"
                damage.append(Damage(cat.key(name, chunk), tile_of(run), problem))
    for tile in reader.tiles():
        try:
            values = reader.read(tile)
        except StoreDamagedError:
            continue   # reported by the tile scan
        runs = run_indices(shape, reader.region(tile)).reshape(values["done"].shape)
        for index in zip(*np.nonzero(values["done"])):
            run, count = int(runs[index]), int(values[cat.count][index])
            if count > cat.capacity:
                damage.append(Damage(reader.key(cat.count, tile), tuple(tile),
                                     f"counts {count} events, more than the catalog's {cat.capacity} per run"))
                continue
            for chunk in cat.chunks_of(run, count):
                for name in cat.arrays:
                    if not (cat.path / cat.key(name, chunk)).is_file():
                        damage.append(Damage(cat.key(name, chunk), tuple(tile), "catalog chunk of a done run missing"))
    return damage, n_chunks


def read_catalog(store, *, law=None, nearest: bool = False, notes=None, **axes) -> dict:
    """The catalog of the one run of ``store`` selected by ``law`` and one value per axis.

    Returns ``{"run": {label, axes, status, per-run outputs}, "<output>": array, ...}`` with one array
    per per-event output (``count`` events). Reads the run's tile (checked) and only the catalog chunks
    of its own events. A selection of more than one run, or of a run not computed yet, is an
    ``InputError`` naming what to add.
    """
    from .query import _Plan

    plan = _Plan(store, law, {k: v for k, v in axes.items() if v is not None}, nearest, notes)
    model = plan.model
    if not model.catalog_outputs:
        raise InputError("store", str(store), f"holds model {model.name!r}, which has no per-event catalogs",
                         "query it without --catalog")
    several = [d for d in plan.dims if len(plan.selected[d]) != 1]
    if several:
        d = several[0]
        option = "--law" if d == model.labels.name else model.axis(d).option
        raise InputError(option, f"{len(plan.selected[d])} labels", "selects more than one run for a catalog",
                         f"give one value of {option} (labels: {', '.join(map(str, plan.labels[d][:6]))}"
                         + (", ..." if len(plan.labels[d]) > 6 else "") + ")")
    index = tuple(plan.selected[d][0] for d in plan.dims)
    tile = tuple(i // c for i, c in zip(index, plan.reader.chunks))
    values = plan.reader.read(tile)
    local = tuple(i - t * c for i, t, c in zip(index, tile, plan.reader.chunks))
    run = int(np.ravel_multi_index(index, plan.reader.shape))
    if not values["done"][local]:
        raise _not_done(plan.reader.path, run)
    cat = _Catalog(plan.reader.path)
    count = int(values[cat.count][local])
    names = [n for n in plan.reader.variables if n != "done"]
    record = plan.maker.make(plan.labels[plan.dims[0]][index[0]],
                             {d: plan.labels[d][i] for d, i in zip(plan.dims[1:], index[1:])},
                             int(values["status"][local]), {n: values[n][local].item() for n in names})
    out = {"run": record}
    out.update(cat.read(run, count, [o.name for o in model.catalog_outputs]))
    return out


def _not_done(path, run: int) -> InputError:
    """The error for a run not done: what the store holds of it (a checkpoint's events; status and report
    count only done runs, so they are not shown as a catalog), who is writing it, and how to resume."""
    from .lock import holder
    from .zarr_store import read_attrs

    events = checkpointed_events(path, run)
    found = holder(path)
    attrs = read_attrs(path)
    if found is not None:
        fix = f"it is being written by {found.describe()}: query it when that run ends"
    else:
        import shlex

        try:   # the command that created the store, less --new-store (which would drop the checkpoints)
            words = [w for w in shlex.split(str(attrs.get("command") or "")) if w != "--new-store"]
        except ValueError:
            words = []
        again = f"`{shlex.join(words)}`" if words[:2] == ["bifurcation", "submit"] else \
            "its workflow with `bifurcation submit WORKFLOW --store STORE`"
        fix = f"resume with {again} (it continues from the checkpoint), or query another run"
    if events:
        return InputError("store", str(path), f"has {events} events of this run checkpointed, run not finished "
                          "(a catalog is shown only for a finished run)", fix)
    return InputError("store", str(path), "has not computed this run yet",
                      fix.replace(" (it continues from the checkpoint)", ""))


def checkpointed_events(path, run: int) -> int:
    """Events of ``run`` saved by its last checkpoint in the store at ``path`` (0: none, or a checkpoint of
    another run_id, i.e. of a store this one replaced). Reads the checkpoint's metadata only."""
    from .zarr_store import read_attrs

    try:
        with np.load(_checkpoint_file(path, run), allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
    except (OSError, ValueError, KeyError):
        return 0
    if meta.get("run") != run or meta.get("run_id") != read_attrs(path).get("run_id"):
        return 0
    return int(meta.get("events", 0))


# -- checkpoints ---------------------------------------------------------------------------------------
def _checkpoint_file(path, run: int) -> Path:
    return Path(path) / CHECKPOINTS / f"{run}.npz"


class Checkpoints:
    """Where a tile's runs save and find their checkpoints (``model.runner(..., checkpoints=...)``).

    ``runs[i]`` is the flat run number of the runner's point ``i``; ``every`` the catalog chunk C.
    ``save`` writes the run's full catalog chunks not yet written, then its state (atomically);
    ``load`` returns the last sound checkpoint of this store (``run_id``), or None.
    """

    def __init__(self, path, run_id: str, runs) -> None:
        self.path, self.run_id = Path(path), str(run_id)
        self.runs = np.asarray(runs, dtype=np.int64).ravel()
        self.catalog = _writer(path, run_id)
        self.every = self.catalog.chunk
        self._written = {}

    def load(self, i: int) -> dict | None:
        run = int(self.runs[i])
        file = _checkpoint_file(self.path, run)
        try:
            with np.load(file, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                blobs = {name: data[name].tobytes() for name in meta["state"]}
        except (OSError, ValueError, KeyError):
            return None   # none, or unreadable: the run starts from the beginning
        crc = 0
        for name in meta["state"]:
            crc = zlib.crc32(blobs[name], crc)
        if meta.get("run_id") != self.run_id or meta.get("run") != run or meta.get("crc32") != crc:
            return None
        events = int(meta["events"])
        try:
            catalog = self.catalog.read(run, events)
        except InputError:
            return None
        self._written[i] = events
        return {"state": blobs, "catalog": catalog, "steps": int(meta["steps"]), "events": events}

    def save(self, i: int, state: dict, catalog: dict, *, steps: int, first: int = 0) -> None:
        """``catalog`` holds the run's events from ``first`` on (0: all of them; a runner that saved the
        events before ``first`` at earlier calls passes only the new ones: no copy of the whole catalog)."""
        from .zarr_store import _check_run

        _check_run(str(self.path), self.run_id)   # never into a store that replaced this run's
        run = int(self.runs[i])
        events = first + len(next(iter(catalog.values())))
        start = self._written.get(i, 0)
        if first > start:
            raise ValueError(f"checkpoint of run {run}: events {start}..{first} were never saved")
        self.catalog.write(run, catalog, start, first=first)
        self._written[i] = events
        blobs = {name: np.ascontiguousarray(value).tobytes() for name, value in state.items()}
        crc = 0
        for name in blobs:
            crc = zlib.crc32(blobs[name], crc)
        meta = {"run_id": self.run_id, "run": run, "events": events, "steps": int(steps), "crc32": crc,
                "state": list(blobs)}
        buffer = io.BytesIO()
        np.savez(buffer, meta=np.array(json.dumps(meta)),
                 **{name: np.frombuffer(blob, dtype=np.uint8) for name, blob in blobs.items()})
        file = _checkpoint_file(self.path, run)
        file.parent.mkdir(exist_ok=True)
        tmp = file.with_name(f".{file.name}.{os.getpid()}.tmp")
        with open(tmp, "wb") as out:
            out.write(buffer.getvalue())
            out.flush()
            os.fsync(out.fileno())
        os.replace(tmp, file)


def tile_checkpoints(path, run_id: str, tile) -> Checkpoints:
    """The checkpoints of ``tile``'s points to compute, in the order the runner gets them."""
    runs = run_indices(_writer(path, run_id).grid, tile.region).reshape(tile.shape)
    mask = np.ones(tile.shape, dtype=bool) if tile.todo is None else np.asarray(tile.todo, dtype=bool)
    return Checkpoints(path, run_id, runs[mask])


def drop_checkpoints(path, shape, tile, done) -> None:
    """Delete the checkpoints of ``tile``'s runs that are done (their catalogs are whole)."""
    runs = run_indices(shape, tile.region).reshape(tile.shape)
    for run in runs[np.asarray(done, dtype=bool)]:
        _checkpoint_file(path, int(run)).unlink(missing_ok=True)


def catalog_dataset(path):
    """The catalogs of the store at ``path`` as CF *contiguous ragged arrays* (CF 1.10, §9.3.3), for
    netCDF export: dimension ``run`` (every grid point, C order over the store's dimensions) with
    ``run_count`` (its events, attribute ``sample_dimension = "event"``), and one variable per
    per-event output along ``event``: the events of run 0, then of run 1, ... (runs not done: 0
    events). Read into memory, run by run, every chunk checked."""
    import xarray as xr

    from .integrity import TileReader

    reader = TileReader(path)
    cat = _Catalog(path)
    counts = np.zeros(reader.shape, dtype=np.int64)
    for tile in reader.tiles():
        values = reader.read(tile)
        counts[reader.region(tile)] = np.where(values["done"], values[cat.count], 0)
    counts = counts.ravel()
    data = {name: [] for name in cat.arrays}
    for run in np.flatnonzero(counts):
        for name, values in cat.read(int(run), int(counts[run])).items():
            data[name].append(values)
    variables = {"run_count": ("run", counts, {"long_name": "events of each run (C order over "
                                               + ", ".join(reader.done.metadata.dimension_names or ()) + ")",
                                               "sample_dimension": "event", "units": "1"})}
    for name, array in cat.arrays.items():
        values = np.concatenate(data[name]) if data[name] else np.empty(0, dtype=array.dtype)
        variables[f"event_{name}"] = ("event", values, {k: v for k, v in array.attrs.items()})
    return xr.Dataset(variables)
