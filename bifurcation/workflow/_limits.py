"""Bounded work before work: the size of a workflow's grid, counted from the TOML before any point is made.

A range's points are counted from its ``num`` (or its decades × ``per_decade``) without computing
them, so a 10 KB workflow that declares 200 ranges of 10^5 points is refused in milliseconds with
its count, instead of taking minutes and gigabytes to build a grid that would be refused anyway.
The counts are upper bounds (points shared by several ranges are counted once per range).

Limits (documented in docs/studies.md, "Bounds and limits", and the workflow schema):

* ``AXIS_MAX_POINTS`` = 10^5 points declared on one axis, over all its values and ranges;
* ``MAX_POINTS`` = 10^8 points in the grid (laws × the axes): the resume mask alone is one byte a
  point (100 MB) and the study ~2 hours of one 16-core machine at ~15 000 points/s.
"""

from __future__ import annotations

from ..errors import InputError
from ._axes import log_count

__all__ = ["AXIS_MAX_POINTS", "MAX_POINTS", "check_declared_size"]

AXIS_MAX_POINTS = 100_000
MAX_POINTS = 10**8
_FIX = "split the study into several workflows, or use fewer points (num, per_decade)"


def _count(value, default: int = 0) -> int:
    return value if isinstance(value, int) and not isinstance(value, bool) and value > 0 else default


def _axis_count(table: dict) -> int:
    """Points an axis table declares: its values, its ranges' ``num`` and its log range's count."""
    n = len(table["values"]) if isinstance(table.get("values"), list) else 0
    ranges = table.get("ranges")
    if isinstance(ranges, list):
        n += sum(_count(r.get("num")) for r in ranges if isinstance(r, dict))
    log = table.get("log")
    if isinstance(log, dict):
        if "num" in log:
            n += _count(log["num"])
        else:
            start, stop, per_decade = log.get("start"), log.get("stop"), _count(log.get("per_decade"))
            try:
                if per_decade and float(start) > 0 and float(stop) > 0 and per_decade <= 1000:
                    n += log_count(float(start), float(stop), per_decade)
            except (TypeError, ValueError, ArithmeticError):
                pass   # a malformed range is refused with its own message by the axis parser
    return n


def check_declared_size(data: dict) -> None:
    """Refuse a TOML workflow (parsed ``data``) whose declared grid exceeds the limits; cheap: nothing
    is materialised. Every ``[grid.<axis>]`` table counts (whatever the model's axes); malformed
    tables are left to the schema checks."""
    grid = data.get("grid") if isinstance(data, dict) else None
    engine = data.get("engine") if isinstance(data, dict) else None
    if not isinstance(grid, dict):
        return
    counts = {}
    for key, table in grid.items():
        counts[key] = _axis_count(table) if isinstance(table, dict) else 0
        if counts[key] > AXIS_MAX_POINTS:
            raise InputError(f"grid.{key}", f"{counts[key]} points",
                             f"declares more than {AXIS_MAX_POINTS} points on one axis", _FIX)
    laws = engine.get("laws") if isinstance(engine, dict) else None
    n_laws = len(laws) if isinstance(laws, list) else 1
    total = n_laws
    for n in counts.values():
        total *= n
    if total > MAX_POINTS:
        shape = " × ".join(f"{n} {axis}" for axis, n in reversed(list(counts.items())))
        raise InputError("grid", f"{total} points", f"declares more than {MAX_POINTS} points "
                         f"({n_laws} laws × {shape})", _FIX)
