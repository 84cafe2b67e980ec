"""`bifurcation status`: progress per law, outcomes and the writer, read from the store alone.

The store is built tile by tile in process (create_store + write_tile: what workers do), so each state
(empty, part done, complete, being written) is set exactly.
"""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.store import create_store, write_tile
from bifurcation.store.lock import StoreLock
from bifurcation.store.status import study_status
from bifurcation.run.tiles import compute_tile, iter_tiles
from bifurcation.workflow import parse_workflow

TOML = """
[study]
name = "status-test"
[engine]
laws = ["piecewise-linear", "carlson-langer"]
[grid.nu]
values = [1e-6, 1e-9]
[grid.nu_f]
values = [0.3, 0.6, 0.7]
[tiles]
nu_f = 2
nu = 2
"""


@pytest.fixture
def store(tmp_path):
    workflow = parse_workflow(TOML)
    attrs = create_store(tmp_path / "s.zarr", workflow)
    return workflow, tmp_path / "s.zarr", str(attrs["run_id"])


def test_empty_store(store):
    workflow, path, _ = store
    found = study_status(path)
    assert (found.points, found.done, found.failed) == (12, 0, 0)
    assert found.axis == "law" and list(found.per_label) == ["piecewise-linear", "carlson-langer"]
    assert found.writer is None and found.rate is None and not found.complete
    assert "submit the same workflow again to compute the 12 remaining points" in str(found)


def test_part_done_then_complete(store):
    workflow, path, run_id = store
    tiles = list(iter_tiles(workflow))
    first = tiles[0]                     # piecewise-linear, ν_f 0.3 and 0.6, both ν: 4 points
    values = compute_tile(first)
    write_tile(path, first, values, run_id)
    found = study_status(path)
    assert found.done == 4 and found.per_label["piecewise-linear"]["done"] == 4
    assert found.per_label["carlson-langer"]["done"] == 0
    expected = {}
    for code in values["status"].ravel():
        name = {1: "stick-slip", 2: "creep"}[int(code)]
        expected[name] = expected.get(name, 0) + 1
    assert found.per_label["piecewise-linear"]["statuses"] == expected
    assert found.last_write is not None
    for tile in tiles[1:]:
        write_tile(path, tile, compute_tile(tile), run_id)
    found = study_status(path)
    assert found.complete and found.done == 12 and found.failed == 0
    assert str(found).splitlines()[-2].startswith("complete: all 12 points computed and no submit is writing it")


def test_a_writer_is_named_with_its_rate(store):
    workflow, path, run_id = store
    with StoreLock(path).acquire(command="bifurcation submit status-test.toml"):
        for tile in list(iter_tiles(workflow))[:2]:
            write_tile(path, tile, compute_tile(tile), run_id)
        found = study_status(path)
        assert found.writer is not None and "pid" in found.writer["describe"]
        assert found.rate is not None and found.rate > 0 and found.eta is not None and found.eta >= 0
        assert "being written by run" in str(found)
    assert study_status(path).writer is None   # released


def test_cli_text_json_and_bad_store(store, tmp_path):
    _, path, _ = store
    result = CliRunner().invoke(cli, ["status", "--store", str(path)])
    assert result.exit_code == 0, result.output
    assert result.output.startswith("study status-test")
    result = CliRunner().invoke(cli, ["status", "--store", str(path), "--json"])
    assert result.exit_code == 0
    data = json.loads(result.output)
    assert data["points"] == 12 and data["done"] == 0 and data["per_label"]["carlson-langer"]["points"] == 6
    result = CliRunner().invoke(cli, ["status", "--store", str(tmp_path / "missing.zarr")])
    assert result.exit_code == 2
    assert result.output.count("\n") == 1 and "no such store" in result.output


def test_a_damaged_store_is_one_line_naming_the_repair(store):
    """A flipped bit in a done chunk, then a lost done array: one line, exit 2, never a traceback."""
    workflow, path, run_id = store
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile), run_id)
    chunk = next(p for p in sorted((path / "done").rglob("*")) if p.is_file() and p.name != "zarr.json")
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x01
    chunk.write_bytes(bytes(data))
    import shutil

    for damage in ("a flipped bit", "the array lost"):
        if damage == "the array lost":
            shutil.rmtree(path / "done")
        result = CliRunner().invoke(cli, ["status", "--store", str(path)])
        assert result.exit_code == 2, (damage, result.output)
        [line] = result.output.splitlines()
        assert "damaged done array" in line and "verify --store" in line and "--repair" in line


def test_a_status_code_is_named_by_its_flag_value_not_its_position(store):
    # unresolved is code 7 while the flags list 7 values (0..5 and 7): a lookup by list position read it
    # as "code 7"; a point that the engine could not vouch for must be named as such
    workflow, path, run_id = store
    first = next(iter(iter_tiles(workflow)))
    values = compute_tile(first)
    values["status"].ravel()[0] = 7
    write_tile(path, first, values, run_id)
    statuses = study_status(path).per_label["piecewise-linear"]["statuses"]
    assert statuses.get("unresolved") == 1 and not any(k.startswith("code") for k in statuses)


def test_status_of_a_result_chunk_with_a_flipped_bit_does_not_vouch_for_it(store):
    """Issue 21: status read a store with a flipped bit in a delta chunk as a bare "complete"; it reads
    only done and status, so it says the other chunks are unchecked and names verify, which finds it."""
    workflow, path, run_id = store
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile), run_id)
    chunk = next(p for p in sorted((path / "delta").rglob("*")) if p.is_file() and p.name != "zarr.json")
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x04
    chunk.write_bytes(bytes(data))
    result = CliRunner().invoke(cli, ["status", "--store", str(path)])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert lines[-2].startswith("complete: all 12 points computed")
    assert lines[-1] == (f"chunks not checked for damage (status reads only the done and status arrays): "
                         f"`bifurcation verify --store {path}` checks every one")
    data = json.loads(CliRunner().invoke(cli, ["status", "--store", str(path), "--json"]).output)
    assert data["integrity"].startswith("not checked")
    verified = CliRunner().invoke(cli, ["verify", "--store", str(path)])
    assert verified.exit_code != 0 and "delta" in verified.output, verified.output
