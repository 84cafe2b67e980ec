r"""Workflows: a study over a (law, ν_f, ν) grid, written as a TOML file.

Schema (every key is checked; unknown keys, wrong types and impossible values are refused with an
``InputError`` naming the dotted key, e.g. ``grid.nu.log.per_decade``)::

    [study]
    name = "critical-point"          # required; letters, digits, . _ -  (default store results/<name>.zarr)
    description = "..."              # optional

    [engine]
    laws = ["piecewise-linear", "carlson-langer"]   # required; names of bifurcation.law_names()
                                     # or formulas in x ("exp(-x)"); each is checked with resolve_law
    precision = "double"             # optional: "double" (default) or "quad"
    t_max = 1e5                      # optional: bound on the time of one cycle (> 0)
    max_steps = 200000               # optional: bound on the Taylor steps of one cycle (>= 1)
    batch = 8                        # optional: heyoka SIMD lanes (1..64, double only; default 1)

    [grid.nu]                        # pulling speed ν of Eq. (5); at least one of values / log
    values = [1e-9]                  # explicit points, kept exactly as written
    log = { start = 1e-3, stop = 1e-15, per_decade = 4 }   # or num = 49 instead of per_decade

    [grid.nu_f]                      # friction velocity ν_f of Eq. (2); at least one of values / ranges
    values = [0.2, 0.3, 0.4, 0.5]
    ranges = [{ start = 0.45, stop = 0.55, num = 101 }]    # evenly spaced, both ends included

    [tiles]                          # optional: tile (= store chunk) shape, default 64 × 64
    nu_f = 64
    nu = 64

Each axis is the sorted union of its points with exact duplicates removed. Range and log points are
computed in decimal arithmetic and rounded once, so a range that passes through 0.4 yields exactly
``0.4`` (the float a user types) and a log axis from 1e-3 to 1e-15 passes through exactly 1e-9. A log
axis has at least ``per_decade`` points per decade and always includes both ends.

Bounds (one set for the whole package, ``bifurcation.bounds``): ν ∈ [1e-20, 1], ν_f ∈ [1e-4, 10],
``max_steps`` ≤ 10^7, ``t_max`` ≤ 1e9; tiles of 1 … 4096 points a side and at most 2^16 points; the
grid's size limits (points per axis, points in all) are in ``workflow._limits`` and are checked from
the counts of the ranges before any point is computed.

Two workflows are the *same study* when their ``fingerprint`` agrees: the sha256 of what determines
the numbers and the store layout (laws, precision, bounds, grid, tiles) — not of the text, so comments,
formatting, the name and the description may change without invalidating a store.
"""

from __future__ import annotations

import hashlib
import json
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..bounds import NU_BOUNDS, NU_F_BOUNDS, check_max_steps, check_t_max
from ..engine._validate import PRECISIONS, check_batch, check_precision
from ..engine.result import DEFAULT_MAX_STEPS, DEFAULT_T_MAX
from ..errors import InputError
from ..laws import resolve_law
from ._axes import linear_points, log_count, log_points, union
from ._limits import MAX_POINTS, check_declared_size
from ._toml import Table, as_number, check_range

__all__ = ["MAX_POINTS", "NU_BOUNDS", "NU_F_BOUNDS", "PRECISIONS", "TILE_MAX", "TILE_MAX_POINTS",
           "Workflow", "load_workflow", "parse_workflow"]

TILE_MAX = 4096
TILE_MAX_POINTS = 1 << 16
DEFAULT_TILES = (64, 64)
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
_NAME_MAX = 100
#: Most points of one log or linear range (``num``): a typo such as 1e9 is refused, not allocated.
_RANGE_POINTS_MAX = 100_000
#: Most SIMD lanes: far above any vector unit's width (AVX-512 holds 8 doubles); more is a typo.
_BATCH_MAX = 64


def _set(obj, name, value) -> None:
    object.__setattr__(obj, name, value)


