"""Query a store by label: law, ν, ν_f → one record per point, as a table, CSV or JSON.

A ν or ν_f that is a label of the store selects it exactly; any other value selects the nearest label
(the records carry the labels actually selected). Laws are matched exactly.
"""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np

from .engine._validate import check_nu, check_nu_f
from .engine.result import FIELDS, status_names
from .errors import InputError
from .store.layout import VARIABLES

__all__ = ["COLUMNS", "FORMATS", "format_records", "query"]

FORMATS = ("table", "csv", "json")
#: Keys of a record, in order.
COLUMNS = ("law", "nu", "nu_f", "status", *FIELDS, "steps")


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


def query(store, *, law=None, nu=None, nu_f=None, computed_only: bool = False) -> list[dict]:
    """Records of the points selected in ``store`` (a path or a Dataset from ``open_store``).

    ``law``, ``nu``, ``nu_f``: a value or a list of values (None: all). Each record has ``law``,
    ``nu``, ``nu_f``, ``status`` (a string such as ``"stick-slip"``; ``"not-computed"`` where the
    store has no value yet), the float ``FIELDS`` (None for NaN) and ``steps``, ordered by law, ν_f, ν.
    """
    from .store import open_store

    ds = store if hasattr(store, "data_vars") else open_store(store)
    laws = [str(x) for x in ds["law"].values]
    indexers = {}
    wanted_laws = _as_list(law)
    if wanted_laws is not None:
        missing = [x for x in wanted_laws if str(x).strip() not in laws]
        if missing:
            raise InputError("law", missing[0], "is not a law of this store", f"use one of {', '.join(laws)}")
        indexers["law"] = sorted({laws.index(str(x).strip()) for x in wanted_laws})
    for name, wanted in (("nu", nu), ("nu_f", nu_f)):
        selected = _labels(np.asarray(ds[name].values, dtype=float), wanted, name)
        if selected is not None:
            indexers[name] = selected
    sub = ds.isel(indexers)
    values = {name: np.asarray(sub[name].values) for name in VARIABLES}
    statuses = status_names(values["status"])
    sub_laws = [str(x) for x in sub["law"].values]
    sub_nu_f = np.asarray(sub["nu_f"].values, dtype=float)
    sub_nu = np.asarray(sub["nu"].values, dtype=float)
    records = []
    for index in np.ndindex(values["status"].shape):
        if computed_only and not values["done"][index]:
            continue
        l, i, j = index
        record = {"law": sub_laws[l], "nu": float(sub_nu[j]), "nu_f": float(sub_nu_f[i]),
                  "status": statuses[index]}
        for name in FIELDS:
            x = float(values[name][index])
            record[name] = x if math.isfinite(x) else None
        record["steps"] = int(values["steps"][index])
        records.append(record)
    return records


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def format_records(records: list[dict], fmt: str = "table") -> str:
    """``records`` as an aligned ``table``, ``csv`` (header, empty cell = NaN) or strict ``json``."""
    if fmt not in FORMATS:
        raise InputError("--format", fmt, "is not a format", f"use one of {', '.join(FORMATS)}")
    if fmt == "json":
        return json.dumps(records, indent=2, allow_nan=False)
    rows = [[_cell(r.get(c)) for c in COLUMNS] for r in records]
    if fmt == "csv":
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(COLUMNS)
        writer.writerows(rows)
        return buffer.getvalue().rstrip("\n")
    widths = [max(len(c), *(len(row[k]) for row in rows)) if rows else len(c) for k, c in enumerate(COLUMNS)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(COLUMNS, widths)).rstrip()]
    lines += ["  ".join((cell or "-").ljust(w) for cell, w in zip(row, widths)).rstrip() for row in rows]
    return "\n".join(lines)
