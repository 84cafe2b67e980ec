"""submit: results equal a serial run, resume computes only the missing part, refusals write nothing.

One local cluster of two worker processes serves the module (started once: a few seconds).
"""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

import bifurcation.store
from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.run import WRITERS, submit
from bifurcation.store import open_store, read_done
from bifurcation.run.tiles import compute_serial, tile_count
from bifurcation.workflow import Workflow

from _store_helpers import assert_store_equals, local_cluster

TOML = """
[study]
name = "cli-test"

[engine]
laws = ["carlson-langer"]

[grid.nu]
values = [1e-6, 1e-9, 1e-12]

[grid.nu_f]
ranges = [{ start = 0.1, stop = 0.9, num = 9 }]

[tiles]
nu_f = 4
nu = 2
"""


@pytest.fixture(scope="module")
def scheduler():
    with local_cluster(2) as address:
        yield address


def workflow(**changes) -> Workflow:
    options = dict(name="submit-test", laws=("piecewise-linear", "carlson-langer"),
                   nu=(1e-3, 1e-6, 1e-9, 1e-12, 1e-15), nu_f=tuple(round(0.05 * k, 2) for k in range(1, 20)),
                   tiles=(5, 3))
    options.update(changes)
    return Workflow(**options)


def assert_store_equals_serial(path, w) -> None:
    assert_store_equals(path, compute_serial(w))


def chunk_files(path) -> dict:
    """Every file of the store with its (mtime_ns, size): what a run changed."""
    return {str(p.relative_to(path)): (p.stat().st_mtime_ns, p.stat().st_size)
            for p in sorted(path.rglob("*")) if p.is_file()}


