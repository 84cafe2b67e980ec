r"""Workflows: a study over a model's grid (labels × its axes), written as a TOML file.

The model (``[model] name``, default ``single-block``) declares the axes: one ``[grid.<axis>]`` table
per axis (an axis with a ``default`` may be left out: its one point is that default) and one
``[tiles]`` key per axis, with the bounds the model declares. The schema below is
the single block's (axes ``nu_f`` and ``nu``); ``bifurcation.models.get_model(name).axes`` lists
another model's.

Schema (every key is checked; unknown keys, wrong types and impossible values are refused with an
``InputError`` naming the dotted key, e.g. ``grid.nu.log.per_decade``)::

    [study]
    name = "critical-point"          # required; letters, digits, . _ -  (default store results/<name>.zarr)
    description = "..."              # optional

    [model]                          # optional
    name = "single-block"            # a name of bifurcation.models.model_names()

    [engine]
    laws = ["piecewise-linear", "carlson-langer"]   # required; names of bifurcation.law_names()
                                     # or formulas in x ("exp(-x)"); each is checked with resolve_law
    precision = "double"             # optional: "double" (default) or "quad"
    t_max = 1e5                      # optional: bound on the time of one cycle (> 0)
    max_steps = 200000               # optional: bound on the Taylor steps of one cycle (>= 1)
    batch = 8                        # optional: heyoka SIMD lanes (1..64, double only; default 1)
                                     # (rs-chain too: a tile's chains of one structure in
                                     # lanes, tiles of several points; docs/rs-chain.md)

    [grid.nu]                        # pulling speed ν of Eq. (5); at least one of values / ranges / log
    values = [1e-9]                  # explicit points, kept exactly as written
    log = { start = 1e-3, stop = 1e-15, per_decade = 4 }   # or num = 49 instead of per_decade

    [grid.nu_f]                      # friction velocity ν_f of Eq. (2)
    values = [0.2, 0.3, 0.4, 0.5]
    ranges = [{ start = 0.45, stop = 0.55, num = 101 }]    # evenly spaced, both ends included

    [tiles]                          # optional: tile (= store chunk) shape, default 64 × 64
    nu_f = 64
    nu = 64
    catalog = 1000                   # models with per-event outputs (the chain) only: events per
                                     # catalog chunk and per checkpoint (bifurcation.store.catalog)

Each axis is the sorted union of its points with exact duplicates removed. Range and log points are
computed in decimal arithmetic and rounded once, so a range that passes through 0.4 yields exactly
``0.4`` (the float a user types) and a log axis from 1e-3 to 1e-15 passes through exactly 1e-9. A log
axis has at least ``per_decade`` points per decade and always includes both ends.

Bounds come from the model's axes (for the single block the one set of ``bifurcation.bounds``:
ν ∈ [1e-20, 1], ν_f ∈ [1e-4, 10]); ``max_steps`` ≤ 10^7, ``t_max`` ≤ 1e9; tiles of 1 … 4096 points a
side and at most 2^16 points, at most 10^9 points in a grid.

Two workflows are the *same study* when their ``fingerprint`` agrees: the sha256 of what determines
the numbers and the store layout (model, laws, precision, bounds, grid, tiles) — not of the text, so comments,
formatting, the name and the description may change without invalidating a store.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from ..bounds import NU_BOUNDS, NU_F_BOUNDS, check_max_steps, check_t_max
from ..engine._validate import PRECISIONS, check_batch, check_precision
from ..outcome import DEFAULT_MAX_STEPS, DEFAULT_T_MAX
from ..errors import InputError
from ..models import DEFAULT_MODEL, get_model
from ._axes import linear_points, log_count, log_points, union
from ._limits import MAX_POINTS, check_declared_size
from .validate import Table, as_number, check_range

__all__ = ["MAX_POINTS", "NU_BOUNDS", "NU_F_BOUNDS", "PRECISIONS", "TILE_MAX", "TILE_MAX_POINTS",
           "Workflow", "load_workflow", "parse_workflow"]

TILE_MAX = 4096
TILE_MAX_POINTS = 1 << 16
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
_NAME_MAX = 100
#: Most points of one log or linear range (``num``): a typo such as 1e9 is refused, not allocated.
_RANGE_POINTS_MAX = 100_000
#: Most SIMD lanes: far above any vector unit's width (AVX-512 holds 8 doubles); more is a typo.
_BATCH_MAX = 64
_ENGINE_KEYS = ("precision", "t_max", "max_steps", "batch")
#: Events per chunk of a run's catalog and per checkpoint (models with per-event outputs: ``[tiles]
#: catalog = C``; bifurcation.store.catalog).
CATALOG_CHUNK = 1000
_CATALOG_CHUNK_MAX = 1 << 20


def _set(obj, name, value) -> None:
    object.__setattr__(obj, name, value)


@dataclass(frozen=True, init=False)
class Workflow:
    """A validated study: labels (laws) × the model's axes, engine options and the tile (chunk) shape.

    Build one with ``load_workflow(path)``, ``parse_workflow(text)`` or directly, giving each axis of
    the model as a keyword (``Workflow(name="s", laws=["carlson-langer"], nu=[1e-9], nu_f=[0.4])``;
    any sequences, sorted and deduplicated) or as ``grid={"nu": [...], ...}``. Axis points are
    attributes (``w.nu``); ``w.grid`` holds them as ``((axis, points), ...)`` in the model's order.
    ``tiles`` is a tuple in axis order or a mapping axis → size. Checked on construction.
    """

    name: str
    laws: tuple[str, ...]
    grid: tuple
    model: str = DEFAULT_MODEL
    description: str = ""
    precision: str = "double"
    t_max: float = DEFAULT_T_MAX
    max_steps: int = DEFAULT_MAX_STEPS
    batch: int = 1                           # heyoka SIMD lanes (see bifurcation.slip)
    tiles: tuple = ()                        # chunk shape, one size per axis
    catalog_chunk: int = 0                   # events per catalog chunk and checkpoint (0: no catalogs)
    source: str | None = field(default=None, compare=False, repr=False)

    def __init__(self, name, laws, *, model=None, grid=None, description="", precision="double",
                 t_max=DEFAULT_T_MAX, max_steps=DEFAULT_MAX_STEPS, batch=1, tiles=None, source=None,
                 catalog_chunk=None, **axes) -> None:
        spec = _solvable(get_model(model))
        points = dict(grid or {})
        for key, value in axes.items():
            if key in points:
                raise InputError(f"grid.{key}", value, "is given twice", "give each axis once")
            points[key] = value
        for key in points:
            if key not in spec.dims[1:]:
                raise InputError(f"grid.{key}", points[key], f"is not an axis of model {spec.name!r}",
                                 f"give the axes {', '.join(spec.dims[1:])}")
        for k, v in (("name", name), ("laws", laws), ("model", spec.name), ("description", description),
                     ("precision", precision), ("t_max", t_max), ("max_steps", max_steps), ("batch", batch),
                     ("source", source)):
            _set(self, k, v)
        self._check(spec, points, tiles)
        _set(self, "catalog_chunk", _check_catalog_chunk(spec, catalog_chunk))
        if self.batch != 1 and spec.runner is not None:
            _check_runner_batch(self, spec)

    def _check(self, spec, points, tiles) -> None:
        if not isinstance(self.name, str) or not _NAME.match(self.name):
            raise InputError("study.name", self.name, "is not a valid study name",
                             "use letters, digits, '.', '_' and '-' (it names the default store)")
        if len(self.name) > _NAME_MAX:   # results/<name>.zarr must fit a file name (255 bytes)
            raise InputError("study.name", f"{self.name[:20]}...", f"has {len(self.name)} characters",
                             f"use at most {_NAME_MAX} characters (it names the default store)")
        if not isinstance(self.description, str):
            raise InputError("study.description", self.description, "is not a string", "write it in quotes")
        _set(self, "laws", _check_labels(spec, self.laws))
        _engine_check("engine.precision", check_precision, self.precision)
        _set(self, "t_max", check_t_max("engine.t_max", as_number("engine.t_max", self.t_max)))
        check_max_steps("engine.max_steps", self.max_steps)
        _set(self, "batch", _engine_check("engine.batch", check_batch, self.batch, self.precision))
        if self.batch > _BATCH_MAX:
            raise InputError("engine.batch", self.batch, f"is more than {_BATCH_MAX} lanes",
                             "give e.g. batch = 8 (SIMD lanes), or leave it out for 1")
        if self.batch != 1 and spec.runner is not None and not spec.batch_revision:   # its runner ignores it
            raise InputError("engine.batch", self.batch, f"does not apply to model {spec.name!r}: its runner "
                             "integrates one run at a time (one lane), and the batch would only change the "
                             "store's fingerprint", "leave batch out (SIMD batches are the single block's)")
        grid = []
        for axis in spec.axes:
            if axis.name not in points and axis.default is not None:
                points[axis.name] = (axis.default,)
            if axis.name not in points:
                raise InputError(f"grid.{axis.name}", None, "is missing",
                                 f"add a table [grid.{axis.name}] ({axis.long_name})")
            grid.append((axis.name, _check_axis(f"grid.{axis.name}", points[axis.name], axis)))
        _set(self, "grid", tuple(grid))
        if (check_grid := spec.hook("check_grid")) is not None:   # the model's bounds across axes
            check_grid(self)
        _set(self, "tiles", _check_tiles(spec, tiles))
        if self.n_points > MAX_POINTS:
            raise InputError("grid", self.shape, f"has {self.n_points} points, more than {MAX_POINTS}",
                             "split the study into several workflows")

    def __getattr__(self, name: str):
        # the axes as attributes (w.nu, w.nu_f), and the labels by their dimension name (w.law);
        # only called for names that are not fields
        grid = self.__dict__.get("grid", ())
        for axis, values in grid:
            if axis == name:
                return values
        if "model" in self.__dict__ and name == get_model(self.__dict__["model"]).labels.name:
            return self.__dict__["laws"]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    # -- derived -------------------------------------------------------------------------------
    @property
    def spec(self):
        """The ``bifurcation.models.Model`` of this study."""
        return get_model(self.model)

    @property
    def axes(self) -> dict:
        """Axis name → points, in the model's order."""
        return dict(self.grid)

    @property
    def shape(self) -> tuple[int, ...]:
        """(laws, *axes): the shape of the store's arrays."""
        return (len(self.laws), *(len(values) for _, values in self.grid))

    @property
    def n_points(self) -> int:
        return math.prod(self.shape)

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
                         max_steps=self.max_steps, tiles=list(self.tiles),
                         **{axis: [repr(x) for x in values] for axis, values in self.grid})
        if self.batch != 1:  # batch results equal scalar ones to rounding only; 1 keeps old fingerprints
            canonical["batch"] = self.batch
            # Revision 2: maxima and t1 became terminal events in batch mode (the scalar loop's steps), which
            # moved last bits; an older batch store must not be resumed with tiles of the new revision.
            canonical["batch_revision"] = 2 if self.spec.runner is None else f"{self.model}:{self.spec.batch_revision}"
        if self.model != DEFAULT_MODEL:   # the single block's stores predate models: keep their prints
            canonical["model"] = self.model
        if self.catalog_chunk:
            canonical["catalog_chunk"] = self.catalog_chunk
        if (revision := self.spec.revision):   # the model's engine revision (Model.revision)
            canonical["engine_revision"] = revision
        return hashlib.sha256(json.dumps(canonical, sort_keys=True).encode()).hexdigest()

    @property
    def default_store(self) -> Path:
        return Path("results") / f"{self.name}.zarr"

    def to_toml(self) -> str:
        """A TOML text that ``parse_workflow`` turns back into this workflow (explicit values)."""
        def floats(xs):
            return "[" + ", ".join(repr(x) for x in xs) + "]"

        lines = ["[study]", f"name = {json.dumps(self.name)}",
                 f"description = {json.dumps(self.description, ensure_ascii=False)}", ""]
        if self.model != DEFAULT_MODEL:
            lines += ["[model]", f"name = {json.dumps(self.model)}", ""]
        key = self.spec.labels.workflow_key
        lines += ["[engine]",
                  f"{key} = [" + ", ".join(json.dumps(law, ensure_ascii=False) for law in self.laws) + "]",
                  f"precision = {json.dumps(self.precision)}", f"t_max = {self.t_max!r}",
                  f"max_steps = {self.max_steps}", f"batch = {self.batch}", ""]
        for axis, values in self.grid:
            lines += [f"[grid.{axis}]", f"values = {floats(values)}", ""]
        lines += ["[tiles]", *(f"{axis} = {size}" for (axis, _), size in zip(self.grid, self.tiles))]
        lines += [f"catalog = {self.catalog_chunk}", ""] if self.catalog_chunk else [""]
        return "\n".join(lines)


