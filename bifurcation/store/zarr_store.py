"""Create, open, check and write the Zarr store (layout in ``bifurcation.store.layout``).

Only the coordinator creates the store, changes its metadata and consolidates it; tile writers (worker
tasks or the coordinator) only write the chunks of their own tile.
"""

from __future__ import annotations

import json
import shutil
import warnings
from collections import OrderedDict
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..errors import InputError, uninterrupted
from .layout import (STORE_FORMAT, coordinate_attrs, fills, provenance, store_model, utc_now, variable_attrs,
                     variables)

__all__ = ["StoreReplacedError", "check_store", "chunk_codecs", "create_store", "open_store", "read_attrs",
           "read_done", "record_submit", "store_kind", "write_tile", "write_whole_store"]

class StoreReplacedError(RuntimeError):
    """The store at a run's path is no longer the one the run created (its ``run_id`` changed)."""


def chunk_codecs() -> list:
    """The bytes-to-bytes codecs of every array: zstd, then a CRC-32C of the compressed chunk.

    CRC-32C (Castagnoli) detects every single-bit error and every burst of up to 32 bits in the
    stored chunk, and a truncated chunk (its last 4 bytes are no longer the checksum of the rest), so a
    damaged chunk fails to decode instead of reading as numbers (``bifurcation verify``).
    """
    from zarr.codecs import Crc32cCodec, ZstdCodec

    return [ZstdCodec(), Crc32cCodec()]


_WRITERS: OrderedDict = OrderedDict()   # (path, run_id) → {name: zarr.Array}, per process
_WRITERS_MAX = 4


@contextmanager
def _quiet():
    # zarr warns that consolidated metadata and string arrays are not in the v3 spec yet; both are
    # read back by the zarr and xarray versions we pin, and the warning would reach every user.
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*Consolidated metadata.*")
        warnings.filterwarnings("ignore", message=".*does not have a Zarr V3 specification.*")
        # the one-writer lock file (store.lock) lives in the store's directory
        warnings.filterwarnings("ignore", message=".*is not recognized as a component of a Zarr hierarchy.*")
        yield


def _inspect(path) -> tuple[str, dict | None]:
    """``(store_kind, attrs)`` from one read of the attributes (attrs None unless a store)."""
    path = Path(path)
    if not path.exists() or _only_lock(path):
        return "missing", None
    try:
        attrs = read_attrs(path)
    except Exception:
        return "other", None
    return ("store", attrs) if attrs.get("bifurcation_store") == STORE_FORMAT else ("other", None)


def _only_lock(path: Path) -> bool:
    """A directory that holds nothing but the lock (a submit that died before creating the store)."""
    from .lock import LOCK_NAME

    try:
        names = [p.name for p in path.iterdir()] if path.is_dir() else []
    except OSError:
        return False
    return bool(names) and all(name.startswith(LOCK_NAME) for name in names)


def only_lock_error(path, argument: str = "--store") -> InputError:
    """The error for a directory that holds only a submit's lock: that submit was killed before it made the
    store (said 'no such store' by status, 'neither a Zarr store nor a directory of stores' by report)."""
    from .lock import _read, lock_path

    found = _read(lock_path(path))
    if found is not None and found.alive() is not False:
        return InputError(argument, str(path), f"is being created by {found.describe()} (it holds only its lock "
                          "yet)", "wait a moment and run this command again")
    return InputError(argument, str(path), "holds only the lock of a submit that stopped before it made the store "
                      "(no point was computed)", "submit the workflow again with this --store: the lock of a run "
                      "that is gone is taken over")


def store_kind(path) -> str:
    """``"missing"``, ``"store"`` (a bifurcation store) or ``"other"`` (anything else at ``path``)."""
    return _inspect(path)[0]


def read_attrs(path) -> dict:
    """The group attributes of the store at ``path``."""
    import zarr

    with _quiet():
        return dict(zarr.open_group(str(path), mode="r").attrs)


