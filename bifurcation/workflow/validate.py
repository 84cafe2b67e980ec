"""The one validator of TOML workflows: every key known, every value of the right type and range.

Every command that reads a workflow (``submit``'s study schema in ``spec``, a model's own workflow such
as rate-state's ``continue``) reads it through here: ``read_toml`` (a bounded, UTF-8, valid TOML file,
not a workflow of another command) and ``Table`` (key sets, types, ranges, finite numbers, arrays of
tables). Each error is one ``InputError`` naming the dotted key (``grid.nu.log.per_decade``), the value
and the fix; a key nobody asked for is named with its table and the file it is in.

Which command a workflow belongs to is declared, not listed here: ``submit``'s kind is ``SUBMIT``, and a
model with a workflow of its own declares a ``WorkflowKind`` as its ``workflow`` hook (``Model.hooks``).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from numbers import Real

from ..errors import InputError

__all__ = ["MAX_WORKFLOW_BYTES", "SUBMIT", "Table", "WorkflowKind", "as_number", "check_range", "other_command",
           "parse_toml", "read_toml", "read_workflow_text"]


@dataclass(frozen=True)
class WorkflowKind:
    """The workflows of one command: the top-level tables that tell them from the others' (``tables``),
    what they are (``what``, for the message) and how to run one (``fix``)."""

    command: str
    tables: tuple[str, ...]
    what: str
    fix: str


#: The study workflows of ``bifurcation submit`` (schema: ``bifurcation.workflow.spec``).
SUBMIT = WorkflowKind("submit", ("engine", "grid", "tiles", "model"),
                      "a study workflow of `bifurcation submit` ([engine], [grid])",
                      "run it with `bifurcation submit FILE`")


def _kinds() -> list[WorkflowKind]:
    """``SUBMIT`` and the kinds the registered models declare (their ``workflow`` hook)."""
    from ..models import get_model, model_names

    kinds = [SUBMIT]
    for name in model_names():
        declared = get_model(name).hook("workflow")
        kinds += [] if declared is None else list(declared) if isinstance(declared, (list, tuple)) else [declared]
    return kinds


def other_command(data, own: WorkflowKind, argument: str, source) -> None:
    """Refuse a parsed workflow written for another command than ``own``'s, naming that command (a
    table of ``own``'s kind anywhere in it keeps it here, for the schema checks to name)."""
    if not isinstance(data, dict) or any(key in data for key in own.tables):
        return
    for kind in _kinds():   # only for a workflow that is not of its own kind: the registry is read here
        if kind.command != own.command and any(key in data for key in kind.tables):
            raise InputError(argument, str(source), f"is {kind.what}, not one for `bifurcation {own.command}`",
                             kind.fix)


#: Tables and arrays nest at most this deep in a workflow (the shipped ones: 3).
MAX_DEPTH = 32


class _OutOfRange(ValueError):
    def __init__(self, literal: str) -> None:
        super().__init__(literal)
        self.literal = literal


def _toml_float(literal: str) -> float:
    """A TOML float as ``tomllib`` reads it, except that a nonzero literal read as 0 (``1e-400``) or a finite one
    read as infinity (``1e400``) is refused rather than silently changed, and ``-0.0`` reads as 0.0 (a label ``-0`` would differ from ``0`` in text
    only)."""
    value = float(literal)
    if math.isinf(value) and "inf" not in literal:   # 1e400: refused as the literal, not as 'inf'
        raise _OutOfRange(literal)
    if value == 0.0:
        mantissa = literal.lower().split("e")[0]
        if any(c in "123456789" for c in mantissa):
            raise _OutOfRange(literal)
        return 0.0
    return value


def _depth(data) -> int:
    """How deep tables and arrays nest in ``data`` (iteratively: no recursion limit to hit)."""
    deepest, stack = 0, [(data, 1)]
    while stack:
        node, level = stack.pop()
        if isinstance(node, dict):
            node = list(node.values())
        elif not isinstance(node, list):
            continue
        deepest = max(deepest, level)
        if level <= MAX_DEPTH:
            stack.extend((child, level + 1) for child in node if isinstance(child, (dict, list)))
    return deepest