@dataclass(frozen=True)
class Workflow:
    """A validated study: laws × ν_f × ν points, engine options and the tile (chunk) shape.

    Build one with ``load_workflow(path)``, ``parse_workflow(text)`` or directly (``nu`` and ``nu_f``
    are any sequences; they are sorted and deduplicated). Checked on construction.
    """

    name: str
    laws: tuple[str, ...]
    nu: tuple[float, ...]
    nu_f: tuple[float, ...]
    description: str = ""
    precision: str = "double"
    t_max: float = DEFAULT_T_MAX
    max_steps: int = DEFAULT_MAX_STEPS
    batch: int = 1                           # heyoka SIMD lanes (see bifurcation.slip)
    tiles: tuple[int, int] = DEFAULT_TILES   # (nu_f, nu)
    source: str | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _NAME.match(self.name):
            raise InputError("study.name", self.name, "is not a valid study name",
                             "use letters, digits, '.', '_' and '-' (it names the default store)")
        if len(self.name) > _NAME_MAX:   # results/<name>.zarr must fit a file name (255 bytes)
            raise InputError("study.name", f"{self.name[:20]}...", f"has {len(self.name)} characters",
                             f"use at most {_NAME_MAX} characters (it names the default store)")
        if not isinstance(self.description, str):
            raise InputError("study.description", self.description, "is not a string", "write it in quotes")
        _set(self, "laws", _check_laws(self.laws))
        _engine_check("engine.precision", check_precision, self.precision)
        _set(self, "t_max", check_t_max("engine.t_max", as_number("engine.t_max", self.t_max)))
        check_max_steps("engine.max_steps", self.max_steps)
        _set(self, "batch", _engine_check("engine.batch", check_batch, self.batch, self.precision))
        if self.batch > _BATCH_MAX:
            raise InputError("engine.batch", self.batch, f"is more than {_BATCH_MAX} lanes",
                             "give e.g. batch = 8 (SIMD lanes), or leave it out for 1")
        _set(self, "nu", _check_axis("grid.nu", self.nu, NU_BOUNDS))
        _set(self, "nu_f", _check_axis("grid.nu_f", self.nu_f, NU_F_BOUNDS))
        tiles = tuple(self.tiles)
        if len(tiles) != 2:
            raise InputError("tiles", self.tiles, "is not a (nu_f, nu) pair", "give two tile sizes")
        for key, size in zip(("tiles.nu_f", "tiles.nu"), tiles):
            if isinstance(size, bool) or not isinstance(size, int):
                raise InputError(key, size, "is not an integer", "give a whole number such as 64")
            check_range(key, size, 1, TILE_MAX)
        if tiles[0] * tiles[1] > TILE_MAX_POINTS:
            raise InputError("tiles", f"{tiles[0]} x {tiles[1]}", f"has more than {TILE_MAX_POINTS} points",
                             "use smaller tiles so that one task stays small in memory")
        _set(self, "tiles", tiles)
        if self.n_points > MAX_POINTS:
            raise InputError("grid", self.shape, f"has {self.n_points} points, more than {MAX_POINTS}",
                             "split the study into several workflows")

    # -- derived -------------------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int, int]:
        """(laws, ν_f, ν): the shape of the store's arrays."""
        return (len(self.laws), len(self.nu_f), len(self.nu))

    @property
    def n_points(self) -> int:
        law, nu_f, nu = self.shape
        return law * nu_f * nu

    @property
    def text(self) -> str:
        """The TOML source (as loaded), or a canonical TOML rendering for a workflow built in code."""
        return self.source if self.source is not None else self.to_toml()

    @property
    def sha256(self) -> str:
        """sha256 of ``text``."""
        return hashlib.sha256(self.text.encode()).hexdigest()

    @property
    def fingerprint(self) -> str:
        """sha256 of what determines the numbers and the store layout (see the module docstring)."""
        canonical = dict(laws=list(self.laws), precision=self.precision, t_max=repr(self.t_max),
                         max_steps=self.max_steps, nu=[repr(x) for x in self.nu],
                         nu_f=[repr(x) for x in self.nu_f], tiles=list(self.tiles))
        if self.batch != 1:  # batch results equal scalar ones to rounding only; 1 keeps old fingerprints
            canonical["batch"] = self.batch
        return hashlib.sha256(json.dumps(canonical, sort_keys=True).encode()).hexdigest()

    @property
    def default_store(self) -> Path:
        return Path("results") / f"{self.name}.zarr"

    def to_toml(self) -> str:
        """A TOML text that ``parse_workflow`` turns back into this workflow (explicit values)."""
        def floats(xs):
            return "[" + ", ".join(repr(x) for x in xs) + "]"

        return "\n".join([
            "[study]",
            f"name = {json.dumps(self.name)}",
            f"description = {json.dumps(self.description, ensure_ascii=False)}",
            "",
            "[engine]",
            "laws = [" + ", ".join(json.dumps(law, ensure_ascii=False) for law in self.laws) + "]",
            f"precision = {json.dumps(self.precision)}",
            f"t_max = {self.t_max!r}",
            f"max_steps = {self.max_steps}",
            f"batch = {self.batch}",
            "",
            "[grid.nu]",
            f"values = {floats(self.nu)}",
            "",
            "[grid.nu_f]",
            f"values = {floats(self.nu_f)}",
            "",
            "[tiles]",
            f"nu_f = {self.tiles[0]}",
            f"nu = {self.tiles[1]}",
            "",
        ])