def check_store(path, workflow=None, *, argument: str = "--store", record: bool = True) -> dict:
    """Attributes of the store at ``path``; ``InputError`` if it is not one, or holds another study, or (with
    ``record``; ``verify`` reports it as damage instead) its record of its workflow is damaged."""
    kind, attrs = _inspect(path)
    if kind == "missing" and _only_lock(Path(path)):
        raise only_lock_error(path, argument)
    if kind == "missing":
        raise InputError(argument, str(path), "no such store",
                         "give the path of a store written by `bifurcation submit`")
    if kind == "other":
        if _is_branch_store(path):
            raise InputError(argument, str(path),
                             "is a branch store of an older `bifurcation continue` (written before continuation "
                             "stores were bifurcation stores)",
                             "run `bifurcation continue WORKFLOW --out DIR` again to rewrite it as a store that "
                             "status, query, verify and report read, or read it with "
                             "xarray.open_zarr(PATH, consolidated=False)")
        root = Path(path) / "zarr.json"
        if root.is_file() and (Path(path) / "done").is_dir():   # a store's layout whose root metadata is cut
            try:
                json.loads(root.read_bytes())
            except (OSError, ValueError):
                raise InputError(argument, str(path), "has a root zarr.json that is not valid JSON (cut while it "
                                 "was written, or damaged): the store's description and metadata are lost",
                                 "restore it from a copy, or remove the directory and submit its workflow again") from None
        raise InputError(argument, str(path), "is not a bifurcation store (or of another format)",
                         "give the path of a store written by `bifurcation submit`, or another path")
    _check_axes(path, attrs, argument)
    if record:
        from .integrity import workflow_record_fix, workflow_record_problem

        problem = workflow_record_problem(attrs)
        if problem:
            raise InputError(argument, str(path), problem, workflow_record_fix(path))
    if workflow is not None and attrs.get("workflow_fingerprint") != workflow.fingerprint:
        made, now = int(attrs.get("engine_revision", 0)), workflow.spec.revision
        if made != now and attrs.get("model") == workflow.spec.name:
            raise InputError(argument, str(path),
                             f"was begun by revision {made} of the {workflow.spec.name} engine, which is now "
                             f"revision {now}: its runs and new ones could differ (in their last bits or in how a run ends)",
                             "pass --new-store to compute it again with this engine, or finish it with the "
                             "version of bifurcation that began it")
        raise InputError(argument, str(path),
                         f"holds another workflow (study {attrs.get('title')!r}, fingerprint "
                         f"{str(attrs.get('workflow_fingerprint'))[:12]} ≠ {workflow.fingerprint[:12]})",
                         "pass --new-store to replace it, or choose another --store path")
    return attrs


def _check_axes(path, attrs: dict, argument: str) -> None:
    """The store has a coordinate array for every axis of its model: a store written by an older version,
    before an axis was added (the chain's sigma, v_threshold), made query and report fail with KeyError
    'sigma' (issue 21 walk)."""
    from ..models import get_model
    from .layout import store_model

    try:
        model = get_model(store_model(attrs))
    except InputError as exc:   # status, verify, export and submit went on with it; query said "model='nope'"
        from ..models import model_names

        raise InputError(argument, str(path), f"holds a store of the model {store_model(attrs)!r}, which this "
                         f"version of bifurcation does not know (written by version "
                         f"{attrs.get('version_bifurcation', '?')})",
                         f"read it with the version that wrote it; this one knows {', '.join(model_names())}") from exc
    missing = [a.name for a in model.axes if not (Path(path) / a.name / "zarr.json").is_file()]
    if missing:
        raise InputError(argument, str(path), f"was written by an older version of bifurcation "
                         f"({attrs.get('version_bifurcation', '?')}, {attrs.get('created_utc', '?')}): it has no axis "
                         f"{', '.join(missing)} of the model {model.name!r}",
                         "submit its workflow again into a new store (--store NEW.zarr, or --new-store); "
                         "xarray.open_zarr(PATH, consolidated=False) still reads it as it is")


def _is_branch_store(path) -> bool:
    """Whether ``path`` is a ``branches.zarr`` of an older ``bifurcation continue`` (its own Zarr layout, before
    it wrote through ``write_whole_store``): refused with what to do, and replaced by a new one."""
    try:
        attrs = read_attrs(path)
    except Exception:
        return False
    # that layout is told apart by its attributes alone (no store of today writes branch_labels, and
    # only a store of today has bifurcation_store): the store names no model
    return "branch_labels" in attrs and "bifurcation_store" not in attrs


