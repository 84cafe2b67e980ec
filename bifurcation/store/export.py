"""Export a store to netCDF (CF conventions) or CSV; both read back to the same numbers.

The Zarr store stays the study's working copy (resumable, checked chunk by chunk); an export is the
file to hand on. Nothing is exported from a damaged store: every chunk is checked first
(``store.integrity``) and a damaged one stops the export in one line naming it and the repair command.
The file is written beside its target and renamed into place, so a failed export leaves no half file.

netCDF: the dataset of ``open_store`` with CF attributes (``Conventions``, ``history`` with one line per
submit), its attributes made netCDF types (lists of records as JSON text), written chunk by chunk by
xarray (netCDF4 engine); ``xarray.open_dataset`` reads back every variable with its dtype (``done``
is stored as int8 with a ``dtype = bool`` attribute, which xarray decodes). CSV: one row per point, the
columns of ``bifurcation query``, floats as their shortest exact text (``repr``), an empty cell for NaN.
"""

from __future__ import annotations

import glob
import json
import os
import re
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["CONVENTIONS", "FORMATS", "cf_dataset", "cf_problems", "export", "netcdf_ready", "read_csv"]

CONVENTIONS = "CF-1.10"
FORMATS = ("netcdf", "csv")
_SUFFIX = {".nc": "netcdf", ".nc4": "netcdf", ".csv": "csv"}
_FLAG_WORD = re.compile(r"^[A-Za-z0-9_.+@-]+$")


def _netcdf_attr(value):
    """An attribute value netCDF can hold: str, number, or a 1-D array of numbers; else JSON text."""
    if isinstance(value, (str, int, float, np.integer, np.floating)) and not isinstance(value, bool):
        return value
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (list, tuple)) and value and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return np.asarray(value)
    return json.dumps(value, default=str)


def _history(attrs: dict) -> str:
    lines = [f"{attrs.get('created_utc', '')} {attrs.get('command', '')}: store created".strip()]
    for entry in attrs.get("submits", []) or []:
        if isinstance(entry, dict):
            lines.append(f"{entry.get('utc', '')} {entry.get('command', '')}: {entry.get('computed', 0)} points "
                         f"computed, {entry.get('failed', 0)} failed ({entry.get('cluster', '')})".strip())
    return "\n".join(lines)


def netcdf_ready(ds):
    """``ds`` (a store's dataset) with CF global attributes (``Conventions``, ``history`` with one line
    per submit), string coordinates as fixed-width ``str`` and every attribute of a netCDF type (lists of
    records as JSON text), so that ``ds.to_netcdf()`` works as it is. ``open_store`` returns this view."""
    attrs = dict(ds.attrs)
    out = {k: _netcdf_attr(v) for k, v in attrs.items()}
    out["Conventions"] = CONVENTIONS
    out["history"] = _history(attrs)
    ds = ds.assign_attrs(out)
    for name, coord in ds.coords.items():
        if coord.dtype.kind not in "biufcmM":   # zarr v3 strings come back as numpy StringDType/object
            labels = np.array([str(v) for v in np.asarray(coord.values).ravel()], dtype=str).reshape(coord.shape)
            ds = ds.assign_coords({name: (coord.dims, labels, coord.attrs)})
    for var in ds.variables.values():
        var.attrs = {k: _netcdf_attr(v) for k, v in var.attrs.items()}
    return ds


def cf_dataset(store):
    """The store at ``store`` as an ``xarray.Dataset`` ready for netCDF (``netcdf_ready``); lazy (dask)."""
    from .zarr_store import open_store

    return open_store(store, chunks={})


def cf_problems(ds) -> list[str]:
    """What in ``ds`` breaks the CF conventions this package claims (empty when none): the
    ``Conventions`` attribute; a ``long_name`` or ``standard_name`` on every variable; ``units`` on every
    numeric variable that is not a flag variable; ``flag_values`` and ``flag_meanings`` of equal length with
    CF words; monotonic 1-D coordinates; attributes of netCDF types only."""
    problems = []
    if not str(ds.attrs.get("Conventions", "")).startswith("CF-"):
        problems.append("global: no Conventions attribute")
    for name, var in ds.variables.items():
        attrs = var.attrs
        if not (attrs.get("long_name") or attrs.get("standard_name")):
            problems.append(f"{name}: no long_name or standard_name")
        flags = "flag_values" in attrs or "flag_meanings" in attrs
        if var.dtype.kind in "iuf" and not flags and "units" not in attrs and var.dtype != bool \
                and attrs.get("dtype") != "bool":
            problems.append(f"{name}: numeric without units")
        if flags:
            values = np.atleast_1d(attrs.get("flag_values", []))
            words = str(attrs.get("flag_meanings", "")).split()
            if len(values) != len(words):
                problems.append(f"{name}: {len(values)} flag_values but {len(words)} flag_meanings")
            problems += [f"{name}: flag meaning {w!r} is not a CF word" for w in words if not _FLAG_WORD.match(w)]
        problems += [f"{name}: attribute {key} ({type(value).__name__}) is not a netCDF type"
                     for key, value in attrs.items() if not _is_netcdf_attr(value)]
    for name in ds.dims:
        if name in ds.coords and ds[name].dtype.kind in "iuf":
            diffs = np.diff(np.asarray(ds[name].values, dtype=float))
            if not (np.all(diffs > 0) or np.all(diffs < 0)):
                problems.append(f"{name}: coordinate not strictly monotonic")
    problems += [f"global: attribute {key} ({type(value).__name__}) is not a netCDF type"
                 for key, value in ds.attrs.items() if not _is_netcdf_attr(value)]
    return problems