def _engine_check(key: str, check, value, *args):
    """``check(value, *args)`` (a ``bifurcation.engine`` check), its error naming the workflow ``key``."""
    try:
        return check(value, *args)
    except InputError as exc:
        raise InputError(key, value, exc.problem, exc.fix) from None


def _check_laws(laws) -> tuple[str, ...]:
    if isinstance(laws, str) or not laws:
        raise InputError("engine.laws", laws, "is not a non-empty list of laws",
                         "write laws = [\"carlson-langer\"] (names or formulas in x)")
    out, seen = [], {}
    for i, law in enumerate(laws):
        key = f"engine.laws[{i}]"
        if not isinstance(law, str):
            raise InputError(key, law, "is not a string", "write a law name or formula in quotes")
        try:
            resolved = resolve_law(law)
        except InputError as exc:
            raise InputError(key, law, exc.problem, exc.fix) from None
        text = law.strip()
        identity = (resolved.name, resolved.formula)
        if identity in seen:
            raise InputError(key, law, f"repeats engine.laws[{seen[identity]}]", "list each law once")
        seen[identity] = i
        out.append(text)
    return tuple(out)


def _check_axis(key: str, values, bounds) -> tuple[float, ...]:
    try:
        points = [as_number(key, v) for v in values]
    except TypeError:
        raise InputError(key, values, "is not a sequence of numbers", "give a list of numbers") from None
    if not points:
        raise InputError(key, [], "is empty", "give at least one point")
    for x in points:
        check_range(key, x, *bounds)
    return union(points)


