"""`bifurcation export`: netCDF (CF) and CSV files that read back to the store's numbers, bit for bit;
nothing exported from a damaged store; `open_store(...).to_netcdf()` works as it is."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.store.query import query
from bifurcation.store import create_store, open_store, record_submit, write_tile
from bifurcation.store.export import cf_problems, read_csv
from bifurcation.run.tiles import compute_tile, iter_tiles
from bifurcation.workflow import parse_workflow

TOML = """
[study]
name = "export-test"
[engine]
laws = ["carlson-langer", "1/(1+x/2)^2"]
[grid.nu]
values = [1e-6, 1e-12]
[grid.nu_f]
values = [0.3, 0.5, 0.7]
[tiles]
nu_f = 2
nu = 2
"""


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    path = tmp_path_factory.mktemp("export") / "s.zarr"
    workflow = parse_workflow(TOML)
    run_id = str(create_store(path, workflow, command="bifurcation submit export-test.toml")["run_id"])
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile), run_id)
    record_submit(path, {"command": "bifurcation submit export-test.toml", "computed": 12, "skipped": 0,
                         "failed": 0, "cluster": "in process"})
    return path


def _bits(values: np.ndarray) -> np.ndarray:
    return values.view(np.int64) if values.dtype.kind == "f" else values


def test_netcdf_round_trip_and_cf(store, tmp_path):
    out = tmp_path / "s.nc"
    result = CliRunner().invoke(cli, ["export", "--store", str(store), "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert result.output.strip() == f"wrote 12 points to {out} (netcdf)"
    original = open_store(store)
    with xr.open_dataset(out) as back:
        assert cf_problems(back) == []
        assert back.attrs["Conventions"] == "CF-1.10"
        assert back.attrs["history"].count("\n") == 1   # created + one submit
        assert list(back["law"].values) == ["carlson-langer", "1/(1+x/2)^2"]
        for name in original.data_vars:
            assert back[name].dtype == original[name].dtype, name
            np.testing.assert_array_equal(_bits(back[name].values), _bits(original[name].values), err_msg=name)
        for name in ("nu", "nu_f"):
            np.testing.assert_array_equal(back[name].values, original[name].values)
        assert back["status"].attrs["flag_meanings"] == original["status"].attrs["flag_meanings"]


def test_open_store_writes_netcdf_as_it_is(store, tmp_path):
    ds = open_store(store)
    assert cf_problems(ds) == []
    assert json.loads(ds.attrs["submits"])[0]["computed"] == 12
    ds.to_netcdf(tmp_path / "direct.nc")   # failed before: a list of dicts as an attribute
    with xr.open_dataset(tmp_path / "direct.nc") as back:
        np.testing.assert_array_equal(_bits(back["delta"].values), _bits(ds["delta"].values))


def test_csv_round_trip(store, tmp_path):
    out = tmp_path / "s.csv"
    result = CliRunner().invoke(cli, ["export", "--store", str(store), "--out", str(out), "--json"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.output) == {"out": str(out), "format": "csv", "points": 12, "computed": 12}
    rows = read_csv(out)
    assert rows == query(store)   # every float exact (repr), NaN as None, same order


@pytest.mark.parametrize("args, message", [
    (["--out", "{tmp}/s.txt"], "has no known file type"),
    (["--out", "{tmp}/missing/s.nc"], "directory that does not exist"),
    (["--out", "{tmp}"], "is a directory"),
    (["--out", "{tmp}/s.nc", "--format", "xlsx"], "Invalid value for '--format'"),
])
def test_bad_output_is_one_line(store, tmp_path, args, message):
    args = [a.format(tmp=tmp_path) for a in args]
    result = CliRunner().invoke(cli, ["export", "--store", str(store), *args])
    assert result.exit_code == 2
    [line] = result.output.splitlines()
    assert message in line


def test_nothing_exported_from_a_damaged_store(store, tmp_path):
    import shutil

    damaged = tmp_path / "d.zarr"
    shutil.copytree(store, damaged)
    chunk = next(p for p in sorted((damaged / "delta").rglob("*")) if p.is_file() and p.name != "zarr.json")
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x10
    chunk.write_bytes(bytes(data))
    for name in ("d.nc", "d.csv"):
        result = CliRunner().invoke(cli, ["export", "--store", str(damaged), "--out", str(tmp_path / name)])
        assert result.exit_code == 2
        [line] = result.output.splitlines()
        assert "delta/c/" in line and "verify --store" in line
        assert not (tmp_path / name).exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []   # no partial file
