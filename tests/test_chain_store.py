"""Chain studies through the model layer and the store (issue 10, "Studies"; docs/chain.md).

The chain is a registered model whose per-event outputs are ragged catalogs in the study's Zarr store:
each run's events in chunks of C that only its own task writes, read back one run at a time, covered by
the CRC and `bifurcation verify`, and checkpointed every C events so that a run whose worker was killed
(-9, a real `dask worker`) resumes from its last checkpoint with a catalog bit-identical to an
uninterrupted run. Tiny chains, few events: the whole module takes seconds, the kill test ~20 s.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli
from bifurcation.models import get_model
from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles
from bifurcation.store import create_store, open_store, write_tile
from bifurcation.store.catalog import read_catalog, tile_checkpoints
from bifurcation.workflow import parse_workflow

CATALOG = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")

WORKFLOW = textwrap.dedent("""
    [study]
    name = "chain-store-test"
    [model]
    name = "chain"
    [engine]
    laws = ["carlson-langer", "piecewise-linear"]
    [grid.n]
    values = [1, 6]
    [grid.ell]
    values = [1.0]
    [grid.nu]
    values = [1e-3]
    [grid.nu_f]
    values = [0.3, 0.45]
    [grid.amplitude]
    values = [0.5]
    [grid.seed]
    values = [2]
    [grid.events]
    values = [12, 30]
    [grid.periodic]
    values = [0, 1]
    [tiles]
    nu_f = 2
    catalog = 8
    """)


def _bits(a) -> np.ndarray:
    a = np.asarray(a)
    return a.view(np.int64) if a.dtype.kind == "f" else a


def assert_same(a, b, what="") -> None:
    """Bit for bit, NaN payloads included."""
    assert np.asarray(a).dtype == np.asarray(b).dtype, what
    np.testing.assert_array_equal(_bits(a), _bits(b), err_msg=what)


@pytest.fixture(scope="module")
def workflow():
    return parse_workflow(WORKFLOW)


@pytest.fixture(scope="module")
def serial(workflow):
    return compute_serial(workflow)


@pytest.fixture(scope="module")
def store(workflow, tmp_path_factory):
    path = tmp_path_factory.mktemp("chain") / "chain.zarr"
    run_id = create_store(path, workflow)["run_id"]
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile, tile_checkpoints(path, run_id, tile)), run_id)
    return path


def test_the_chain_is_a_registered_model_with_catalog_outputs():
    model = get_model("chain")
    assert model.dims == ("law", "n", "ell", "nu", "nu_f", "amplitude", "seed", "events", "periodic")
    assert [o.name for o in model.catalog_outputs] == list(CATALOG)
    assert model.checkpoint and model.runner is not None and model.axis("n").structural
    assert model.catalog_size == "events" and model.catalog_count == "events_done"


def test_a_run_of_the_model_is_bifurcation_chain_bit_for_bit(serial, workflow):
    # the store's runner against the public API (one ChainLoop.run(K) call, no checkpoints)
    for law_i, law in enumerate(workflow.laws):
        for index in [(1, 0, 0, 0, 0, 0, 1, 1), (1, 0, 0, 1, 0, 0, 0, 0), (0, 0, 0, 0, 0, 0, 1, 0)]:
            p = {name: values[i] for (name, values), i in zip(workflow.grid, index)}
            ref = bf.chain(law, n=p["n"], ell=p["ell"], nu=p["nu"], nu_f=p["nu_f"], amplitude=p["amplitude"],
                           seed=p["seed"], events=p["events"], ends="periodic" if p["periodic"] else "free",
                           t_max=workflow.t_max, max_steps=workflow.max_steps)
            at = (law_i, *index)
            for name in CATALOG:
                assert_same(serial[name][at], ref[name], name)
            assert serial["events_done"][at] == ref.events == p["events"]
            assert_same(serial["t_end"][at], np.float64(ref.t), "t_end")
            assert serial["steps"][at] == ref.steps.sum()


def test_the_store_equals_the_serial_engine_bit_for_bit(store, serial, workflow):
    ds = open_store(store)
    for name in ("status", "events_done", "t_end", "steps", "resumed", "done"):
        assert_same(ds[name].values, serial[name], name)
    assert np.all(serial["status"] == 1)   # complete
    # the whole catalog arrays, sliced by the layout (offset r·capacity, count events_done) ...
    import zarr

    group = zarr.open_group(str(store), mode="r")
    assert dict(group["catalog"].attrs)["events_per_run"] == 32   # ceil(30 / 8)·8
    arrays = {name: group["catalog"][name][...] for name in CATALOG}
    for run, index in enumerate(np.ndindex(workflow.shape)):
        count = int(serial["events_done"][index])
        for name in CATALOG:
            assert_same(arrays[name][run * 32:run * 32 + count], serial[name][index], name)
            assert np.all(_bits(arrays[name][run * 32 + count:(run + 1) * 32])
                          == _bits(np.full(32 - count, group["catalog"][name].fill_value)))
    # ... and through the query API, a few runs
    for index in [(0, 1, 0, 0, 1, 0, 0, 1, 1), (1, 0, 0, 0, 0, 0, 0, 0, 0)]:
        p = {d: (workflow.laws if d == "law" else workflow.axes[d])[i] for d, i in zip(get_model("chain").dims, index)}
        cat = read_catalog(store, law=p.pop("law"), **p)
        assert cat["run"]["events_done"] == p["events"] and cat["run"]["status"] == "complete"
        for name in CATALOG:
            assert_same(cat[name], serial[name][index], name)


def test_one_runs_query_reads_only_its_own_chunks(store, workflow, monkeypatch):
    """Every key the store is asked for while one run's catalog is read: its catalog chunks, its tile of
    per-run outputs and metadata — never another run's catalog chunk."""
    from zarr.storage import LocalStore

    seen = []
    original = LocalStore.get

    async def spy(self, key, *args, **kwargs):
        seen.append(key)
        return await original(self, key, *args, **kwargs)

    monkeypatch.setattr(LocalStore, "get", spy)
    cat = read_catalog(store, law="piecewise-linear", n=6, nu_f=0.3, seed=2, events=30, periodic=1)
    monkeypatch.undo()
    run = int(np.ravel_multi_index((1, 1, 0, 0, 0, 0, 0, 1, 1), workflow.shape))
    capacity, chunk = 32, 8      # ceil(30/8)·8; C = [tiles] catalog
    own = {f"catalog/{name}/c/{run * capacity // chunk + k}" for name in CATALOG for k in range(4)}
    catalog_keys = {k for k in seen if k.startswith("catalog/") and not k.endswith("zarr.json")}
    assert catalog_keys == own and len(cat["potency"]) == 30
    data_keys = {k for k in seen if "/c/" in k and not k.startswith("catalog/")}
    # per-run outputs: one chunk (its tile) per variable, plus the coordinates
    assert all(k.split("/")[0] in get_model("chain").dims or k.endswith("/c/1/1/0/0/0/0/0/1/1")
               for k in data_keys), data_keys
    read = sum((store / k).stat().st_size for k in own)
    total = sum(p.stat().st_size for p in (store / "catalog").rglob("*") if p.is_file())
    assert read < total / 20


