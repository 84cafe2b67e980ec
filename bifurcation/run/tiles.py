"""Tiles: chunk-aligned blocks of a study's grid (labels × the model's axes), the unit of work and of
store writes.

A tile is one label (law) × a block of ``tiles.<axis>`` values along each axis of the model, aligned
with the store's chunks, so each tile is written by exactly one writer. ``compute_tile`` is a pure
function of the tile (the worker task): it runs the engine on the tile's points; a worker process
compiles the law's integrator once and reuses it for every later tile (``engine._integrator`` cache).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Iterator

import numpy as np

from ..models import DEFAULT_MODEL, get_model
from ..store.layout import VARIABLES, fills, variables

__all__ = ["OUTPUTS", "Tile", "compute_serial", "compute_tile", "iter_tiles", "tile_count"]

#: Arrays of a computed tile of the single block, in write order: the data first, ``done`` last.
OUTPUTS = tuple(VARIABLES)


@dataclass(frozen=True, eq=False)
class Tile:
    """One block of the grid. ``index`` = (label, *axis) start indices of the block in the store.

    ``axes`` holds ``(axis name, values)`` per axis of the model. ``todo`` is None (compute every
    point) or a bool array of the tile's shape: compute only those points (a tile that a killed run
    left partly done).
    """

    law: str
    index: tuple[int, ...]
    axes: tuple
    precision: str
    t_max: float
    max_steps: int
    batch: int
    todo: np.ndarray | None = None
    model: str = DEFAULT_MODEL

    def __getattr__(self, name: str):
        for axis, values in self.__dict__.get("axes", ()):
            if axis == name:
                return values
        raise AttributeError(f"'Tile' object has no attribute {name!r}")

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(values) for _, values in self.axes)

    @property
    def region(self) -> tuple[slice, ...]:
        """Where the tile goes in the (label, *axes) arrays."""
        law, *starts = self.index
        return (slice(law, law + 1), *(slice(s, s + n) for s, n in zip(starts, self.shape)))

    @property
    def n_todo(self) -> int:
        return math.prod(self.shape) if self.todo is None else int(np.count_nonzero(self.todo))

    @property
    def name(self) -> str:
        return "-".join(str(i) for i in self.index)


def tile_count(workflow) -> int:
    """Number of tiles of ``workflow`` (whether done or not)."""
    n_law, *sizes = workflow.shape
    return n_law * math.prod(-(-n // t) for n, t in zip(sizes, workflow.tiles))


def iter_tiles(workflow, done: np.ndarray | None = None) -> Iterator[Tile]:
    """The tiles of ``workflow`` that still have points to compute (all of them when ``done`` is None).

    ``done`` is the store's (label, *axes) bool mask; fully done tiles are skipped and partly done
    tiles carry a ``todo`` mask. Tiles are generated lazily, so a huge grid costs no memory up front.
    """
    grid = workflow.grid
    starts = [range(0, len(values), size) for (_, values), size in zip(grid, workflow.tiles)]
    for law_index, law in enumerate(workflow.laws):
        for corner in itertools.product(*starts):
            block = tuple(slice(s, s + size) for s, size in zip(corner, workflow.tiles))
            todo = None
            if done is not None:
                mask = done[(law_index, *block)]
                if mask.all():
                    continue
                if mask.any():
                    todo = ~mask
            yield Tile(law=law, index=(law_index, *corner),
                       axes=tuple((name, values[b]) for (name, values), b in zip(grid, block)),
                       precision=workflow.precision, t_max=workflow.t_max, max_steps=workflow.max_steps,
                       batch=workflow.batch, todo=todo, model=workflow.model)


def _points(axes) -> dict[str, np.ndarray]:
    """Axis name → values at every point of the block (``indexing="ij"``: the store's C order)."""
    grids = np.meshgrid(*(np.asarray(values, dtype=float) for _, values in axes), indexing="ij")
    return {name: g for (name, _), g in zip(axes, grids)}


def compute_tile(tile: Tile, checkpoints=None) -> dict[str, np.ndarray]:
    """Run the engine on the tile's points: a dict of the store's variables, each of the tile's shape.

    Points outside ``tile.todo`` are left at the store's fill values (NaN, 0, ``done = False``).
    The values equal those of one engine call over the whole grid bit for bit: each point is an
    independent run of the same compiled integrator, reset per point.
    """
    from ..engine.solve import solve

    model = get_model(tile.model)
    shape = tile.shape
    points = _points(tile.axes)
    mask = np.ones(shape, dtype=bool) if tile.todo is None else np.asarray(tile.todo, dtype=bool)
    kinds, fill = variables(model), fills(model)
    out = {name: np.full(shape, fill[name], dtype=kinds[name]) for name in kinds if name != "done"}
    for output in model.catalog_outputs:   # per-event outputs: one array per run (store.catalog)
        out[output.name] = np.empty(shape, dtype=object)
        out[output.name].fill(np.empty(0, dtype=output.dtype))
    out["done"] = mask.copy()
    if mask.any():
        result = solve(model, tile.law, {k: v[mask] for k, v in points.items()}, precision=tile.precision,
                       t_max=tile.t_max, max_steps=tile.max_steps, batch=tile.batch, checkpoints=checkpoints)
        for name in out:
            if name != "done":
                out[name][mask] = result[name]
    return out


def compute_serial(workflow) -> dict[str, np.ndarray]:
    """The whole grid in this process, one engine call per law: (label, *axes) arrays of the store's
    variables. The reference a distributed run must equal bit for bit."""
    from ..engine.solve import solve

    model = workflow.spec
    points = _points(workflow.grid)
    results = [solve(model, law, points, precision=workflow.precision, t_max=workflow.t_max,
                     max_steps=workflow.max_steps, batch=workflow.batch) for law in workflow.laws]
    names = [*(n for n in variables(model) if n != "done"), *(o.name for o in model.catalog_outputs)]
    out = {name: np.stack([np.asarray(r[name]) for r in results]) for name in names}
    out["done"] = np.ones(workflow.shape, dtype=bool)
    return out
