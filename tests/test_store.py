"""The Zarr store: layout, round trip through xarray, fill values, partial tiles, refusals."""

from __future__ import annotations

import hashlib
import json
from datetime import datetime

import numpy as np
import pytest

from bifurcation.engine.result import FIELD_ATTRS, FIELDS
from bifurcation.errors import InputError
from bifurcation.store import check_store, create_store, open_store, read_done, store_kind, write_tile
from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles, tile_count
from bifurcation.workflow import Workflow

from _store_helpers import assert_bitwise_equal


def small_workflow(**changes) -> Workflow:
    # 7 × 9 points in 3 × 4 tiles: full tiles and edge tiles on both axes
    options = dict(name="store-test", laws=("piecewise-linear", "carlson-langer"),
                   nu=(1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15),
                   nu_f=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.9), tiles=(3, 4))
    options.update(changes)
    return Workflow(**options)


@pytest.fixture
def written(tmp_path):
    w = small_workflow()
    path = tmp_path / "s.zarr"
    attrs = create_store(path, w, command="pytest")
    for tile in iter_tiles(w):
        write_tile(path, tile, compute_tile(tile), attrs["run_id"])
    return w, path


def test_round_trip_equals_serial_engine_bit_for_bit(written):
    w, path = written
    ds = open_store(path)
    assert ds["delta"].dims == ("law", "nu_f", "nu")
    assert [str(x) for x in ds["law"].values] == list(w.laws)
    assert tuple(ds["nu"].values) == w.nu and tuple(ds["nu_f"].values) == w.nu_f
    assert ds["nu"].dtype == np.float64 and ds["nu_f"].dtype == np.float64
    assert_bitwise_equal(ds, compute_serial(w))
    assert read_done(path).all()


def test_layout_attrs_and_provenance(written):
    w, path = written
    ds = open_store(path)
    for name in (*FIELDS, "steps", "status"):
        assert (ds[name].attrs["long_name"], ds[name].attrs["units"]) == FIELD_ATTRS[name]
        assert ds[name].encoding["chunks"] == (1, 3, 4)
    assert {ds[n].dtype.name for n in FIELDS} == {"float64"}
    assert (ds["steps"].dtype, ds["status"].dtype, ds["done"].dtype) == (np.int64, np.int8, np.bool_)
    assert ds["status"].attrs["flag_meanings"].split()[:3] == ["not-computed", "stick-slip", "creep"]
    attrs = ds.attrs
    assert attrs["workflow_toml"] == w.text
    assert attrs["workflow_sha256"] == hashlib.sha256(w.text.encode()).hexdigest()
    assert attrs["workflow_fingerprint"] == w.fingerprint
    for package in ("bifurcation", "heyoka", "numpy", "dask", "zarr", "xarray"):
        assert attrs[f"version_{package}"][0].isdigit(), package
    assert attrs["command"] == "pytest"
    assert datetime.fromisoformat(attrs["created_utc"]).tzinfo is not None
    assert "consolidated_metadata" in json.loads((path / "zarr.json").read_text())


def test_unwritten_points_read_as_fill_values(tmp_path):
    w = small_workflow()
    create_store(tmp_path / "s.zarr", w)
    ds = open_store(tmp_path / "s.zarr")
    assert np.isnan(ds["delta"].values).all() and np.isnan(ds["max_velocity"].values).all()
    assert not ds["steps"].values.any() and not ds["status"].values.any() and not ds["done"].values.any()
    assert not list((tmp_path / "s.zarr" / "delta").rglob("c/*"))   # metadata only, no chunk written


def test_one_chunk_per_tile_and_partial_tiles_keep_done_points(tmp_path):
    w = small_workflow()
    path = tmp_path / "s.zarr"
    attrs = create_store(path, w)
    first = next(iter_tiles(w))
    write_tile(path, first, compute_tile(first), attrs["run_id"])
    assert len([p for p in (path / "delta").rglob("*") if p.is_file() and p.name != "zarr.json"]) == 1
    # a tile left half done: only its missing points are computed, the done ones are kept
    done = read_done(path)
    done[0, 0, 0:4] = False
    tiles = list(iter_tiles(w, done))
    assert len(tiles) == tile_count(w) and tiles[0].n_todo == 4
    values = compute_tile(tiles[0])
    assert np.isnan(values["delta"][~tiles[0].todo]).all()
    write_tile(path, tiles[0], values, attrs["run_id"])
    reference = compute_serial(w)
    ds = open_store(path)
    np.testing.assert_array_equal(ds["delta"].values[0, :3, :4], reference["delta"][0, :3, :4])
    assert ds["done"].values[0, :3, :4].all()


def test_refusals(tmp_path):
    w = small_workflow()
    path = tmp_path / "s.zarr"
    with pytest.raises(InputError, match=r"^store=.*no such store"):
        open_store(path)
    create_store(path, w)
    with pytest.raises(InputError, match=r"^--store=.*already exists; pass --new-store"):
        create_store(path, w)
    other = small_workflow(nu=(1e-3, 1e-9))
    with pytest.raises(InputError, match=r"^--store=.*holds another workflow.*--new-store"):
        check_store(path, other)
    (tmp_path / "plain").mkdir()
    (tmp_path / "plain" / "keep.txt").write_text("data")
    assert store_kind(tmp_path / "plain") == "other"
    with pytest.raises(InputError, match=r"is not a bifurcation store"):
        create_store(tmp_path / "plain", w, overwrite=True)
    assert (tmp_path / "plain" / "keep.txt").read_text() == "data"   # never deleted
    with pytest.raises(InputError, match=r"is not a bifurcation store"):
        open_store(tmp_path / "plain")
    # overwrite replaces a bifurcation store, with a new run id
    old = check_store(path)["run_id"]
    assert create_store(path, other, overwrite=True)["run_id"] != old
    assert check_store(path, other)["workflow_fingerprint"] == other.fingerprint