# -- TOML ------------------------------------------------------------------------------------------
def parse_workflow(text: str, *, source: str | None = None) -> Workflow:
    """The ``Workflow`` written in TOML ``text`` (schema in the module docstring).

    ``source`` (the file name) is only used in error messages.
    """
    try:
        data = tomllib.loads(text)
    except RecursionError:   # tables or arrays nested thousands deep
        raise InputError("workflow", source if source is not None else _short(text), "is nested too deeply",
                         "a workflow needs only the tables of workflows/*.toml, nested two deep") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError("workflow", source if source is not None else _short(text),
                         f"is not valid TOML ({exc})", "fix the syntax; see workflows/*.toml for examples") from None
    root = Table(data, "", ("study", "engine", "grid", "tiles"))
    check_declared_size(data)   # before any point is made
    study = root.table("study", ("name", "description"))
    engine = root.table("engine", ("laws", "precision", "t_max", "max_steps", "batch"))
    grid = root.table("grid", ("nu", "nu_f"))
    tiles = root.table("tiles", ("nu_f", "nu"), required=False)

    laws = engine.array("laws", fix="write laws = [\"carlson-langer\"] (names or formulas in x)")
    # Workflow checks the engine options and tiles (with the same dotted keys) on construction
    options = {name: engine.raw(name) for name in ("precision", "t_max", "max_steps", "batch") if engine.has(name)}
    if tiles is not None:
        options["tiles"] = (tiles.raw("nu_f", DEFAULT_TILES[0]), tiles.raw("nu", DEFAULT_TILES[1]))
    return Workflow(
        name=study.string("name", fix="add name = \"my-study\" to [study]"),
        description=study.string("description", ""),
        laws=tuple(laws),
        nu=_nu_axis(grid.table("nu", ("values", "log"))),
        nu_f=_nu_f_axis(grid.table("nu_f", ("values", "ranges"))),
        source=text,
        **options,
    )


def load_workflow(path) -> Workflow:
    """The ``Workflow`` of the TOML file at ``path``."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError("workflow", str(path), "no such file",
                         "give the path of a TOML workflow such as workflows/paper-fig2.toml") from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as exc:
        raise InputError("workflow", str(path), f"cannot be read ({type(exc).__name__})",
                         "give the path of a readable UTF-8 TOML file") from None
    return parse_workflow(text, source=str(path))


def _short(text: str) -> str:
    return text if len(text) <= 40 else text[:37] + "..."


def _values(table: Table, bounds) -> list[float]:
    values = table.array("values")
    for i, v in enumerate(values):
        key = f"{table.key}.values[{i}]"
        check_range(key, as_number(key, v), *bounds)
    return [float(v) for v in values]


def _nu_axis(table: Table) -> tuple[float, ...]:
    if not (table.has("values") or table.has("log")):
        raise InputError("grid.nu", table.data, "has no points", "give values = [...] and/or log = {...}")
    groups = [_values(table, NU_BOUNDS)] if table.has("values") else []
    log = table.table("log", ("start", "stop", "per_decade", "num"), required=False)
    if log is not None:
        start, stop = log.number("start"), log.number("stop")
        check_range(log.path("start"), start, *NU_BOUNDS)
        check_range(log.path("stop"), stop, *NU_BOUNDS)
        if start == stop:
            raise InputError(log.path("stop"), stop, "equals start", "give two different ends")
        if log.has("per_decade") == log.has("num"):
            raise InputError(log.path("per_decade"), log.data.get("per_decade"),
                             "must be given, or num instead, but not both", "give per_decade = 4 or num = 49")
        if log.has("num"):
            num = log.integer("num", low=2, high=_RANGE_POINTS_MAX)
        else:
            num = log_count(start, stop, log.integer("per_decade", high=1000))
        groups.append(log_points(start, stop, num))
    return union(*groups)


def _nu_f_axis(table: Table) -> tuple[float, ...]:
    if not (table.has("values") or table.has("ranges")):
        raise InputError("grid.nu_f", table.data, "has no points",
                         "give values = [...] and/or ranges = [{start, stop, num}]")
    groups = [_values(table, NU_F_BOUNDS)] if table.has("values") else []
    if table.has("ranges"):
        for i, item in enumerate(table.array("ranges", fix="write ranges = [{ start = 0.05, stop = 0.95, num = 19 }]")):
            r = Table(item, f"grid.nu_f.ranges[{i}]", ("start", "stop", "num"))
            start, stop = r.number("start"), r.number("stop")
            check_range(r.path("start"), start, *NU_F_BOUNDS)
            check_range(r.path("stop"), stop, *NU_F_BOUNDS)
            if not start < stop:
                raise InputError(r.path("stop"), stop, f"is not above start = {start!r}",
                                 "give start < stop")
            groups.append(linear_points(start, stop, r.integer("num", low=2, high=_RANGE_POINTS_MAX)))
    return union(*groups)
