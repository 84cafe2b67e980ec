"""A strict reader for TOML tables: every key known, every value of the right type.

Each error is an ``InputError`` naming the dotted key (``grid.nu.log.per_decade``), the value and the fix.
"""

from __future__ import annotations

import math
from numbers import Real

from ..errors import InputError

__all__ = ["MAX_WORKFLOW_BYTES", "Table", "other_command", "read_workflow_text"]

#: The tables that tell each command's workflow from the others'.
_KINDS = (
    ("submit", ("engine", "grid", "tiles", "model"), "a study workflow of `bifurcation submit` ([engine], [grid])",
     "run it with `bifurcation submit FILE`"),
    ("continue", ("slider", "branch", "hopf"),
     "a rate-state continuation workflow of `bifurcation continue` ([slider], [[branch]], [hopf])",
     "run it with `bifurcation continue FILE`"),
    ("chain-report", ("chain", "sweep", "catalog", "threshold", "near_half"),
     "a chain report workflow ([chain], [sweep])",
     "run it with `python -m bifurcation.models.chain.report FILE`"),
)


def other_command(data, command: str, argument: str, source) -> None:
    """Refuse a parsed workflow written for another command than ``command``, naming that command (a
    table of this command's own kind anywhere in it keeps it here, for the schema checks to name)."""
    if not isinstance(data, dict):
        return
    own = next(tables for kind, tables, _, _ in _KINDS if kind == command)
    if any(key in data for key in own):
        return
    for kind, tables, what, fix in _KINDS:
        if kind != command and any(key in data for key in tables):
            raise InputError(argument, str(source), f"is {what}, not one for `bifurcation {command}`", fix)

#: A workflow is a page of TOML (the shipped ones are < 3 KB); anything larger is not one, and reading it
#: whole (``/dev/zero``, a log, a data file) could take all the memory there is.
MAX_WORKFLOW_BYTES = 1 << 20


def read_workflow_text(path, argument: str, example: str) -> str:
    """The text of the workflow file at ``path``: a regular file of at most ``MAX_WORKFLOW_BYTES`` bytes of
    UTF-8, else an ``InputError`` naming ``argument`` (checked before it is read whole)."""
    import stat
    from pathlib import Path

    path = Path(path)
    fix = f"give the path of a TOML workflow such as {example}"
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        raise InputError(argument, str(path), "cannot be read (no such file)", fix) from None
    except OSError as exc:
        raise InputError(argument, str(path), f"cannot be read ({exc.strerror or exc})", fix) from None
    if stat.S_ISDIR(mode):
        raise InputError(argument, str(path), "is a directory, not a file", fix)
    if not stat.S_ISREG(mode):
        raise InputError(argument, str(path), "is not a regular file (a device, pipe or socket)", fix)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_WORKFLOW_BYTES + 1)
    except OSError as exc:
        raise InputError(argument, str(path), f"cannot be read ({exc.strerror or exc})", fix) from None
    if len(data) > MAX_WORKFLOW_BYTES:
        raise InputError(argument, str(path), f"is larger than {MAX_WORKFLOW_BYTES} bytes: not a workflow", fix)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(argument, str(path), f"cannot be read: not UTF-8 text (byte {data[exc.start]:#04x} at "
                         f"offset {exc.start})", "give a TOML workflow saved as UTF-8 text") from None

_MISSING = object()


def _type_name(value) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array",
            dict: "a table"}.get(type(value), type(value).__name__)


class Table:
    """Read keys of one TOML table; ``done()`` refuses the keys nobody asked for."""

    def __init__(self, data, key: str, allowed: tuple[str, ...]) -> None:
        if not isinstance(data, dict):
            raise InputError(key, data, f"is {_type_name(data)}, not a table",
                             f"write it as a table [{key}] or {{ ... }}")
        self.data, self.key, self.allowed = data, key, allowed
        unknown = [k for k in data if k not in allowed]
        if unknown:
            raise InputError(self.path(unknown[0]), data[unknown[0]], "is not a known key",
                             f"use only {', '.join(allowed)} in [{key}]" if key else
                             f"use only the tables {', '.join(allowed)}")

    def path(self, name: str) -> str:
        return f"{self.key}.{name}" if self.key else name

    def has(self, name: str) -> bool:
        return name in self.data

    def raw(self, name: str, default=_MISSING, *, fix: str = ""):
        if name in self.data:
            return self.data[name]
        if default is _MISSING:
            raise InputError(self.path(name), None, "is missing", fix or f"add {name} = ... to [{self.key}]")
        return default

    def table(self, name: str, allowed: tuple[str, ...], *, required: bool = True) -> "Table | None":
        if name not in self.data and not required:
            return None
        return Table(self.raw(name, fix=f"add a table [{self.path(name)}]"), self.path(name), allowed)

    def string(self, name: str, default=_MISSING, *, fix: str = "") -> str:
        value = self.raw(name, default, fix=fix)
        if not isinstance(value, str):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not a string",
                             fix or "write it in quotes")
        return value

    def integer(self, name: str, default=_MISSING, *, low: int = 1, high: int | None = None,
                fix: str = "") -> int:
        value = self.raw(name, default, fix=fix)
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not an integer",
                             fix or "write a whole number without a decimal point")
        check_range(self.path(name), value, low, high, fix)
        return value

    def number(self, name: str, default=_MISSING, *, fix: str = "") -> float:
        return as_number(self.path(name), self.raw(name, default, fix=fix), fix)

    def array(self, name: str, default=_MISSING, *, fix: str = "") -> list:
        value = self.raw(name, default, fix=fix)
        if not isinstance(value, list):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not an array",
                             fix or f"write {name} = [ ... ]")
        if not value:
            raise InputError(self.path(name), value, "is empty", fix or "give at least one element")
        return value


def as_number(key: str, value, fix: str = "") -> float:
    """A finite real number (TOML integer or float, never a boolean or a string)."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise InputError(key, value, f"is {_type_name(value)}, not a number",
                         fix or "write a number such as 0.4 or 1e-9 (no quotes)")
    value = float(value)
    if not math.isfinite(value):
        raise InputError(key, value, "is not finite", fix or "give a finite number")
    return value


def _bound(x) -> str:
    """A bound as written exactly: 1048576, not 1.04858e+06 (which a value just above it would match)."""
    x = float(x)
    if float(f"{x:g}") == x:   # short and exact: 1e+09, 0.99
        return f"{x:g}"
    return str(int(x)) if x.is_integer() and abs(x) < 2 ** 53 else repr(x)


def check_range(key: str, value, low, high, fix: str = "") -> None:
    if (low is not None and value < low) or (high is not None and value > high):
        span = f"in [{_bound(low)}, {_bound(high)}]" if high is not None else f">= {_bound(low)}"
        raise InputError(key, value, f"is out of range: must be {span}", fix or f"give a value {span}")