def _check_runner_batch(workflow, spec) -> None:
    """``[engine] batch`` of a runner model that batches (``Model.batch_revision``): its lanes are a tile's
    points, so a tile of one point would only change the fingerprint."""
    if math.prod(min(size, len(values)) for size, (_, values) in zip(workflow.tiles, workflow.grid)) < 2:
        raise InputError("engine.batch", workflow.batch, "has no lanes to fill: a tile holds one point and the "
                         "batch runs a tile's points together", "give [tiles] with several points of one "
                         "structure, e.g. seed = 4, or leave batch out")
    if (check_batch := spec.hook("check_batch")) is not None:   # the model's own notion of a lane's fellows
        check_batch(workflow)


def _solvable(spec):
    """``spec``, unless its stores are written whole by its own command (rate-state's branches of cycles)."""
    if spec.written_by:
        raise InputError("model.name", spec.name, f"is the store of `bifurcation {spec.written_by}`, not a model "
                         "of a study grid", "name a model whose points are solved one by one, e.g. rate-state")
    return spec


def _engine_check(key: str, check, value, *args):
    """``check(value, *args)`` (a ``bifurcation.engine`` check), its error naming the workflow ``key``."""
    try:
        return check(value, *args)
    except InputError as exc:
        raise InputError(key, value, exc.problem, exc.fix) from None


