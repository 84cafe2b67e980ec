"""Integrity: checksums on every chunk, verify, repair, queries that never show a damaged value.

Faults are injected into a store written in this process (the serial engine, no cluster); the repair
runs on a module-wide local cluster. The full count (100 flips + 20 lost chunks) is
bifurcation/bench/store_faults.py; here 10 flips and 4 lost chunks, drawn with a fixed seed.
"""

from __future__ import annotations

import json
import random
import shutil

import numpy as np
import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.store.query import query
from bifurcation.run import submit
from bifurcation.run.repair import verify
from bifurcation.store import create_store, open_store, write_tile
from bifurcation.store.integrity import StoreDamagedError, scan
from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles
from bifurcation.workflow import Workflow

from _store_helpers import assert_store_equals, local_cluster

W = Workflow(name="integrity-test", laws=("piecewise-linear", "carlson-langer"),
             nu=(1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13), nu_f=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.9), tiles=(4, 3))
ARRAYS = 9   # six float fields, steps, status, done


@pytest.fixture(scope="module")
def reference():
    return compute_serial(W)


@pytest.fixture(scope="module")
def scheduler():
    with local_cluster(1) as address:
        yield address


def write_store(path):
    run_id = create_store(path, W)["run_id"]
    for tile in iter_tiles(W):
        write_tile(path, tile, compute_tile(tile), run_id)
    return path


def data_chunks(path) -> list:
    return sorted(p for p in path.rglob("*") if p.is_file() and p.relative_to(path).parts[1:2] == ("c",)
                  and len(p.relative_to(path).parts) == 5)


def tile_of(path, chunk) -> tuple:
    return tuple(int(k) for k in chunk.relative_to(path).parts[2:])


def test_every_chunk_has_a_crc32c_and_every_tile_chunk_is_written(tmp_path):
    path = write_store(tmp_path / "s.zarr")
    for name in ("delta", "creep_time", "done", "nu"):
        codecs = [c["name"] for c in json.loads((path / name / "zarr.json").read_text())["codecs"]]
        assert codecs[-1] == "crc32c", (name, codecs)
    # creep_time is NaN (the fill value) in most tiles: written anyway, so a deleted chunk is visible
    assert len(data_chunks(path)) == 2 * 2 * 2 * ARRAYS
    damage, tiles, chunks = scan(path)
    assert (damage, tiles, chunks) == ([], 8, 8 * ARRAYS + 3)
    result = CliRunner().invoke(cli, ["verify", "--store", str(path), "--json"])
    assert result.exit_code == 0 and json.loads(result.stdout)["ok"] is True
    result = CliRunner().invoke(cli, ["verify", "--store", str(tmp_path / "none.zarr")])
    assert result.exit_code == 2 and result.stderr.startswith("bifurcation: error: --store=")


def test_faults_are_detected_never_shown_and_repaired_bit_for_bit(tmp_path, reference, scheduler):
    path = write_store(tmp_path / "s.zarr")
    rng = random.Random(8)
    victims = rng.sample(data_chunks(path), 14)
    for chunk in victims[:10]:   # a random single bit of the chunk file
        data = bytearray(chunk.read_bytes())
        bit = rng.randrange(8 * len(data))
        data[bit // 8] ^= 1 << (bit % 8)
        chunk.write_bytes(bytes(data))
    victims[10].unlink()
    victims[11].unlink()
    for chunk in victims[12:]:
        chunk.write_bytes(chunk.read_bytes()[:-7])
    injected = {tile_of(path, c) for c in victims}
    damage, _, _ = scan(path)
    assert {d.tile for d in damage} == injected   # every damaged tile found, no false alarm
    # a query never prints a value of a damaged tile: it fails in one line naming a chunk and the fix
    result = CliRunner().invoke(cli, ["query", "--store", str(path), "--format", "csv"])
    assert result.exit_code == 2 and result.stdout == ""
    (line,) = result.stderr.strip().splitlines()
    assert "chunk " in line and f"bifurcation verify --store {path} --repair" in line
    with pytest.raises(StoreDamagedError):
        query(path)
    # verify without --repair: exit 1 and the damaged chunks listed
    result = CliRunner().invoke(cli, ["verify", "--store", str(path)])
    assert result.exit_code == 1 and f"{len(damage)} damaged" in result.stdout
    report = verify(path, repair=True, scheduler=scheduler, progress=False)
    assert report.ok and report.repaired_tiles == len(injected) and not report.after
    assert report.submit["computed"] == len(injected) * 4 * 3   # exactly the damaged tiles (all full tiles)
    assert_store_equals(path, reference)
    assert len(query(path)) == W.n_points


def test_done_directory_deleted(tmp_path, reference, scheduler):
    path = write_store(tmp_path / "s.zarr")
    shutil.rmtree(path / "done")
    with pytest.raises(StoreDamagedError, match=r"done/zarr.json"):
        query(path)
    report = verify(path, repair=True, scheduler=scheduler, progress=False)
    assert report.restored == ("done",) and report.ok and report.repaired_tiles == 8
    assert_store_equals(path, reference)


def test_a_resume_finds_and_recomputes_damaged_tiles(tmp_path, reference, scheduler):
    path = write_store(tmp_path / "s.zarr")
    shutil.rmtree(path / "done")                         # was: a KeyError traceback
    summary = submit(W, store=path, scheduler=scheduler, progress=False)
    # the done array's metadata is restored; no point is vouched for, so every tile is computed again
    assert (summary.repaired, summary.computed, summary.skipped) == (0, W.n_points, 0)
    assert_store_equals(path, reference)
    (path / "delta" / "c" / "1" / "0" / "0").unlink()    # was: never repaired by a resume
    summary = submit(W, store=path, scheduler=scheduler, progress=False)
    assert (summary.repaired, summary.computed) == (1, 4 * 3)
    assert "recomputed: 1" in str(summary)
    assert_store_equals(path, reference)
    chunk = path / "steps" / "c" / "0" / "1" / "1"
    chunk.write_bytes(chunk.read_bytes()[:-3])           # truncated: was "0 computed"
    summary = submit(W, store=path, scheduler=scheduler, progress=False)
    assert (summary.repaired, summary.computed) == (1, 4 * 3)
    assert_store_equals(path, reference)


def test_done_and_data_disagree(tmp_path):
    path = write_store(tmp_path / "s.zarr")
    import zarr

    group = zarr.open_group(str(path), mode="r+", use_consolidated=False)
    status = group["status"].with_config({"write_empty_chunks": True})
    status[0, 0, 0] = 0                # not computed where done: the done mask would lie
    done = group["done"].with_config({"write_empty_chunks": True})
    done[1, 7, 5] = False              # a value where done is False
    damage, _, _ = scan(path)
    assert [(d.tile, d.problem) for d in damage] == [
        ((0, 0, 0), "marks a point not computed where done is True"),
        ((1, 1, 1), "holds a value where done is False")]
    assert damage[0].chunk == "status/c/0/0/0"   # the first variable found holding a value is named


def test_partly_written_store_is_sound_and_reads_not_computed(tmp_path):
    path = tmp_path / "s.zarr"
    run_id = create_store(path, W)["run_id"]
    first = next(iter_tiles(W))
    write_tile(path, first, compute_tile(first), run_id)
    assert scan(path)[0] == []
    records = query(path, law="carlson-langer")
    assert {r["status"] for r in records} == {"not-computed"} and all(r["delta"] is None for r in records)
    assert np.isnan(open_store(path)["delta"].values[1]).all()
