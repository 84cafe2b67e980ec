"""Query a store by label: law, ν, ν_f → one record per point, as a table, CSV or JSON.

A ν or ν_f that is a label of the store selects it exactly; any other value selects the nearest label
(the records carry the labels actually selected). Laws are matched exactly.
"""

from __future__ import annotations

import csv
import io
import json
import math
from json.encoder import encode_basestring_ascii
from typing import Iterable, Iterator, TextIO

import numpy as np

from .engine._validate import check_nu, check_nu_f
from .engine.result import FIELDS, Status
from .errors import InputError
from .store.layout import VARIABLES

__all__ = ["COLUMNS", "FORMATS", "RecordStream", "format_records", "iter_records", "query", "write_records"]

FORMATS = ("table", "csv", "json")
#: Keys of a record, in order.
COLUMNS = ("law", "nu", "nu_f", "status", *FIELDS, "steps")
_STATUS_NAMES = [str(s) for s in Status]


def _as_list(value) -> list | None:
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or np.ndim(value) == 0:
        return [value]
    return list(value)


_CHECKS = {"nu": check_nu, "nu_f": check_nu_f}


def _labels(axis: np.ndarray, wanted, argument: str) -> list[int] | None:
    """Indices of ``axis`` selected by ``wanted`` (exact label, else nearest; log distance for ν)."""
    wanted = _as_list(wanted)
    if wanted is None:
        return None
    out = set()
    for value in wanted:
        x = float(_CHECKS[argument](value))   # one value at a time: an error shows that value
        exact = np.flatnonzero(axis == x)
        if exact.size:
            out.add(int(exact[0]))
        else:   # ν spans decades: nearest in log; ν_f is linear
            distance = np.abs(np.log(axis) - np.log(x)) if argument == "nu" else np.abs(axis - x)
            out.add(int(np.argmin(distance)))
    return sorted(out)


def _selection(labels: dict, law, nu, nu_f) -> dict[str, list[int]]:
    """Selected indices per axis (all when not given), from the axes' ``labels``."""
    laws = [str(x) for x in labels["law"]]
    selected = {"law": list(range(len(laws)))}
    wanted_laws = _as_list(law)
    if wanted_laws is not None:
        missing = [x for x in wanted_laws if str(x).strip() not in laws]
        if missing:
            raise InputError("law", missing[0], "is not a law of this store", f"use one of {', '.join(laws)}")
        selected["law"] = sorted({laws.index(str(x).strip()) for x in wanted_laws})
    for name, wanted in (("nu_f", nu_f), ("nu", nu)):
        axis = np.asarray(labels[name], dtype=float)
        chosen = _labels(axis, wanted, name)
        selected[name] = list(range(axis.size)) if chosen is None else chosen
    return selected


def _record(law: str, nu: float, nu_f: float, status: int, floats: list, steps: int) -> dict:
    record = {"law": law, "nu": nu, "nu_f": nu_f, "status": _STATUS_NAMES[status]}
    for name, x in zip(FIELDS, floats):
        record[name] = x if math.isfinite(x) else None
    record["steps"] = steps
    return record


def query(store, *, law=None, nu=None, nu_f=None, computed_only: bool = False) -> list[dict]:
    """Records of the points selected in ``store`` (a path or a Dataset from ``open_store``).

    ``law``, ``nu``, ``nu_f``: a value or a list of values (None: all). Each record has ``law``,
    ``nu``, ``nu_f``, ``status`` (a string such as ``"stick-slip"``; ``"not-computed"`` where the
    store has no value yet), the float ``FIELDS`` (None for NaN) and ``steps``, ordered by law, ν_f, ν.
    ``iter_records`` yields the same records one at a time (memory independent of the store's size).
    """
    return list(iter_records(store, law=law, nu=nu, nu_f=nu_f, computed_only=computed_only))


class RecordStream:
    """The records of a query, iterated one at a time; ``law_width`` is the longest law label."""

    def __init__(self, records: Iterator[dict], law_width: int) -> None:
        self._records, self.law_width = records, law_width

    def __iter__(self) -> Iterator[dict]:
        return self._records


def iter_records(store, *, law=None, nu=None, nu_f=None, computed_only: bool = False) -> RecordStream:
    """The records of ``query``, streamed: read a chunk row at a time, every chunk checked.

    From a path, every selected chunk is checked (checksum, ``done`` against the data;
    ``store.integrity``) in this call, before any record is made, so a damaged store yields nothing:
    ``StoreDamagedError`` names the chunk and the repair command. A Dataset is read as it is.
    """
    if hasattr(store, "data_vars"):
        laws = [str(x) for x in store["law"].values]
        return RecordStream(_dataset_records(store, law, nu, nu_f, computed_only), max(map(len, laws)))
    plan = _Plan(store, law, nu, nu_f)
    plan.check()
    return RecordStream(plan.records(computed_only), max(map(len, plan.labels["law"])))