def create_store(path, workflow, *, command: str | None = None, overwrite: bool = False) -> dict:
    """Write the empty store of ``workflow`` (coordinates, metadata, attributes); returns its attrs.

    No data chunk is written: every point reads as not computed. With ``overwrite`` an existing
    bifurcation store at ``path`` is deleted first (anything else at ``path`` is refused).
    """
    path = Path(path)
    kind = store_kind(path)
    if kind == "other":
        raise InputError("--store", str(path), "exists and is not a bifurcation store",
                         "choose another --store path (only a bifurcation store is ever replaced)")
    if kind == "store" and not overwrite:
        raise InputError("--store", str(path), "already exists", "pass --new-store to replace it")
    if kind == "store":
        _clear(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    attrs = provenance(workflow, command)
    try:
        _create(path, workflow.spec, workflow.laws, workflow.grid, workflow.tiles, attrs)
        if workflow.spec.catalog_outputs:   # the ragged per-event arrays (store.catalog), then one consolidation
            import zarr

            from .catalog import create_catalog

            create_catalog(path, workflow)
            with _quiet():
                zarr.consolidate_metadata(str(path))
    except OSError:   # disk full, quota: leave no half-made store behind (the lock stays with its holder)
        _clear(path)
        raise
    return attrs


def _create(path: Path, model, labels, grid, tiles, attrs: dict) -> None:
    """Write the metadata of an empty store of ``model`` (labels × ``grid``, one chunk per tile)."""
    import dask.array as da
    import xarray as xr

    shape = (len(labels), *(len(values) for _, values in grid))
    chunks, dims = (1, *tiles), model.dims
    data_vars, encoding = {}, {}
    fill = fills(model)
    for name, dtype in variables(model).items():
        # one lazy dask chunk: nothing is computed (compute=False), only the metadata is written
        data_vars[name] = (dims, da.full(shape, fill[name], dtype=dtype, chunks=shape),
                           variable_attrs(name, model))
        encoding[name] = {"chunks": chunks, "compressors": chunk_codecs()}
    coords_attrs = coordinate_attrs(model)
    label = model.labels.name
    coords = {label: (label, np.array(labels, dtype=object), coords_attrs[label])}
    for axis, values in grid:
        coords[axis] = (axis, np.array(values, dtype=model.axis(axis).dtype), coords_attrs[axis])
    for name in coords:   # the coordinates carry a checksum too, and are written even when they equal the
        # fill value (a chain's periodic = [0]): a coordinate chunk missing is damage (integrity)
        encoding[name] = {"compressors": chunk_codecs(), "write_empty_chunks": True}
    ds = xr.Dataset(data_vars, coords=coords, attrs=attrs)
    # "a" into a directory that holds only the writer's lock (checked above: no store, nothing else)
    mode = "a" if path.exists() else "w-"
    with _quiet():
        ds.to_zarr(str(path), mode=mode, compute=False, encoding=encoding, zarr_format=3, consolidated=True)


def write_whole_store(path, model, labels, grid, values: dict, attrs: dict, *, tiles=None,
                      argument: str = "--out") -> dict:
    """Write a complete store at once: for a model whose command computes all of it before writing
    (``Model.written_by``: rate-state's branches of cycles). The layout, checksums, ``done`` mask and
    consolidated metadata are a submit's (``status``, ``query``, ``verify`` and ``report`` read it like any
    store); ``values`` holds every data variable over (labels, *grid), ``done`` included.

    Built beside ``path`` (``<path>.partial``) and renamed into place: a killed run leaves the previous
    store whole, never half a store. Only a bifurcation store (or an older branch store) is replaced.
    """
    import zarr

    path = Path(path)
    if store_kind(path) == "other" and not _is_branch_store(path):
        raise InputError(argument, str(path), "exists and is not a bifurcation store",
                         "choose another path (only a bifurcation store is ever replaced)")
    shape = (len(labels), *(len(points) for _, points in grid))
    tiles = tuple(tiles or shape[1:])
    attrs = {**attrs, "tiles": list(tiles)}
    partial, old = path.with_name(path.name + ".partial"), path.with_name(path.name + ".old")
    # one writer at a time (the lock file in the directory beside the store: the store itself is renamed):
    # two runs into one --out removed each other's .partial and failed with zarr's ValueError tracebacks
    from .lock import StoreLock

    with StoreLock(path.parent, argument=argument).acquire(command=f"write {path.name}"):
        if old.is_dir() and not path.exists():   # a run killed between the two renames below: the store was that
            old.rename(path)
        for leftover in (partial, old):
            shutil.rmtree(leftover, ignore_errors=True)
        try:
            _create(partial, model, labels, grid, tiles, attrs)
            with _quiet():
                group = zarr.open_group(str(partial), mode="r+", use_consolidated=False)
                for name, dtype in variables(model).items():   # in write order: "done" last
                    data = np.asarray(values[name], dtype=dtype)
                    if data.shape != shape:
                        raise ValueError(f"write_whole_store: {name} has shape {data.shape}, not {shape}")
                    # every chunk written, also one that equals the fill value: a missing chunk is damage
                    group[name].with_config({"write_empty_chunks": True})[...] = data
        except BaseException:   # Ctrl-C mid-write: no half store left beside it (a kill -9's: the next run's)
            shutil.rmtree(partial, ignore_errors=True)
            raise
        if path.exists():
            path.rename(old)
        partial.rename(path)
        shutil.rmtree(old, ignore_errors=True)
    return attrs


def _clear(path: Path) -> None:
    """Delete the store at ``path`` but keep its directory and the lock its writer holds."""
    from .lock import LOCK_NAME

    for entry in path.iterdir():
        if entry.name.startswith(LOCK_NAME):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry)
        else:
            entry.unlink()