@pytest.mark.slow   # 10 s; store = serial engine is checked fast in test_distributed, test_models, test_chain_store
def test_submit_equals_serial_and_resubmit_computes_nothing(scheduler, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    w = workflow()
    seen = []
    summary = submit(w, scheduler=scheduler, progress=lambda done, total: seen.append((done, total)))
    assert summary.store == "results/submit-test.zarr"   # the default store
    assert (summary.computed, summary.skipped, summary.failed) == (w.n_points, 0, 0)
    assert summary.tiles == tile_count(w) == 2 * 4 * 2
    assert sum(summary.statuses.values()) == w.n_points
    assert seen[-1] == (w.n_points, w.n_points) and len(seen) == summary.tiles
    assert_store_equals_serial(tmp_path / summary.store, w)
    attrs = open_store(tmp_path / summary.store).attrs
    assert json.loads(attrs["submits"])[-1]["computed"] == w.n_points

    again = submit(w, scheduler=scheduler, progress=False)
    assert (again.computed, again.skipped, again.tiles) == (0, w.n_points, 0)
    assert json.loads(open_store(tmp_path / summary.store).attrs["submits"])[-1]["skipped"] == w.n_points


def test_batched_study_equals_its_serial_run(scheduler, tmp_path):
    # batch = 8: heyoka's SIMD lanes in every tile; lanes and point order do not change the bits, so
    # the distributed store still equals the serial run exactly
    w = workflow(name="batched", batch=8)
    summary = submit(w, store=tmp_path / "b.zarr", scheduler=scheduler, progress=False)
    assert summary.computed == w.n_points and summary.failed == 0
    assert_store_equals_serial(tmp_path / "b.zarr", w)


def test_resume_computes_only_missing_tiles_and_points(scheduler, tmp_path):
    import zarr

    w = workflow()
    path = tmp_path / "r.zarr"
    submit(w, store=path, scheduler=scheduler, progress=False)
    # a run killed after some tiles: remove the done chunks of three tiles ...
    removed = ["c/0/0/0", "c/1/1/1", "c/1/3/0"]
    for key in removed:
        (path / "done" / key).unlink()
    # ... and leave one more tile half done at the point level
    group = zarr.open_group(str(path), mode="r+", use_consolidated=False)
    group["done"][0, 5:7, 0:3] = False
    before = chunk_files(path)
    missing = int((~read_done(path)).sum())
    assert missing == 5 * 3 + 5 * 2 + 4 * 3 + 6   # full, edge-ν and edge-ν_f tiles, 6 points

    summary = submit(w, store=path, scheduler=scheduler, progress=False)
    assert (summary.computed, summary.skipped, summary.tiles) == (missing, w.n_points - missing, 4)
    after = chunk_files(path)
    untouched = [k for k in before if k.split("/")[-3:] not in (["0", "0", "0"], ["1", "1", "1"], ["1", "3", "0"],
                                                                ["0", "1", "0"])
                 and "/c/" in k]
    assert untouched and all(after[k] == before[k] for k in untouched)   # done tiles not rewritten
    assert_store_equals_serial(path, w)


def test_submit_accepts_a_client_and_leaves_it_open(scheduler, tmp_path):
    from distributed import Client

    w = workflow(laws=("piecewise-linear",), nu=(1e-9,))
    with Client(scheduler, set_as_default=False) as client:
        summary = submit(w, store=tmp_path / "k.zarr", scheduler=client, workers=2, progress=False)
        assert summary.complete and summary.cluster == f"client of {scheduler}"
        assert client.status == "running" and client.submit(abs, -1).result() == 1
    assert_store_equals_serial(tmp_path / "k.zarr", w)


def test_mismatched_workflow_is_refused_and_nothing_written(scheduler, tmp_path):
    w = workflow()
    path = tmp_path / "m.zarr"
    submit(w, store=path, scheduler=scheduler, progress=False)
    before = chunk_files(path)
    other = workflow(nu=(1e-3, 1e-9))
    with pytest.raises(InputError) as info:
        submit(other, store=path, scheduler=scheduler, progress=False)
    assert info.value.argument == "--store" and "--new-store" in str(info.value)
    assert chunk_files(path) == before

    replaced = submit(other, store=path, scheduler=scheduler, progress=False, new_store=True)
    assert (replaced.computed, replaced.skipped) == (other.n_points, 0)
    assert_store_equals_serial(path, other)


def test_client_writer_and_failed_tiles_are_reported_then_resumed(scheduler, tmp_path, monkeypatch):
    w = workflow(laws=("carlson-langer",))
    path = tmp_path / "c.zarr"
    real_write = bifurcation.store.write_tile

    def flaky(store, tile, values, run_id):
        if tile.name == "0-5-0":   # a full tile: 5 × 3 points
            raise OSError("disk full (injected)")
        real_write(store, tile, values, run_id)

    monkeypatch.setattr(bifurcation.store, "write_tile", flaky)
    summary = submit(w, store=path, scheduler=scheduler, progress=False, writer="client")
    assert summary.failed == 15 and summary.computed == w.n_points - 15 and not summary.complete
    assert "disk full (injected)" in summary.errors[0]
    assert int((~read_done(path)).sum()) == 15

    monkeypatch.setattr(bifurcation.store, "write_tile", real_write)
    again = submit(w, store=path, scheduler=scheduler, progress=False, writer="client")
    assert (again.computed, again.failed, again.tiles) == (15, 0, 1)
    assert_store_equals_serial(path, w)


# -- CLI -------------------------------------------------------------------------------------------
BAD_INVOCATIONS = [
    (["submit", "missing.toml"], "WORKFLOW="),
    (["submit", "bad-syntax.toml"], "is not valid TOML"),
    (["submit", "unknown-key.toml"], "engine.precison="),
    (["submit", "ok.toml", "--workers", "0"], "--workers=0"),
    (["submit", "ok.toml", "--workers", "two"], "--workers"),
    (["submit", "ok.toml", "--scheduler", "no-such-file"], "--scheduler="),
    (["submit", "ok.toml", "--store", "plain-dir"], "--store="),
    (["query", "--store", "results/none.zarr"], "--store="),
    (["query", "--store", "plain-dir"], "is not a bifurcation store"),
    (["query", "--store", "plain-dir", "--format", "xml"], "--format"),
    (["query"], "--store"),
]


@pytest.mark.parametrize("args, needle", BAD_INVOCATIONS, ids=[" ".join(a) for a, _ in BAD_INVOCATIONS])
def test_cli_bad_input_is_one_line_exit_2_and_writes_nothing(args, needle, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ok.toml").write_text(TOML)
    (tmp_path / "bad-syntax.toml").write_text(TOML.replace("[tiles]", "[tiles"))
    (tmp_path / "unknown-key.toml").write_text(TOML.replace("[engine]", "[engine]\nprecison = 'quad'"))
    (tmp_path / "plain-dir").mkdir()
    before = sorted(p.name for p in tmp_path.rglob("*"))
    result = CliRunner().invoke(cli, args)
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bifurcation: error: ") and needle in lines[0]
    assert sorted(p.name for p in tmp_path.rglob("*")) == before


def test_cli_writer_choices_are_the_writers():
    # hard-coded in the CLI so that --help does not import bifurcation.run; kept equal here
    (option,) = [p for p in cli.get_command(None, "submit").params if p.name == "writer"]
    assert tuple(option.type.choices) == WRITERS


def test_cli_submit_and_query(scheduler, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "ok.toml").write_text(TOML)
    result = CliRunner().invoke(cli, ["submit", "ok.toml", "--scheduler", scheduler, "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert (summary["computed"], summary["failed"], summary["store"]) == (27, 0, "results/cli-test.zarr")
    result = CliRunner().invoke(cli, ["query", "--store", "results/cli-test.zarr", "--nu", "1e-9",
                                      "--nu-f", "0.4", "--format", "json"])
    assert result.exit_code == 0, result.output
    (record,) = json.loads(result.stdout)
    assert (record["law"], record["nu"], record["nu_f"], record["status"]) == ("carlson-langer", 1e-9, 0.4, "stick-slip")
    result = CliRunner().invoke(cli, ["submit", "ok.toml", "--scheduler", scheduler])
    assert result.exit_code == 0 and "0 computed, 27 skipped" in result.stdout


@pytest.mark.slow   # 11 s: the Dask pipeline benchmark at its smallest; submit itself is covered fast
def test_bench_pipeline_smoke():
    from bifurcation.bench.pipeline import bench_pipeline

    out = bench_pipeline(points=1000, workers=1, tiles=(8, 64))
    assert out["points"] == 16 * 64 and out["complete"]
    # measured ~200 MB: numpy, heyoka, distributed and zarr alone take ~160 MB, a 8 × 64 tile a few kB.
    # The bounds catch ru_maxrss read in the wrong unit (kB taken as bytes or scaled twice: a factor
    # 1024 either way) and a worker that grows by gigabytes, not small changes
    assert 50 < out["worker_peak_rss_mb"] < 2000