def _check_labels(spec, laws) -> tuple[str, ...]:
    labels = spec.labels
    key = f"engine.{labels.workflow_key}"
    if isinstance(laws, str) or not laws:
        raise InputError(key, laws, f"is not a non-empty list of {labels.workflow_key}",
                         f"write {labels.workflow_key} = [\"{labels.example}\"]")
    out, seen = [], {}
    for i, law in enumerate(laws):
        item = f"{key}[{i}]"
        if not isinstance(law, str):
            raise InputError(item, law, "is not a string", "write a law name or formula in quotes")
        try:
            labels.resolve(law)
            identity = labels.identity(law)
        except InputError as exc:
            raise InputError(item, law, exc.problem, exc.fix) from None
        if identity in seen:
            first = laws[seen[identity]]
            same = "" if first.strip() == law.strip() else f" ({first!r} is the same law Φ)"
            raise InputError(item, law, f"repeats {key}[{seen[identity]}]{same}", "list each one once")
        seen[identity] = i
        out.append(law.strip())
    return tuple(out)


def _check_axis(key: str, values, axis) -> tuple:
    if isinstance(values, (str, bytes, Mapping)):
        raise InputError(key, values, "is not a sequence of numbers", "give a list of numbers")
    try:
        points = [as_number(key, v) for v in values]
    except TypeError:
        raise InputError(key, values, "is not a sequence of numbers", "give a list of numbers") from None
    if not points:
        raise InputError(key, [], "is empty", "give at least one point")
    for x in points:
        check_range(key, x, *axis.bounds)
        if axis.dtype == "int64" and x != int(x):
            raise InputError(key, x, "is not a whole number", f"give whole numbers for {axis.symbol}")
    out = union(points)
    return tuple(int(x) for x in out) if axis.dtype == "int64" else out