def _is_netcdf_attr(value) -> bool:
    if isinstance(value, (str, np.ndarray, np.number)) or (isinstance(value, (int, float)) and not isinstance(value, bool)):
        return not isinstance(value, np.ndarray) or value.dtype.kind in "iufSU"
    if isinstance(value, (list, tuple)):
        return all(isinstance(v, (int, float, np.number)) and not isinstance(v, bool) for v in value) or \
            all(isinstance(v, str) for v in value)
    return False


def _format(out: Path, fmt: str | None) -> str:
    implied = _SUFFIX.get(out.suffix.lower())
    if fmt is None:
        fmt = implied
        if fmt is None:
            raise InputError("--out", str(out), "has no known file type", "end it in .nc or .csv, or pass --format")
    if fmt not in FORMATS:
        raise InputError("--format", fmt, "is not an export format", f"use one of {', '.join(FORMATS)}")
    if implied is not None and implied != fmt:   # x.nc holding CSV misleads every reader after
        raise InputError("--format", fmt, f"contradicts the suffix of --out {out.name} ({implied})",
                         f"give --out a name ending in .{'csv' if fmt == 'csv' else 'nc'}, or leave --format out")
    return fmt


def _remove_dead_parts(out: Path) -> None:
    """The ``.NAME.part-PID`` files of exports to ``out`` that were killed (kill -9: no ``finally`` ran) and whose
    process is gone: each kill left one, as large as the export, that nothing removed (walk 6)."""
    import psutil

    for part in out.parent.glob(f".{glob.escape(out.name)}.part-*"):
        pid = part.name.rpartition("-")[2]
        if pid.isdigit() and not psutil.pid_exists(int(pid)):
            part.unlink(missing_ok=True)


def export(store, out, fmt: str | None = None, *, force: bool = False, partial: bool = False) -> dict:
    """Write the store at ``store`` to ``out`` as netCDF or CSV (``fmt``, or from the suffix); returns
    ``{"out", "format", "points", "computed"}``. ``InputError`` (one line) for a bad path, a damaged store,
    an existing ``out`` (unless ``force``) or a store that a submit is still writing (unless ``partial``);
    points not computed are exported empty (NaN, status not-computed)."""
    from .integrity import StoreDamagedError, scan
    from .lock import holder
    from .zarr_store import check_store, read_done

    path, out = Path(store), Path(out)
    if out.is_dir():
        raise InputError("--out", str(out), "is a directory", "give a file path ending in .nc or .csv")
    fmt = _format(out, fmt)
    check_store(path, None)
    if fmt == "csv":
        from .catalog import has_catalog

        if has_catalog(path):   # one row per point cannot hold them, and dropping them would be silent
            raise InputError("--out", str(out), "is a CSV file, and this store's runs have per-event catalogs "
                             "(a chain store), which one row per run cannot hold",
                             "export to .nc (catalogs as CF ragged arrays), or print one run's events with "
                             "`bifurcation query --store S ... --catalog --format csv`")
    if not out.parent.is_dir():
        raise InputError("--out", str(out), "is in a directory that does not exist", "create it first")
    if (out.exists() or out.is_symlink()) and not force:
        raise InputError("--out", str(out), "exists", "pass --force to replace it, or choose another file")
    writer = holder(path)
    if writer is not None and not partial:
        raise InputError("--store", str(path), f"is still being written by {writer.describe()}: an export now "
                         "would hold only the points finished so far",
                         "wait for it to end (bifurcation status), or pass --partial to export what is done")
    damage, _, _ = scan(path)
    if damage:
        raise StoreDamagedError(path, damage[0])
    tmp = out.with_name(f".{out.name}.part-{os.getpid()}")
    _remove_dead_parts(out)
    try:
        if fmt == "netcdf":
            ds = cf_dataset(path)
            from .catalog import catalog_dataset, has_catalog

            if has_catalog(path):   # per-event catalogs as CF contiguous ragged arrays (store.catalog)
                ds = ds.merge(catalog_dataset(path), combine_attrs="override")
            ds.to_netcdf(tmp, engine="netcdf4")
            points = int(np.prod([ds.sizes[d] for d in ds["done"].dims]))
        else:
            from .query import iter_records, write_records

            with open(tmp, "w", encoding="utf-8", newline="") as fh:
                points = write_records(iter_records(path), "csv", fh)
        os.replace(tmp, out)
    except OSError as exc:
        raise InputError("--out", str(out), f"cannot be written ({exc.strerror or exc})",
                         "choose a writable path with free space") from None
    finally:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:   # a read-only file system says so even of a file that is not there: it hid the line above
            pass          # (exit 1 naming the temporary file, walk 6)
    from .catalog import has_catalog

    written = {"out": str(out), "format": fmt, "points": points, "computed": int(read_done(path).sum())}
    if fmt == "csv" and has_catalog(path):   # one row per run: the per-event catalogs need netCDF
        written["catalogs"] = "not in CSV"
    return written


def read_csv(path) -> list[dict]:
    """The records of an exported CSV: numbers as float (exact), steps as int, empty cells as None."""
    import csv

    out = []
    with open(path, encoding="utf-8", newline="") as fh:
        for row in csv.DictReader(fh):
            record = {}
            for key, text in row.items():
                if text == "":
                    record[key] = None
                elif key in ("law", "status"):
                    record[key] = text
                elif key == "steps":
                    record[key] = int(text)
                else:
                    record[key] = float(text)
            out.append(record)
    return out
