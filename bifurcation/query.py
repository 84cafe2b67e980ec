"""Query a store by label: one value or list per axis of the store's model → one record per point,
as a table, CSV or JSON.

Every requested value must be a label of the store (``bifurcation.store.labels``: within a relative
1e-12; a law by its parsed expression), else a one-line error names the axis, the value and the
nearest labels; with ``nearest=True`` the nearest label is taken and a note says so.
"""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np

from .engine.result import status_names
from .errors import InputError
from .store.labels import match_label, match_value
from .store.layout import store_model, variables

__all__ = ["COLUMNS", "FORMATS", "columns", "format_records", "query"]

FORMATS = ("table", "csv", "json")


def columns(model=None) -> tuple[str, ...]:
    """Keys of a record, in order: the label, the axes (fastest first), status, the float outputs,
    the other outputs."""
    from .models import get_model

    spec = get_model(model)
    rest = [o.name for o in spec.outputs if o.name != "status" and o.name not in spec.float_outputs]
    return (spec.labels.name, *(a.name for a in reversed(spec.axes)), "status", *spec.float_outputs, *rest)


#: The single block's record keys.
COLUMNS = columns()


def _as_list(value) -> list | None:
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or np.ndim(value) == 0:
        return [value]
    return list(value)


def query(store, *, law=None, computed_only: bool = False, nearest: bool = False, notes=None,
          **axes) -> list[dict]:
    """Records of the points selected in ``store`` (a path or a Dataset from ``open_store``).

    ``law`` and one keyword per axis of the store's model (``nu=``, ``nu_f=`` for the single block):
    a value or a list of values (None: all). Each record has the label, the axes, ``status`` (a
    string such as ``"stick-slip"``; ``"not-computed"`` where the store has no value yet) and the
    model's outputs (None for NaN), in the store's order. ``nearest`` takes the nearest label where a
    value is not one; each such match appends a line to the list ``notes`` (if given).
    """
    from .models import get_model
    from .store import open_store

    ds = store if hasattr(store, "data_vars") else open_store(store)
    model = get_model(store_model(ds.attrs))
    label_dim = model.labels.name
    unknown = [k for k in axes if k not in model.dims[1:]]
    if unknown:
        raise InputError(unknown[0], axes[unknown[0]], f"is not an axis of model {model.name!r}",
                         f"use the axes {', '.join(model.dims[1:])}")
    indexers = {}
    wanted = _as_list(law)
    if wanted is not None:
        labels = ds[label_dim].values
        indexers[label_dim] = sorted({match_label(label_dim, labels, x, model.labels.identity, argument="law").index
                                      for x in wanted})
    for axis in model.axes:
        values = _as_list(axes.get(axis.name))
        if values is None:
            continue
        labels = np.asarray(ds[axis.name].values, dtype=float)
        chosen = set()
        for value in values:   # one value at a time: an error shows that value
            m = match_value(axis.name, labels, value, nearest=nearest, scale=axis.scale)
            chosen.add(m.index)
            if not m.exact and notes is not None:
                notes.append(m.note())
        indexers[axis.name] = sorted(chosen)
    sub = ds.isel(indexers)
    names = variables(model)
    values = {name: np.asarray(sub[name].values) for name in names}
    statuses = status_names(values["status"])
    coords = [[str(x) for x in sub[label_dim].values]]
    coords += [[v.item() for v in np.asarray(sub[a.name].values)] for a in model.axes]
    floats = model.float_outputs
    others = [n for n in names if n not in floats and n not in ("status", "done")]
    records = []
    for index in np.ndindex(values["status"].shape):
        if computed_only and not values["done"][index]:
            continue
        record = {label_dim: coords[0][index[0]]}
        for k in range(len(model.axes) - 1, -1, -1):
            record[model.axes[k].name] = coords[k + 1][index[k + 1]]
        record["status"] = statuses[index]
        for name in floats:
            x = float(values[name][index])
            record[name] = x if math.isfinite(x) else None
        for name in others:
            record[name] = values[name][index].item()
        records.append(record)
    return records


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def format_records(records: list[dict], fmt: str = "table", keys=None) -> str:
    """``records`` as an aligned ``table``, ``csv`` (header, empty cell = NaN) or strict ``json``.

    ``keys``: the columns (default: those of the first record, else the single block's).
    """
    if fmt not in FORMATS:
        raise InputError("--format", fmt, "is not a format", f"use one of {', '.join(FORMATS)}")
    if fmt == "json":
        return json.dumps(records, indent=2, allow_nan=False)
    keys = tuple(keys) if keys is not None else (tuple(records[0]) if records else COLUMNS)
    rows = [[_cell(r.get(c)) for c in keys] for r in records]
    if fmt == "csv":
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(keys)
        writer.writerows(rows)
        return buffer.getvalue().rstrip("\n")
    widths = [max(len(c), *(len(row[k]) for row in rows)) if rows else len(c) for k, c in enumerate(keys)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(keys, widths)).rstrip()]
    lines += ["  ".join((cell or "-").ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    return "\n".join(lines)