def _check_catalog_chunk(spec, size) -> int:
    """``[tiles] catalog``: events per chunk of a run's catalog (models with per-event outputs only)."""
    if not spec.catalog_outputs:
        if size is not None:
            raise InputError("tiles.catalog", size, f"is not a key of model {spec.name!r} (it has no catalogs)",
                             "leave it out")
        return 0
    if size is None:
        return CATALOG_CHUNK
    if isinstance(size, bool) or not isinstance(size, int):
        raise InputError("tiles.catalog", size, "is not an integer", f"give a whole number such as {CATALOG_CHUNK}")
    check_range("tiles.catalog", size, 1, _CATALOG_CHUNK_MAX)
    return size


def _check_tiles(spec, tiles) -> tuple[int, ...]:
    names = [a.name for a in spec.axes]
    if tiles is None:
        tiles = tuple(a.default_tile for a in spec.axes)
    elif isinstance(tiles, Mapping):
        unknown = [k for k in tiles if k not in names]
        if unknown:
            raise InputError(f"tiles.{unknown[0]}", tiles[unknown[0]], "is not an axis of the model",
                             f"use only {', '.join(names)} in [tiles]")
        tiles = tuple(tiles.get(a.name, a.default_tile) for a in spec.axes)
    tiles = tuple(tiles)
    if len(tiles) != len(names):
        raise InputError("tiles", tiles, f"is not a ({', '.join(names)}) tuple", f"give {len(names)} tile sizes")
    for name, size in zip(names, tiles):
        if isinstance(size, bool) or not isinstance(size, int):
            raise InputError(f"tiles.{name}", size, "is not an integer", "give a whole number such as 64")
        check_range(f"tiles.{name}", size, 1, TILE_MAX)
    if math.prod(tiles) > TILE_MAX_POINTS:
        raise InputError("tiles", " x ".join(map(str, tiles)), f"has more than {TILE_MAX_POINTS} points",
                         "use smaller tiles so that one task stays small in memory")
    return tiles