class _Plan:
    """The chunks a selection touches, read one chunk row (law, ν_f block) at a time."""

    def __init__(self, path, law, nu, nu_f) -> None:
        from .store import check_store
        from .store.integrity import TileReader

        check_store(path, None, argument="store")
        # a tile being written (or left half written by a killed run) reads as not computed
        self.reader = reader = TileReader(path, in_progress=True)
        self.dims = tuple(reader.done.metadata.dimension_names or ("law", "nu_f", "nu"))
        labels = {name: self._coordinate(name) for name in self.dims}
        self.labels = {"law": [str(x) for x in labels["law"]],
                       "nu_f": [float(x) for x in labels["nu_f"]], "nu": [float(x) for x in labels["nu"]]}
        self.selected = _selection(self.labels, law, nu, nu_f)
        self.chunks = dict(zip(self.dims, reader.chunks))

    def _coordinate(self, name: str) -> np.ndarray:
        from .store.integrity import Damage, StoreDamagedError

        array = self.reader.coordinates[name]
        for k in range(-(-array.shape[0] // array.chunks[0])):
            if not self.reader.exists(name, (k,)):
                raise StoreDamagedError(self.reader.path, Damage(self.reader.key(name, (k,)), (k,),
                                                                 "missing coordinate chunk"))
        return self.reader._decode(array, name, (0,), (slice(None),))

    def _blocks(self, name: str) -> list[tuple[int, list[int]]]:
        """``(chunk index, selected indices in it)`` along axis ``name``."""
        size, out = self.chunks[name], {}
        for index in self.selected[name]:
            out.setdefault(index // size, []).append(index)
        return sorted(out.items())

    def tiles(self):
        for l in self.selected["law"]:
            for cf, rows in self._blocks("nu_f"):
                yield l, cf, rows, [(cn, cols) for cn, cols in self._blocks("nu")]

    def check(self) -> None:
        """Every selected chunk, decoded and checked, before anything is printed."""
        for l, cf, _, columns in self.tiles():
            for cn, _ in columns:
                self.reader.read((l // self.chunks["law"], cf, cn))

    def records(self, computed_only: bool) -> Iterator[dict]:
        size_f, size_n = self.chunks["nu_f"], self.chunks["nu"]
        names = self.labels
        for l, cf, rows, columns in self.tiles():
            # one chunk row at a time: memory is one row of chunks, whatever the store's size
            row = {cn: self.reader.read((l // self.chunks["law"], cf, cn)) for cn, _ in columns}
            law = names["law"][l]
            for i in rows:
                for cn, cols in columns:
                    values = row[cn]
                    r = i - cf * size_f
                    done = values["done"][0, r].tolist()
                    status = values["status"][0, r].tolist()
                    steps = values["steps"][0, r].tolist()
                    floats = [values[name][0, r].tolist() for name in FIELDS]
                    for j in cols:
                        c = j - cn * size_n
                        if computed_only and not done[c]:
                            continue
                        yield _record(law, names["nu"][j], names["nu_f"][i], status[c],
                                      [f[c] for f in floats], steps[c])


def _dataset_records(ds, law, nu, nu_f, computed_only) -> Iterator[dict]:
    labels = {"law": [str(x) for x in ds["law"].values], "nu_f": ds["nu_f"].values, "nu": ds["nu"].values}
    selected = _selection(labels, law, nu, nu_f)
    sub = ds.isel(selected)
    values = {name: np.asarray(sub[name].values) for name in VARIABLES}
    sub_laws = [str(x) for x in sub["law"].values]
    sub_nu_f = np.asarray(sub["nu_f"].values, dtype=float)
    sub_nu = np.asarray(sub["nu"].values, dtype=float)
    for index in np.ndindex(values["status"].shape):
        if computed_only and not values["done"][index]:
            continue
        l, i, j = index
        yield _record(sub_laws[l], float(sub_nu[j]), float(sub_nu_f[i]), int(values["status"][index]),
                      [float(values[name][index]) for name in FIELDS], int(values["steps"][index]))


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def format_records(records: list[dict], fmt: str = "table") -> str:
    """``records`` as an aligned ``table``, ``csv`` (header, empty cell = NaN) or strict ``json``."""
    buffer = io.StringIO()
    write_records(records, fmt, buffer)
    return buffer.getvalue().rstrip("\n")


#: Table column widths: a float's repr is at most 24 characters (-1.7976931348623157e+308).
_FLOAT_WIDTH = 24


def write_records(records: Iterable[dict], fmt: str, out: TextIO, *, law_width: int | None = None) -> int:
    """Write ``records`` to ``out`` as they come (the table has fixed column widths); returns the count.

    The JSON is the text of ``json.dumps(list(records), indent=2)``, written one record at a time.
    """
    if fmt not in FORMATS:
        raise InputError("--format", fmt, "is not a format", f"use one of {', '.join(FORMATS)}")
    n = 0
    if fmt == "json":
        # json.dumps with indent takes its pure-Python path (slow); a record is flat, so its scalars are
        # written as json writes them, in the layout of json.dumps(records, indent=2)
        keys = {}
        for record in records:
            lines = []
            for key, value in record.items():
                if key not in keys:
                    keys[key] = f'    {json.dumps(key)}: '
                lines.append(keys[key] + _json_scalar(value))
            out.write(("[\n  {\n" if n == 0 else ",\n  {\n") + ",\n".join(lines) + "\n  }")
            n += 1
        out.write("\n]\n" if n else "[]\n")
        return n
    if fmt == "csv":
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(COLUMNS)
        for record in records:   # csv writes floats with repr (exact) and None as an empty cell
            writer.writerow([record[c] for c in COLUMNS])
            n += 1
        return n
    if law_width is None:
        records = list(records)
        law_width = max((len(r["law"]) for r in records), default=0)
    widths = [max(len(c), _width(c, law_width)) for c in COLUMNS]
    out.write("  ".join(c.ljust(w) for c, w in zip(COLUMNS, widths)).rstrip() + "\n")
    for record in records:
        cells = [_cell(record.get(c)) or "-" for c in COLUMNS]
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


def _width(column: str, law_width: int) -> int:
    if column == "law":
        return law_width
    if column == "status":
        return max(len(name) for name in _STATUS_NAMES)
    if column == "steps":
        return 8   # max_steps ≤ 10^7 (bifurcation.bounds)
    return _FLOAT_WIDTH