def test_checkpoint_snapshot_restore_is_bit_identical():
    """Run 17 events, snapshot through bytes, restore into a fresh loop, run 23 more: the same 40 events
    and final state as one uninterrupted run (piecewise-linear, so the friction switch is crossed)."""
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._loop import ChainLoop
    from bifurcation.models.chain._validate import check_initial
    from bifurcation.models.chain.checkpoint import restore, snapshot

    law = resolve_law("piecewise-linear")
    u = check_initial(6, 1.2, "periodic", None, 0.7, 5)

    def loop():
        return ChainLoop(law, 6, 1.2, 1e-4, 0.25, "periodic", u)

    whole = loop().run(40)["catalog"]
    first = loop()
    a = first.run(17)["catalog"]
    blob = {k: np.ascontiguousarray(v).tobytes() for k, v in snapshot(first).items()}
    second = loop()
    restore(second, blob)
    b = second.run(23)["catalog"]
    for name in CATALOG:
        assert_same(np.array(a[name] + b[name]), np.array(whole[name]), name)
    assert max(whole["n_blocks"]) > 1          # events of several blocks are in the interrupted stretch
    with pytest.raises(RuntimeError, match="between events"):
        second.slipping[0] = True
        snapshot(second)


def test_a_run_killed_between_checkpoints_resumes_bit_identical(workflow, serial, tmp_path, monkeypatch):
    """In process: the task dies (an exception) after its 2nd checkpoint of a 30-event run (C = 8); the
    recomputed tile restores 16 events and its catalog equals the uninterrupted run's."""
    from bifurcation.store.catalog import Checkpoints

    path = tmp_path / "ck.zarr"
    run_id = create_store(path, workflow)["run_id"]
    tile = next(t for t in iter_tiles(workflow) if t.index == (0, 1, 0, 0, 0, 0, 0, 1, 0))
    calls = []
    original = Checkpoints.save

    def dying(self, i, *args, **kwargs):
        original(self, i, *args, **kwargs)
        calls.append(i)
        if calls.count(0) == 2:
            raise KeyboardInterrupt("killed")   # not an Exception: nothing catches it on the way out

    monkeypatch.setattr(Checkpoints, "save", dying)
    with pytest.raises(KeyboardInterrupt):
        compute_tile(tile, tile_checkpoints(path, run_id, tile))
    monkeypatch.undo()
    assert list((path / "checkpoints").glob("*.npz"))
    values = compute_tile(tile, tile_checkpoints(path, run_id, tile))
    write_tile(path, tile, values, run_id)
    region = tile.region
    assert values["resumed"].ravel()[0] == 16
    for name in CATALOG:
        for k, got in enumerate(values[name].ravel()):
            assert_same(got, serial[name][region].ravel()[k], name)
    assert not list((path / "checkpoints").glob("*.npz"))   # dropped once the tile is done
    cat = read_catalog(path, law="carlson-langer", n=6, nu_f=0.3, seed=2, events=30, periodic=0)
    assert_same(cat["potency"], serial["potency"][0, 1, 0, 0, 0, 0, 0, 1, 0], "potency")