# -- TOML ------------------------------------------------------------------------------------------
def parse_workflow(text: str, *, source: str | None = None) -> Workflow:
    """The ``Workflow`` written in TOML ``text`` (schema in the module docstring).

    ``source`` (the file name) is only used in error messages.
    """
    from .validate import SUBMIT, other_command, parse_toml

    where = source if source is not None else _short(text)
    data = parse_toml(text, "workflow", where, "workflows/*.toml")
    other_command(data, SUBMIT, "workflow", where)
    root = Table(data, "", ("study", "model", "engine", "grid", "tiles"), source=source)
    check_declared_size(data)   # before any point is made
    study = root.table("study", ("name", "description"))
    model_table = root.table("model", ("name", "preset"), required=False)
    model_name = model_table.string("name", DEFAULT_MODEL) if model_table is not None else DEFAULT_MODEL
    try:
        spec = get_model(model_name)
    except InputError as exc:
        raise InputError("model.name", model_name, exc.problem, exc.fix) from None
    _solvable(spec)   # before its grid tables are read
    preset_points, preset_laws = _preset(model_table, spec)
    key = spec.labels.workflow_key
    axis_names = tuple(a.name for a in spec.axes)
    engine = root.table("engine", (key, *_ENGINE_KEYS), required=not preset_laws)
    grid = root.table("grid", axis_names)
    tile_keys = (*axis_names, "catalog") if spec.catalog_outputs else axis_names
    tiles = root.table("tiles", tile_keys, required=False)

    laws = engine.array(key, *preset_laws, fix=f"write {key} = [\"{spec.labels.example}\"]") \
        if engine is not None else preset_laws[0]
    # Workflow checks the engine options and tiles (with the same dotted keys) on construction
    options = {name: engine.raw(name) for name in _ENGINE_KEYS if engine is not None and engine.has(name)}
    if tiles is not None:
        options["tiles"] = {name: tiles.raw(name) for name in axis_names if tiles.has(name)}
        if tiles.has("catalog"):
            options["catalog_chunk"] = tiles.raw("catalog")
    # an axis with a default may be left out (Workflow takes its one default point)
    tables = {axis: grid.table(axis.name, ("values", "ranges", "log"),
                               required=axis.default is None and axis.name not in preset_points)
              for axis in spec.axes}
    axes = {axis.name: _axis_points(table, axis) for axis, table in tables.items() if table is not None}
    for name, value in preset_points.items():     # a preset fills the axes the grid leaves out
        axes.setdefault(name, (value,))
    return Workflow(
        name=study.string("name", fix="add name = \"my-study\" to [study]"),
        description=study.string("description", ""),
        laws=tuple(laws),
        model=spec.name,
        grid=axes,
        source=text,
        **options,
    )