def parse_toml(text: str, argument: str, source, example: str) -> dict:
    """The TOML document ``text`` (from ``source``, a file name for messages), or an ``InputError``."""
    try:
        data = tomllib.loads(text, parse_float=_toml_float)
    except RecursionError:   # tables or arrays nested thousands deep
        raise InputError(argument, str(source), "is nested too deeply",
                         f"a workflow needs only tables nested a few deep (see {example})") from None
    except _OutOfRange as exc:
        line = text.count("\n", 0, max(text.find(exc.literal), 0)) + 1
        what = ("is beyond the range of a double (|x| < ~1.8e308) and would be read as infinity"
                if math.isinf(float(exc.literal)) else "is below the smallest double (~5e-324) and would be read as 0")
        raise InputError(argument, str(source), f"holds the number {exc.literal} (line {line}), which {what}",
                         "write a number a double holds (or 0 where 0 is meant)") from None
    except tomllib.TOMLDecodeError as exc:
        if text.startswith("\ufeff"):   # said as 'Invalid statement (at line 1, column 1)' before
            raise InputError(argument, str(source), "starts with a byte-order mark (U+FEFF, as some editors save "
                             "UTF-8), which TOML does not allow", "save it as UTF-8 without a BOM") from None
        raise InputError(argument, str(source), f"is not valid TOML ({exc})",
                         f"fix the syntax; see {example} for an example") from None
    if _depth(data) > MAX_DEPTH:   # dotted keys a.a.a… parse without recursion, but every repr of them overflows
        raise InputError(argument, str(source), f"is nested too deeply (more than {MAX_DEPTH} levels of tables "
                         "or arrays)", f"a workflow needs only tables nested a few deep (see {example})")
    return data


def read_toml(path, kind: WorkflowKind, *, argument: str, example: str) -> tuple[str, dict]:
    """``(text, document)`` of the workflow file at ``path`` for the command of ``kind``: a bounded UTF-8
    file of valid TOML that is not another command's workflow (``InputError`` naming ``argument``)."""
    text = read_workflow_text(path, argument, example)
    data = parse_toml(text, argument, path, example)
    other_command(data, kind, argument, path)
    return text, data


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
            dict: "a table"}.get(type(value), f"a {type(value).__name__.replace('datetime', 'date-time')}")


