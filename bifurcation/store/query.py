"""Query a store by label: one value or list per axis of the store's model → one record per point,
as a table, CSV or JSON, streamed (memory independent of the store's size).

Every requested value must be a label of the store (``bifurcation.store.labels``: within a relative
1e-12; a law by its parsed expression), else a one-line error names the axis, the value and the
nearest labels; with ``nearest=True`` the nearest label is taken and a note says so.
"""

from __future__ import annotations

import csv
import io
import json
import math
from json.encoder import encode_basestring_ascii
from typing import Iterable, Iterator, TextIO

import numpy as np

from ..outcome import Status
from ..errors import InputError
from .labels import match_label, match_value
from .layout import store_model

__all__ = ["COLUMNS", "FORMATS", "RecordStream", "columns", "format_records", "iter_records", "query",
           "write_records"]

FORMATS = ("table", "csv", "json")
_STATUS_NAMES = {int(s): str(s) for s in Status}


def columns(model=None) -> tuple[str, ...]:
    """Keys of a record, in order: the label, the axes (in the model's order, that of the store's
    dimensions and of the workflow), status, the float outputs, the other outputs."""
    from ..models import get_model

    spec = get_model(model)
    rest = [o.name for o in spec.outputs
            if o.name != "status" and o.name not in spec.float_outputs and not o.per_event]
    return (spec.labels.name, *(a.name for a in spec.axes), "status", *spec.float_outputs, *rest)


#: The single block's record keys.
COLUMNS = columns()


def _as_list(value) -> list | None:
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or np.ndim(value) == 0:
        return [value]
    return list(value)


