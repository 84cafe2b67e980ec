"""Tiles: chunk-aligned blocks of the (law, ν_f, ν) grid, the unit of work and of store writes.

A tile is one law × a block of ``tiles.nu_f`` ν_f values × ``tiles.nu`` ν values, aligned with the
store's chunks, so each tile is written by exactly one writer. ``compute_tile`` is a pure function of
the tile (the worker task): it calls ``bifurcation.slip`` on the tile's points; a worker process
compiles the law's integrator once and reuses it for every later tile (``engine._integrator`` cache).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator

import numpy as np

from .store.layout import FILL, VARIABLES

__all__ = ["OUTPUTS", "Tile", "compute_serial", "compute_tile", "iter_tiles", "tile_count"]

#: Arrays of a computed tile, in write order: the data first, ``done`` last (the store's variables).
OUTPUTS = tuple(VARIABLES)
#: The arrays ``slip`` returns per point: every output but ``done``.
_RESULTS = tuple(name for name in OUTPUTS if name != "done")


@dataclass(frozen=True, eq=False)
class Tile:
    """One block of the grid. ``index`` = (law, ν_f, ν) start indices of the block in the store.

    ``todo`` is None (compute every point) or a bool array of the tile's shape: compute only those
    points (a tile that a killed run left partly done).
    """

    law: str
    index: tuple[int, int, int]
    nu_f: tuple[float, ...]
    nu: tuple[float, ...]
    precision: str
    t_max: float
    max_steps: int
    batch: int
    todo: np.ndarray | None = None

    @property
    def shape(self) -> tuple[int, int]:
        return (len(self.nu_f), len(self.nu))

    @property
    def region(self) -> tuple[slice, slice, slice]:
        """Where the tile goes in the (law, ν_f, ν) arrays."""
        law, i, j = self.index
        return (slice(law, law + 1), slice(i, i + len(self.nu_f)), slice(j, j + len(self.nu)))

    @property
    def n_todo(self) -> int:
        return self.shape[0] * self.shape[1] if self.todo is None else int(np.count_nonzero(self.todo))

    @property
    def name(self) -> str:
        law, i, j = self.index
        return f"{law}-{i}-{j}"


def tile_count(workflow) -> int:
    """Number of tiles of ``workflow`` (whether done or not)."""
    n_law, n_nu_f, n_nu = workflow.shape
    t_nu_f, t_nu = workflow.tiles
    return n_law * -(-n_nu_f // t_nu_f) * -(-n_nu // t_nu)


def iter_tiles(workflow, done: np.ndarray | None = None) -> Iterator[Tile]:
    """The tiles of ``workflow`` that still have points to compute (all of them when ``done`` is None).

    ``done`` is the store's (law, ν_f, ν) bool mask; fully done tiles are skipped and partly done tiles
    carry a ``todo`` mask. Tiles are generated lazily, so a huge grid costs no memory up front.
    """
    t_nu_f, t_nu = workflow.tiles
    nu_f, nu = workflow.nu_f, workflow.nu
    for law_index, law in enumerate(workflow.laws):
        for i in range(0, len(nu_f), t_nu_f):
            for j in range(0, len(nu), t_nu):
                todo = None
                if done is not None:
                    block = done[law_index, i:i + t_nu_f, j:j + t_nu]
                    if block.all():
                        continue
                    if block.any():
                        todo = ~block
                yield Tile(law=law, index=(law_index, i, j), nu_f=nu_f[i:i + t_nu_f], nu=nu[j:j + t_nu],
                           precision=workflow.precision, t_max=workflow.t_max,
                           max_steps=workflow.max_steps, batch=workflow.batch, todo=todo)


def compute_tile(tile: Tile) -> dict[str, np.ndarray]:
    """Run the engine on the tile's points: a dict of ``OUTPUTS`` arrays of the tile's shape.

    Points outside ``tile.todo`` are left at the store's fill values (NaN, 0, ``done = False``).
    The values equal those of one ``slip`` call over the whole grid bit for bit: each point is an
    independent cycle of the same compiled integrator, reset per point.
    """
    from .engine.cycle import slip

    shape = tile.shape
    nu_f_grid, nu_grid = np.meshgrid(np.asarray(tile.nu_f, dtype=float), np.asarray(tile.nu, dtype=float),
                                     indexing="ij")
    mask = np.ones(shape, dtype=bool) if tile.todo is None else np.asarray(tile.todo, dtype=bool)
    out = {name: np.full(shape, FILL[name], dtype=VARIABLES[name]) for name in _RESULTS}
    out["done"] = mask.copy()
    if mask.any():
        result = slip(tile.law, nu=nu_grid[mask], nu_f=nu_f_grid[mask], precision=tile.precision,
                      t_max=tile.t_max, max_steps=tile.max_steps, batch=tile.batch)
        for name in _RESULTS:
            out[name][mask] = result[name]
    return out


def compute_serial(workflow) -> dict[str, np.ndarray]:
    """The whole grid in this process, one ``slip`` call per law: (law, ν_f, ν) arrays of ``OUTPUTS``.

    The reference a distributed run must equal bit for bit.
    """
    from .engine.cycle import slip

    nu_f, nu = np.meshgrid(np.asarray(workflow.nu_f, dtype=float), np.asarray(workflow.nu, dtype=float),
                           indexing="ij")
    results = [slip(law, nu=nu, nu_f=nu_f, precision=workflow.precision, t_max=workflow.t_max,
                    max_steps=workflow.max_steps, batch=workflow.batch) for law in workflow.laws]
    out = {name: np.stack([r[name] for r in results]) for name in _RESULTS}
    out["done"] = np.ones(workflow.shape, dtype=bool)
    return out