class Table:
    """Read keys of one TOML table; a key not in ``allowed`` is refused on construction.

    ``key`` is the table's dotted name (``""``: the top level), ``source`` the file it comes from (named
    in the message of an unknown key; inherited by the tables read from this one).
    """

    def __init__(self, data, key: str, allowed, *, source=None) -> None:
        if not isinstance(data, dict):
            raise InputError(key, data, f"is {_type_name(data)}, not a table",
                             f"write it as a table [{key}] or {{ ... }}")
        self.data, self.key, self.allowed, self.source = data, key, tuple(allowed), source
        unknown = [k for k in data if k not in self.allowed]
        if unknown:
            where = f" in {source}" if source is not None else ""
            if key:
                raise InputError(self.path(unknown[0]), data[unknown[0]], f"is not a known key of [{key}]{where}",
                                 f"use only {', '.join(self.allowed)} in [{key}]")
            raise InputError(unknown[0], data[unknown[0]], f"is not a known table or key of the workflow{where}",
                             f"use only the tables {', '.join(self.allowed)}")

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

    def table(self, name: str, allowed, *, required: bool = True) -> "Table | None":
        if name not in self.data and not required:
            return None
        return Table(self.raw(name, fix=f"add a table [{self.path(name)}]"), self.path(name), allowed,
                     source=self.source)

    def tables(self, name: str, allowed, *, most: int | None = None, fix: str = "") -> list["Table"]:
        """An array of tables (``[[name]]`` or ``name = [{ ... }, ...]``), each read as ``name[i]``."""
        items = self.array(name, fix=fix or f"give at least one [[{self.path(name)}]] table")
        if most is not None and len(items) > most:
            raise InputError(self.path(name), f"{len(items)} tables", f"has more than {most}",
                             "split the workflow into several")
        return [Table(item, f"{self.path(name)}[{i}]", allowed, source=self.source) for i, item in enumerate(items)]

    def string(self, name: str, default=_MISSING, *, fix: str = "") -> str:
        value = self.raw(name, default, fix=fix)
        if not isinstance(value, str):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not a string",
                             fix or "write it in quotes")
        return value

    def boolean(self, name: str, default=_MISSING, *, fix: str = "") -> bool:
        value = self.raw(name, default, fix=fix)
        if not isinstance(value, bool):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not true or false",
                             fix or f"write {name} = true or {name} = false")
        return value

    def integer(self, name: str, default=_MISSING, *, low: int = 1, high: int | None = None,
                fix: str = "") -> int:
        value = self.raw(name, default, fix=fix)
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not an integer",
                             fix or "write a whole number without a decimal point")
        check_range(self.path(name), value, low, high, fix)
        return value

    def number(self, name: str, default=_MISSING, *, low=None, high=None, above=None, fix: str = "") -> float:
        """A finite number in [``low``, ``high``] and > ``above`` (each bound only when given)."""
        return _bounded(self.path(name), self.raw(name, default, fix=fix), low, high, above, fix)

    def numbers(self, name: str, default=_MISSING, *, low=None, high=None, above=None, most: int | None = None,
                fix: str = "") -> tuple[float, ...]:
        """A non-empty array of at most ``most`` finite numbers, each bounded as in ``number`` (each named
        ``name[i]``)."""
        values = self.array(name, default, fix=fix)
        if most is not None and len(values) > most:
            raise InputError(self.path(name), f"{len(values)} values", f"has more than {most} values",
                             fix or f"give at most {most}")
        return tuple(_bounded(f"{self.path(name)}[{i}]", v, low, high, above, fix) for i, v in enumerate(values))

    def integers(self, name: str, default=_MISSING, *, low: int | None = 1, high: int | None = None,
                 most: int | None = None, fix: str = "") -> tuple[int, ...]:
        """A non-empty array of at most ``most`` integers in [``low``, ``high``] (each named ``name[i]``)."""
        values = self.array(name, default, fix=fix)
        if most is not None and len(values) > most:
            raise InputError(self.path(name), f"{len(values)} values", f"has more than {most} values",
                             fix or f"give at most {most}")
        for i, value in enumerate(values):
            if isinstance(value, bool) or not isinstance(value, int):
                raise InputError(f"{self.path(name)}[{i}]", value, f"is {_type_name(value)}, not an integer",
                                 fix or "write whole numbers without a decimal point")
            check_range(f"{self.path(name)}[{i}]", value, low, high, fix)
        return tuple(values)

    def array(self, name: str, default=_MISSING, *, fix: str = "") -> list:
        value = self.raw(name, default, fix=fix)
        if not isinstance(value, list):
            raise InputError(self.path(name), value, f"is {_type_name(value)}, not an array",
                             fix or f"write {name} = [ ... ]")
        if not value:
            raise InputError(self.path(name), value, "is empty", fix or "give at least one element")
        return value


def _bounded(key: str, value, low, high, above, fix: str) -> float:
    value = as_number(key, value, fix)
    if above is not None and not value > above:
        span = f"> {above:g}" + (f" and <= {high:g}" if high is not None else "")
        raise InputError(key, value, f"must be {span}", fix or f"give a value {span}")
    check_range(key, value, low, high, fix)
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
        span = (f"in [{_bound(low)}, {_bound(high)}]" if low is not None and high is not None else
                f">= {_bound(low)}" if low is not None else f"<= {_bound(high)}")
        raise InputError(key, value, f"is out of range: must be {span}", fix or f"give a value {span}")