def _preset(model_table, spec) -> tuple[dict, tuple]:
    """``[model] preset = "NAME"``: the preset's axis values and label, from the model's ``presets`` hook."""
    if model_table is None or not model_table.has("preset"):
        return {}, ()
    name = model_table.string("preset")
    lookup = spec.hook("presets")
    if lookup is None:
        raise InputError("model.preset", name, f"is not available for the model {spec.name!r}",
                         "presets are published parameter sets of the models that declare them "
                         "(bifurcation chain --help lists the chain's): use [model] name = \"chain\"")
    try:
        return lookup(name)
    except InputError as exc:
        raise InputError("model.preset", name, exc.problem, exc.fix) from None


def load_workflow(path) -> Workflow:
    """The ``Workflow`` of the TOML file at ``path``."""
    from .validate import read_workflow_text

    text = read_workflow_text(path, "workflow", "workflows/paper-fig2.toml")
    return parse_workflow(text, source=str(path))


def _short(text: str) -> str:
    return text if len(text) <= 40 else text[:37] + "..."


def _value_fix(axis) -> str:
    """What to write for a value of ``axis`` that is not a number: its words' numbers for a choice axis (a
    chain's ends: 0 free, 1 periodic), a whole number for a count, else a number of its scale."""
    if axis.names:
        return "write " + " or ".join(f"{i} ({word})" for i, word in enumerate(axis.names)) + " (no quotes)"
    if axis.dtype == "int64":
        return f"write a whole number such as {axis.cast(axis.example)} (no quotes)"
    return ""   # as_number's own: a number such as 0.4 or 1e-9


def _values(table: Table, axis) -> list[float]:
    values = table.array("values")
    for i, v in enumerate(values):
        key = f"{table.key}.values[{i}]"
        check_range(key, as_number(key, v, _value_fix(axis)), *axis.bounds)
    return [float(v) for v in values]


def _axis_points(table: Table, axis) -> tuple[float, ...]:
    """The points of ``[grid.<axis>]``: the union of ``values``, linear ``ranges`` and one ``log``."""
    if not any(table.has(k) for k in ("values", "ranges", "log")):
        raise InputError(table.key, table.data, "has no points",
                         "give values = [...], ranges = [{ start, stop, num }] and/or "
                         "log = { start, stop, per_decade }")
    bounds = axis.bounds
    groups = [_values(table, axis)] if table.has("values") else []
    if table.has("ranges"):
        for r in table.tables("ranges", ("start", "stop", "num"),
                              fix="write ranges = [{ start = 0.05, stop = 0.95, num = 19 }]"):
            start, stop = r.number("start", low=bounds[0], high=bounds[1]), r.number("stop", low=bounds[0],
                                                                                     high=bounds[1])
            if not start < stop:
                raise InputError(r.path("stop"), stop, f"is not above start = {start!r}", "give start < stop")
            groups.append(linear_points(start, stop, r.integer("num", low=2, high=_RANGE_POINTS_MAX)))
    log = table.table("log", ("start", "stop", "per_decade", "num"), required=False)
    if log is not None:
        start, stop = log.number("start", low=bounds[0], high=bounds[1]), log.number("stop", low=bounds[0],
                                                                                      high=bounds[1])
        for end, value in (("start", start), ("stop", stop)):
            if value <= 0:
                raise InputError(log.path(end), value, "is not > 0", "a log axis needs positive ends")
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