def open_store(path, **kwargs):
    """The store at ``path`` as an ``xarray.Dataset`` (lazy; ``kwargs`` go to ``xarray.open_zarr``).

    Points never computed hold NaN / 0 with ``status == 0`` (not computed) and ``done == False``.
    The dataset carries CF attributes and only netCDF types (``export.netcdf_ready``): ``ds.to_netcdf()``
    works as it is; the submit history is ``history`` (text) and ``submits`` (JSON text).
    """
    import xarray as xr

    from .export import netcdf_ready

    check_store(path, None, argument="store")
    kwargs.setdefault("chunks", None)
    with _quiet():
        return netcdf_ready(xr.open_zarr(str(path), zarr_format=3, consolidated=True, **kwargs))


def read_done(path) -> np.ndarray:
    """The (label, *axes) done mask of the store at ``path``."""
    import zarr

    with _quiet():
        return np.asarray(zarr.open_group(str(path), mode="r", use_consolidated=False)["done"][...], dtype=bool)


def _check_run(path: str, run_id: str) -> None:
    """Refuse to write unless the store at ``path`` is still the one ``run_id`` created.

    Read from ``zarr.json`` at every tile write, never cached: a store replaced under the same path
    (``--new-store`` of another run, a deleted and recreated directory) must not receive this run's
    tiles, and cached array handles would write into the new store's chunk files.
    """
    try:
        found = json.loads((Path(path) / "zarr.json").read_bytes())["attributes"].get("run_id")
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        found = None
    if found != run_id:
        raise StoreReplacedError(f"store {path} is not the one this run created (run_id {run_id[:12]} "
                                 f"≠ {str(found)[:12]}): tile not written")


def _arrays(path: str, run_id: str) -> dict:
    import zarr

    _check_run(path, run_id)
    key = (path, run_id)
    arrays = _WRITERS.get(key)
    if arrays is None:
        with _quiet():
            group = zarr.open_group(path, mode="r+", use_consolidated=False)
            # every chunk is written, also one that equals the fill value (all-NaN creep_time): a
            # missing chunk of a done tile then always means damage (integrity.verify)
            arrays = {name: group[name].with_config({"write_empty_chunks": True})
                      for name in variables(store_model(group.attrs))}
        _WRITERS[key] = arrays
        while len(_WRITERS) > _WRITERS_MAX:
            _WRITERS.popitem(last=False)
    return arrays


def write_tile(path, tile, values: dict, run_id: str) -> None:
    """Write one computed tile into its chunk: the data variables first, ``done`` last.

    For a partly done tile (``tile.todo``) the points already done are read back and kept, so the
    whole chunk is rewritten by this one writer without losing them. A SIGTERM or SIGHUP that arrives
    meanwhile stops the command once the tile is written whole (``errors.uninterrupted``).
    """
    with uninterrupted():
        _write_tile(path, tile, values, run_id)


def _write_tile(path, tile, values: dict, run_id: str) -> None:
    arrays = _arrays(str(path), run_id)
    region = tile.region
    catalogs = [k for k in values if k not in arrays]
    if catalogs:   # per-event outputs: each run's catalog chunks before the tile's per-run outputs
        from ..models import get_model
        from .catalog import write_catalogs

        write_catalogs(path, arrays["done"].shape, tile, values, get_model(tile.model), run_id)
    if tile.todo is not None:
        keep = ~np.asarray(tile.todo, dtype=bool)
        values = {name: np.where(keep, arrays[name][region][0], values[name]) for name in arrays}
    with _quiet():
        for name, array in arrays.items():   # in write order: "done" last
            if name == "done":
                _check_run(str(path), run_id)   # again just before done: nothing claims a foreign tile
            array[region] = np.asarray(values[name], dtype=array.dtype)[None]
    if catalogs:   # done is written: the runs' checkpoints are no longer needed
        from .catalog import drop_checkpoints

        drop_checkpoints(path, arrays["done"].shape, tile, values["done"])


def record_submit(path, entry: dict) -> None:
    """Append one submit's summary to the store's ``submits`` attribute and consolidate the metadata."""
    import zarr

    with _quiet():
        group = zarr.open_group(str(path), mode="r+", use_consolidated=False)
        history = list(group.attrs.get("submits", []))
        history.append({"utc": utc_now(), **entry})
        group.attrs["submits"] = history
        zarr.consolidate_metadata(str(path))