def _within_bounds(axis, value, nearest: bool) -> None:
    """With ``nearest``, a value outside the model's bounds of ``axis`` is refused: ``--nearest --nu -1`` (or
    1e300) took the store's nearest ν and printed its rows as if asked for (issue 21 walk)."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return   # (match_value names it)
    low, high = axis.bounds
    if nearest and math.isfinite(x) and not low <= x <= high:
        raise InputError(axis.name, value, f"is outside [{low:g}, {high:g}], the model's bounds of {axis.symbol}: "
                         "no label is near it", "give a value within them (--nearest takes the label nearest it)")


def _selection(model, labels: dict, law, axes: dict, nearest: bool, notes) -> dict[str, list[int]]:
    """Selected indices per dimension (all when not given), matched by ``store.labels``."""
    unknown = [k for k in axes if k not in model.dims[1:]]
    if unknown:
        raise InputError(unknown[0], axes[unknown[0]], f"is not an axis of model {model.name!r}",
                         f"use the axes {', '.join(model.dims[1:])}")
    label_dim = model.labels.name
    selected = {label_dim: list(range(len(labels[label_dim])))}
    wanted = _as_list(law)
    if wanted is not None:
        selected[label_dim] = sorted({match_label(label_dim, labels[label_dim], x, model.labels.identity,
                                                  argument="law").index for x in wanted})
    for axis in model.axes:
        values = _as_list(axes.get(axis.name))
        axis_labels = np.asarray(labels[axis.name], dtype=float)
        if values is None:
            selected[axis.name] = list(range(axis_labels.size))
            continue
        chosen = set()
        for value in values:   # one value at a time: an error shows that value
            value = axis.parse(value)
            _within_bounds(axis, value, nearest)
            m = match_value(axis.name, axis_labels, value, nearest=nearest, scale=axis.scale,
                            show=axis.shown)
            chosen.add(m.index)
            if not m.exact and notes is not None:
                notes.append(m.note())
        selected[axis.name] = sorted(chosen)
    return selected


class _Records:
    """How one point becomes a record for ``model`` (keys in ``columns`` order)."""

    def __init__(self, model) -> None:
        self.label = model.labels.name
        self.axes = [a.name for a in model.axes]
        self.shown = {a.name: a.shown for a in model.axes if a.names}   # words for choice axes
        self.floats = model.float_outputs
        self.others = [o.name for o in model.outputs if o.name != "status" and o.name not in self.floats]
        self.words = {o.name: o.shown for o in model.outputs if o.names}   # criticality: its word, not a code
        # a model may declare its own status codes (rate-state's RateStateStatus)
        self.status_names = {**_STATUS_NAMES, **{int(s): str(s) for s in model.statuses}}

    def make(self, label: str, coords: dict, status: int, values: dict) -> dict:
        record = {self.label: label}
        for name in self.axes:
            record[name] = self.shown[name](coords[name]) if name in self.shown else coords[name]
        record["status"] = self.status_names[status]
        for name in self.floats:
            x = values[name]
            record[name] = x if math.isfinite(x) else None
        for name in self.others:
            if name in values:   # a per-event output (a catalog) is no value of the point
                record[name] = self.words[name](values[name]) if name in self.words else values[name]
        return record


def query(store, *, law=None, computed_only: bool = False, nearest: bool = False, notes=None,
          **axes) -> list[dict]:
    """Records of the points selected in ``store`` (a path or a Dataset from ``open_store``).

    ``law`` and one keyword per axis of the store's model (``nu=``, ``nu_f=`` for the single block):
    a value or a list of values (None: all). Each record has the label, the axes, ``status`` (a
    string such as ``"stick-slip"``; ``"not-computed"`` where the store has no value yet) and the
    model's outputs (None for NaN), in the store's order. ``nearest`` takes the nearest label where a
    value is not one; each such match appends a line to the list ``notes`` (if given).
    ``iter_records`` yields the same records one at a time (memory independent of the store's size).
    """
    return list(iter_records(store, law=law, computed_only=computed_only, nearest=nearest, notes=notes,
                             **axes))


class RecordStream:
    """The records of a query, iterated one at a time; ``law_width`` is the longest label, ``keys``
    the record keys (the columns of the store's model)."""

    def __init__(self, records: Iterator[dict], law_width: int, keys=COLUMNS, status_width: int | None = None) -> None:
        self._records, self.law_width, self.keys = records, law_width, tuple(keys)
        #: the longest status name of the store's model ("unbounded-growth"), for a streamed table
        self.status_width = status_width

    def __iter__(self) -> Iterator[dict]:
        return self._records


def iter_records(store, *, law=None, computed_only: bool = False, nearest: bool = False, notes=None,
                 **axes) -> RecordStream:
    """The records of ``query``, streamed: read a chunk row at a time, every chunk checked.

    From a path, every selected chunk is checked (checksum, ``done`` against the data;
    ``store.integrity``) in this call, before any record is made, so a damaged store yields nothing:
    ``StoreDamagedError`` names the chunk and the repair command. A Dataset is read as it is.
    """
    axes = {k: v for k, v in axes.items() if v is not None}
    if hasattr(store, "data_vars"):
        from ..models import get_model

        model = get_model(store_model(store.attrs))
        labels = {name: np.asarray(store[name].values) for name in model.dims}
        labels[model.labels.name] = [str(x) for x in labels[model.labels.name]]
        selected = _selection(model, labels, law, axes, nearest, notes)
        width = max(map(len, labels[model.labels.name]))
        return RecordStream(_dataset_records(store, model, selected, computed_only), width, columns(model),
                            _status_width(model))
    plan = _Plan(store, law, axes, nearest, notes)
    plan.check()
    return RecordStream(plan.records(computed_only), max(map(len, plan.labels[plan.model.labels.name])),
                        columns(plan.model), _status_width(plan.model))


def _status_width(model) -> int:
    return max(len(name) for name in _Records(model).status_names.values())


class _Plan:
    """The chunks a selection touches, read one chunk row (label, blocks of all but the last axis)
    at a time."""

    def __init__(self, path, law, axes, nearest, notes) -> None:
        from ..models import get_model
        from . import check_store
        from .integrity import TileReader
        attrs = check_store(path, None, argument="store")
        self.model = model = get_model(store_model(attrs))
        # a tile being written (or left half written by a killed run) reads as not computed
        self.reader = reader = TileReader(path, in_progress=True)
        self.dims = tuple(reader.done.metadata.dimension_names or model.dims)
        labels = {name: self._coordinate(name) for name in self.dims}
        label_dim = model.labels.name
        labels[label_dim] = [str(x) for x in labels[label_dim]]
        self.labels = {name: (labels[name] if name == label_dim else [v.item() for v in labels[name]])
                       for name in self.dims}
        self.selected = _selection(model, self.labels, law, axes, nearest, notes)
        self.chunks = dict(zip(self.dims, reader.chunks))
        self.maker = _Records(model)

    def _coordinate(self, name: str) -> np.ndarray:
        from .integrity import Damage, StoreDamagedError

        array = self.reader.coordinates[name]
        for k in range(-(-array.shape[0] // array.chunks[0])):
            if not self.reader.exists(name, (k,)):
                raise StoreDamagedError(self.reader.path, Damage(self.reader.key(name, (k,)), (k,),
                                                                 "missing coordinate chunk"))
        return self.reader._decode(array, name, (0,), (slice(None),))

    def _blocks(self, name: str) -> list[tuple[int, list[int]]]:
        """``(chunk index, selected indices in it)`` along dimension ``name``."""
        size, out = self.chunks[name], {}
        for index in self.selected[name]:
            out.setdefault(index // size, []).append(index)
        return sorted(out.items())

    def rows(self):
        """Per chunk row: the chunk indices of all dimensions but the last, their selected indices,
        and the blocks of the last dimension."""
        import itertools

        leading = [self._blocks(name) for name in self.dims[:-1]]
        last = self._blocks(self.dims[-1])
        for combo in itertools.product(*leading):
            yield [c for c, _ in combo], [ix for _, ix in combo], last

    def check(self) -> None:
        """Every selected chunk, decoded and checked, before anything is printed."""
        for head, _, last in self.rows():
            for cn, _ in last:
                self.reader.read((*head, cn))

    def records(self, computed_only: bool) -> Iterator[dict]:
        import itertools

        dims, chunks, labels = self.dims, self.chunks, self.labels
        names = [n for n in self.reader.variables if n != "done"]
        for head, indices, last in self.rows():
            # one chunk row at a time: memory is one row of chunks, whatever the store's size
            row = {cn: self.reader.read((*head, cn)) for cn, _ in last}
            for point in itertools.product(*indices):
                local = tuple(i - c * chunks[d] for i, c, d in zip(point, head, dims))
                for cn, cols in last:
                    values = row[cn]
                    for j in cols:
                        at = (*local, j - cn * chunks[dims[-1]])
                        if computed_only and not values["done"][at]:
                            continue
                        coords = {d: labels[d][i] for d, i in zip(dims[1:], (*point[1:], j))}
                        yield self.maker.make(labels[dims[0]][point[0]], coords, int(values["status"][at]),
                                              {n: values[n][at].item() for n in names})


def _dataset_records(ds, model, selected, computed_only) -> Iterator[dict]:
    sub = ds.isel(selected)
    dims = model.dims
    maker = _Records(model)
    names = [o.name for o in model.outputs if not o.per_event]
    values = {name: np.asarray(sub[name].values) for name in (*names, "done")}
    coords = {d: np.asarray(sub[d].values) for d in dims}
    for index in np.ndindex(values["status"].shape):
        if computed_only and not values["done"][index]:
            continue
        at = {d: coords[d][i].item() for d, i in zip(dims[1:], index[1:])}
        yield maker.make(str(coords[dims[0]][index[0]]), at, int(values["status"][index]),
                         {n: values[n][index].item() for n in names})


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def format_records(records: list[dict], fmt: str = "table", keys=None) -> str:
    """``records`` as an aligned ``table``, ``csv`` (header, empty cell = NaN) or strict ``json``."""
    buffer = io.StringIO()
    write_records(records, fmt, buffer, keys=keys)
    return buffer.getvalue().rstrip("\n")


#: Table column widths: a float's repr is at most 24 characters (-1.7976931348623157e+308).
_FLOAT_WIDTH = 24


def write_records(records: Iterable[dict], fmt: str, out: TextIO, *, law_width: int | None = None,
                  keys=None) -> int:
    """Write ``records`` to ``out`` as they come (the table has fixed column widths); returns the count.

    ``keys``: the columns (default: ``records.keys`` of a ``RecordStream``, else those of the first
    record, else the single block's). The JSON is the text of ``json.dumps(list(records), indent=2)``,
    written one record at a time.
    """
    if fmt not in FORMATS:
        raise InputError("--format", fmt, "is not a format", f"use one of {', '.join(FORMATS)}")
    if keys is None:
        keys = getattr(records, "keys", None)
    if keys is None:
        records = list(records)
        keys = tuple(records[0]) if records else COLUMNS
    n = 0
    if fmt == "json":
        # json.dumps with indent takes its pure-Python path (slow); a record is flat, so its scalars are
        # written as json writes them, in the layout of json.dumps(records, indent=2)
        names = {}
        for record in records:
            lines = []
            for key, value in record.items():
                if key not in names:
                    names[key] = f'    {json.dumps(key)}: '
                lines.append(names[key] + _json_scalar(value))
            out.write(("[\n  {\n" if n == 0 else ",\n  {\n") + ",\n".join(lines) + "\n  }")
            n += 1
        out.write("\n]\n" if n else "[]\n")
        return n
    if fmt == "csv":
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(keys)
        for record in records:   # csv writes floats with repr (exact) and None as an empty cell
            writer.writerow([record.get(c) for c in keys])
            n += 1
        return n
    status_width = getattr(records, "status_width", None)
    if law_width is None:
        records = list(records)
        law_width = max((len(str(r.get(keys[0], ""))) for r in records), default=0)
    widths = [max(len(c), _width(c, law_width, k, status_width)) for k, c in enumerate(keys)]
    out.write("  ".join(c.ljust(w) for c, w in zip(keys, widths)).rstrip() + "\n")
    for record in records:
        cells = [_cell(record.get(c)) or "-" for c in keys]
        out.write("  ".join(cell.ljust(w) for cell, w in zip(cells, widths)).rstrip() + "\n")
        n += 1
    return n


def _json_scalar(value) -> str:
    """``value`` (str, float, int, bool or None) exactly as ``json.dumps`` writes it (strict: no NaN)."""
    if value is None:
        return "null"
    if isinstance(value, str):
        return encode_basestring_ascii(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{value!r} is not JSON")
        return float.__repr__(value)
    return int.__repr__(value)


def _width(column: str, law_width: int, position: int, status_width: int | None = None) -> int:
    if position == 0:
        return law_width
    if column == "status":
        return status_width or max(len(name) for name in _STATUS_NAMES.values())
    if column == "steps":
        return 8   # max_steps ≤ 10^7 (bifurcation.bounds)
    return _FLOAT_WIDTH
