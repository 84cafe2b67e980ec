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
import textwrap
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
    assert model.dims == ("law", "n", "ell", "nu", "nu_f", "amplitude", "seed", "events", "periodic", "sigma",
                          "v_threshold")
    assert [o.name for o in model.catalog_outputs] == list(CATALOG)
    assert model.checkpoint and model.runner is not None and model.axis("n").structural
    assert model.catalog_size == "events" and model.catalog_count == "events_done"


def test_a_run_of_the_model_is_bifurcation_chain_bit_for_bit(serial, workflow):
    # the store's runner against the public API (one ChainLoop.run(K) call, no checkpoints)
    for law_i, law in enumerate(workflow.laws):
        for index in [(1, 0, 0, 0, 0, 0, 1, 1, 0, 0), (1, 0, 0, 1, 0, 0, 0, 0, 0, 0), (0, 0, 0, 0, 0, 0, 1, 0, 0, 0)]:
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
    for index in [(0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 0), (1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0)]:
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
    run = int(np.ravel_multi_index((1, 1, 0, 0, 0, 0, 0, 1, 1, 0, 0), workflow.shape))
    capacity, chunk = 32, 8      # ceil(30/8)·8; C = [tiles] catalog
    own = {f"catalog/{name}/c/{run * capacity // chunk + k}" for name in CATALOG for k in range(4)}
    catalog_keys = {k for k in seen if k.startswith("catalog/") and not k.endswith("zarr.json")}
    assert catalog_keys == own and len(cat["potency"]) == 30
    data_keys = {k for k in seen if "/c/" in k and not k.startswith("catalog/")}
    # per-run outputs: one chunk (its tile) per variable, plus the coordinates
    assert all(k.split("/")[0] in get_model("chain").dims or k.endswith("/c/1/1/0/0/0/0/0/1/1/0/0")
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


def test_quad_precision_snapshot_restore_is_bit_identical():
    """real128 state through bytes (a quad study's checkpoint): the same events to the last bit."""
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._loop import ChainLoop
    from bifurcation.models.chain._validate import check_initial
    from bifurcation.models.chain.checkpoint import restore, snapshot

    law = resolve_law("carlson-langer")
    u = check_initial(4, 1.0, "free", None, 0.5, 2)

    def loop():
        return ChainLoop(law, 4, 1.0, 1e-3, 0.3, "free", u, precision="quad")

    whole = loop().run(10)["catalog"]
    first = loop()
    a = first.run(4)["catalog"]
    second = loop()
    restore(second, {k: np.ascontiguousarray(v).tobytes() for k, v in snapshot(first).items()})
    b = second.run(6)["catalog"]
    for name in ("t_start", "potency", "duration"):   # real128 values compared by their exact text
        assert [str(x) for x in a[name] + b[name]] == [str(x) for x in whole[name]], name


def test_a_run_that_stops_early_keeps_its_events_and_says_so():
    """t_max = 2 bounds each event's duration: the first multi-block event of this chain (duration > 2)
    stops the run with no-stop; the events before it are kept and t_end is NaN (not a stuck-state time)."""
    from bifurcation.engine.solve import solve

    points = dict(n=[6], ell=[1.0], nu=[1e-3], nu_f=[0.3], amplitude=[0.5], seed=[2], events=[30], periodic=[0])
    out = solve(get_model("chain"), "carlson-langer", points, t_max=2.0)
    full = solve(get_model("chain"), "carlson-langer", points)
    k = int(out["events_done"][0])
    assert out["status"][0] == 3 and k < 30 and np.isnan(out["t_end"][0])   # ChainStatus.NO_STOP
    assert full["duration"][0][k] > 2.0 and np.all(full["duration"][0][:k] <= 2.0)
    for name in CATALOG:
        assert_same(out[name][0], full[name][0][:k], name)
    assert "did not end" in out["messages"][0]


def _kill_after_second_checkpoint(workflow, path, run_id, monkeypatch):
    """Compute the tile of the run (n = 6, ν_f = 0.3, seed 2) in process and kill it (KeyboardInterrupt, not an
    Exception: nothing catches it on the way out) right after its 2nd checkpoint (C = 8: 16 events saved)."""
    from bifurcation.store.catalog import Checkpoints

    tile = next(t for t in iter_tiles(workflow) if t.index == (0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0))
    calls = []
    original = Checkpoints.save

    def dying(self, i, *args, **kwargs):
        original(self, i, *args, **kwargs)
        calls.append(i)
        if calls.count(0) == 2:
            raise KeyboardInterrupt("killed")

    monkeypatch.setattr(Checkpoints, "save", dying)
    with pytest.raises(KeyboardInterrupt):
        compute_tile(tile, tile_checkpoints(path, run_id, tile))
    monkeypatch.undo()
    return tile


def test_a_run_killed_between_checkpoints_resumes_bit_identical(workflow, serial, tmp_path, monkeypatch):
    """In process: the task dies (an exception) after its 2nd checkpoint of a 30-event run (C = 8); the
    recomputed tile restores 16 events and its catalog equals the uninterrupted run's."""

    path = tmp_path / "ck.zarr"
    run_id = create_store(path, workflow)["run_id"]
    tile = _kill_after_second_checkpoint(workflow, path, run_id, monkeypatch)
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
    assert_same(cat["potency"], serial["potency"][0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0], "potency")


def test_query_catalog_of_a_run_killed_mid_run_names_its_checkpointed_events(workflow, tmp_path, monkeypatch):
    """A run killed after its 2nd checkpoint (C = 8: 16 events saved) is not done: `query --catalog` says
    how many events are checkpointed and how to resume (the store's own submit command), not "has not
    computed this run yet" (issue 21, walk 4). Like status and report it shows no catalog of an unfinished run."""

    path = tmp_path / "ck.zarr"
    run_id = create_store(path, workflow, command="bifurcation submit chain.toml --store ck.zarr --new-store")["run_id"]
    tile = _kill_after_second_checkpoint(workflow, path, run_id, monkeypatch)
    args = ["query", "--store", str(path), "--law", "carlson-langer", "--n", "6", "--nu-f", "0.3",
            "--events", "30", "--periodic", "0", "--catalog"]
    result = CliRunner().invoke(cli, args)
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1 and "Traceback" not in result.output
    assert "has 16 events of this run checkpointed, run not finished" in result.output
    # the resume command is the store's own, less --new-store (which would drop the checkpoints)
    assert "resume with `bifurcation submit chain.toml --store ck.zarr`" in result.output
    # a run of the same store with no checkpoint: still "not computed yet"
    other = CliRunner().invoke(cli, [*args[:-4], "12", "--periodic", "1", "--catalog"])
    assert other.exit_code == 2 and "has not computed this run yet" in other.output
    assert "checkpoint" not in other.output


# -- a real `dask worker` killed with -9 in the middle of a run ------------------------------------------
KILL = textwrap.dedent("""
    [study]
    name = "chain-kill"
    [model]
    name = "chain"
    [engine]
    laws = ["carlson-langer"]
    [grid.n]
    values = [4]
    [grid.ell]
    values = [1.0]
    [grid.nu]
    values = [1e-3]
    [grid.nu_f]
    values = [0.3]
    [grid.amplitude]
    values = [0.5]
    [grid.seed]
    values = [3]
    [grid.events]
    values = [4000]
    [grid.periodic]
    values = [0]
    [tiles]
    catalog = 200
    """)


@pytest.mark.slow   # 4-5 s: kills and resumes real runs; the checkpoint's bit-identical resume is tested fast in process
@pytest.mark.distributed
def test_a_dask_worker_killed_mid_run_resumes_from_its_checkpoint_bit_identical(tmp_path):
    """`dask scheduler` + one `dask worker` (its nanny restarts it) on loopback; `bifurcation submit` of one
    4000-event run (~2 s) with a checkpoint every 200 events; the worker process is killed with -9 once the
    first checkpoint is in the store. The scheduler hands the task to the restarted worker, which resumes
    from the last checkpoint; the stored catalog equals an uninterrupted in-process run bit for bit."""
    from distributed import Client
    from _proc import BIN, bifurcation, free_port, start, stop, wait_until

    wf = tmp_path / "kill.toml"
    wf.write_text(KILL)
    store = tmp_path / "kill.zarr"
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                   tmp_path, "scheduler")]
    try:
        procs.append(start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1", "--host",
                            "127.0.0.1", "--no-dashboard", "--death-timeout", "60"], tmp_path, "worker"))
        with Client(address, timeout="60s", set_as_default=False) as client:
            client.wait_for_workers(1, timeout=90)
            (victim,) = client.run(os.getpid).values()
            submit = start(bifurcation("submit", wf, "--scheduler", address, "--store", store, "--json"), tmp_path,
                           "submit")
            procs.append(submit)
            checkpoint = store / "checkpoints" / "0.npz"
            wait_until(checkpoint.exists, 120, "the first checkpoint", proc=submit,
                       detail=lambda: (tmp_path / "submit.log").read_text())
            os.kill(victim, signal.SIGKILL)
            assert submit.wait(300) == 0, (tmp_path / "submit.log").read_text()
        with pytest.raises(ProcessLookupError):
            os.kill(victim, 0)
    finally:
        for proc in reversed(procs):
            stop(proc)
    log = (tmp_path / "submit.log").read_text()
    summary = json.loads(log[log.index("{"):log.rindex("}") + 1])
    assert (summary["computed"], summary["failed"]) == (1, 0)
    cat = read_catalog(store, law="carlson-langer")
    resumed = cat["run"]["resumed"]
    assert 0 < resumed < 4000 and resumed % 200 == 0        # it did resume, from a checkpoint
    reference = compute_serial(parse_workflow(KILL))     # uninterrupted, no checkpoints
    for name in CATALOG:
        assert_same(cat[name], reference[name].reshape(-1)[0], name)
    assert cat["run"]["events_done"] == 4000 and cat["run"]["status"] == "complete"
    ds = open_store(store)
    for name in ("t_end", "steps", "events_done", "status"):
        assert_same(ds[name].values, reference[name], name)
    assert not list((store / "checkpoints").glob("*.npz"))


# -- workflows: submit end to end, bad input ------------------------------------------------------------
def test_submit_of_the_shipped_chain_workflow_end_to_end(tmp_path):
    """`bifurcation submit workflows/chain-study.toml` on the embedded cluster; then status, verify, query
    (per run and --catalog), report: what a new user runs."""
    repo = Path(__file__).resolve().parents[1]
    store = tmp_path / "study.zarr"
    runner = CliRunner()
    result = runner.invoke(cli, ["submit", str(repo / "workflows" / "chain-study.toml"), "--store", str(store),
                                 "--workers", "1", "--json"])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout[result.stdout.index("{"):])
    assert (summary["computed"], summary["failed"], summary["statuses"]) == (4, 0, {"complete": 4})
    reference = compute_serial(parse_workflow((repo / "workflows" / "chain-study.toml").read_text()))
    ds = open_store(store)
    for name in ("t_end", "steps", "events_done", "status"):
        assert_same(ds[name].values, reference[name], name)
    status = runner.invoke(cli, ["status", "--store", str(store)])
    assert status.exit_code == 0 and "complete 4" in status.output and "0 failed" in status.output
    verify = runner.invoke(cli, ["verify", "--store", str(store)])
    assert verify.exit_code == 0 and "0 damaged" in verify.output, verify.output
    out = runner.invoke(cli, ["query", "--store", str(store), "--n", "16", "--nu-f", "0.2", "--catalog", "--json"])
    assert out.exit_code == 0, out.output
    got = json.loads(out.stdout)
    index = (0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0)
    assert got["run"]["n"] == 16 and len(got["potency"]) == 200
    for name in CATALOG:   # JSON floats are repr: exact
        assert_same(np.asarray(got[name], dtype=reference[name][index].dtype), reference[name][index], name)
    table = runner.invoke(cli, ["query", "--store", str(store), "--n", "4", "--nu-f", "0.35", "--catalog",
                                "--format", "csv"])
    assert table.exit_code == 0 and table.stdout.splitlines()[0] == "event," + ",".join(CATALOG)
    assert len(table.stdout.splitlines()) == 201
    report = runner.invoke(cli, ["report", "--store", str(store), "--out", str(tmp_path / "report")])
    assert report.exit_code == 0, report.output
    md = (tmp_path / "report" / "REPORT.md").read_text()
    assert "Chain runs and their catalogs" in md and "| 16 | 0.2 | complete | 200 |" in md
    assert (tmp_path / "report" / "store0_magnitude_frequency.png").is_file()   # a figure, not 0
    assert "](store0_magnitude_frequency.png)" in md and "| periodic | ends | free | free |" in md
    # the axes in the model's (and the workflow's) order; the ends as the CLI names them, not 0/1
    rows = runner.invoke(cli, ["query", "--store", str(store), "--n", "4", "--nu-f", "0.2", "--format", "csv"])
    header, row = rows.stdout.splitlines()[:2]
    assert header.startswith("law,n,ell,nu,nu_f,amplitude,seed,events,periodic,sigma,v_threshold,status,"), header
    assert row.startswith("carlson-langer,4,1.0,0.001,0.2,0.1,1,200,free,0.0,0.0,complete,"), row
    by_word = runner.invoke(cli, ["query", "--store", str(store), "--periodic", "free", "--n", "4",
                                  "--nu-f", "0.2", "--format", "csv"])
    assert by_word.exit_code == 0 and by_word.stdout == rows.stdout   # the word selects what 0 does
    refused = runner.invoke(cli, ["export", "--store", str(store), "--out", str(tmp_path / "runs.csv")])
    assert refused.exit_code == 2 and "per-event catalogs" in refused.output   # not dropped silently
    assert not (tmp_path / "runs.csv").exists()
    again = runner.invoke(cli, ["submit", str(repo / "workflows" / "chain-study.toml"), "--store", str(store),
                                "--workers", "1", "--json"])
    assert again.exit_code == 0 and json.loads(again.stdout[again.stdout.index("{"):])["skipped"] == 4


@pytest.mark.parametrize("change, key", [
    (("values = [1, 6]", "values = [0, 6]"), "grid.n"),                      # N < 1
    (("values = [1, 6]", "values = [1, 4.5]"), "grid.n"),                    # not a whole number of blocks
    (("[grid.ell]\nvalues = [1.0]", "[grid.ell]\nvalues = [-0.5]"), "grid.ell"),   # ℓ < 0
    (("[grid.ell]\nvalues = [1.0]", "[grid.ell]\nvalues = [nan]"), "grid.ell"),    # NaN
    (("values = [0.3, 0.45]", "values = [0.3, inf]"), "grid.nu_f"),
    (("values = [12, 30]", "values = [0, 30]"), "grid.events"),             # events ≤ 0
    (("values = [12, 30]", "values = [-3]"), "grid.events"),
    (("values = [0, 1]", "values = [0, 2]"), "grid.periodic"),
    (("catalog = 8", "catalog = 0"), "tiles.catalog"),
    (("catalog = 8", "catalog = 2.5"), "tiles.catalog"),
    (("[grid.amplitude]\nvalues = [0.5]", "[grid.amplitude]\nvalues = [-1.0]"), "grid.amplitude"),
])
def test_bad_chain_workflows_are_one_line_exit_2_and_write_nothing(change, key, tmp_path):
    text = WORKFLOW.replace(*change)
    assert text != WORKFLOW
    wf = tmp_path / "bad.toml"
    wf.write_text(text)
    store = tmp_path / "bad.zarr"
    result = CliRunner().invoke(cli, ["submit", str(wf), "--store", str(store), "--workers", "1"])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and key in lines[0] and "Traceback" not in result.output, result.output
    assert not store.exists()


def test_the_catalog_chunk_is_part_of_the_study():
    w = parse_workflow(WORKFLOW)
    again = parse_workflow(w.to_toml())
    assert again.catalog_chunk == 8 and again.fingerprint == w.fingerprint
    assert parse_workflow(WORKFLOW.replace("catalog = 8", "catalog = 9")).fingerprint != w.fingerprint
    assert parse_workflow(WORKFLOW.replace("catalog = 8\n", "")).catalog_chunk == 1000   # the default


def test_catalog_key_is_refused_for_a_model_without_catalogs():
    from bifurcation.errors import InputError

    with pytest.raises(InputError, match="tiles.catalog"):
        parse_workflow('[study]\nname = "x"\n[engine]\nlaws = ["carlson-langer"]\n[grid.nu]\nvalues = [1e-9]\n'
                       '[grid.nu_f]\nvalues = [0.4]\n[tiles]\ncatalog = 10\n')


def test_catalog_queries_that_do_not_name_one_done_run_are_one_line(store, workflow, tmp_path):
    runner = CliRunner()
    several = runner.invoke(cli, ["query", "--store", str(store), "--n", "6", "--catalog"])
    assert several.exit_code == 2 and "selects more than one run" in several.output
    assert len(several.output.strip().splitlines()) == 1
    missing = tmp_path / "empty.zarr"
    create_store(missing, workflow)
    args = ["query", "--store", str(missing), "--law", "carlson-langer", "--n", "1", "--nu-f", "0.3",
            "--events", "12", "--periodic", "0", "--catalog"]
    empty = runner.invoke(cli, args)
    assert empty.exit_code == 2 and "not computed this run yet" in empty.output
    bad = runner.invoke(cli, ["query", "--store", str(store), "--n", "7", "--catalog"])
    assert bad.exit_code == 2 and "--n" in bad.output and len(bad.output.strip().splitlines()) == 1


def test_a_damaged_catalog_chunk_is_named_by_query_and_verify_and_repaired(store, serial, workflow, tmp_path):
    """One flipped bit in one run's catalog chunk: its query is one line naming the chunk (no number shown),
    verify names it, verify --repair recomputes that run's tile, and the store equals the serial run again."""
    import shutil

    copy = tmp_path / "damaged.zarr"
    shutil.copytree(store, copy)
    run = int(np.ravel_multi_index((0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0), workflow.shape))
    chunk = copy / "catalog" / "duration" / "c" / str(run * 32 // 8 + 2)
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x10
    chunk.write_bytes(data)
    (copy / "catalog" / "n_blocks" / "c" / str(run * 32 // 8)).unlink()
    runner = CliRunner()
    args = ["query", "--store", str(copy), "--law", "carlson-langer", "--n", "6", "--nu-f", "0.45", "--events",
            "30", "--periodic", "0", "--catalog"]
    out = runner.invoke(cli, args)
    assert out.exit_code == 2 and len(out.output.strip().splitlines()) == 1, out.output
    assert "catalog/" in out.output and "verify --store" in out.output
    verify = runner.invoke(cli, ["verify", "--store", str(copy)])
    assert verify.exit_code == 1
    assert f"catalog/duration/c/{run * 4 + 2}: checksum mismatch" in verify.output
    assert f"catalog/n_blocks/c/{run * 4}: catalog chunk of a done run missing" in verify.output
    repair = runner.invoke(cli, ["verify", "--store", str(copy), "--repair", "--workers", "1"])
    assert repair.exit_code == 0 and "after repair: sound" in repair.output, repair.output
    cat = read_catalog(copy, law="carlson-langer", n=6, nu_f=0.45, events=30, periodic=0)
    for name in CATALOG:
        assert_same(cat[name], serial[name][0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0], name)


def test_a_damaged_or_foreign_checkpoint_is_ignored_and_the_run_starts_over(workflow, serial, tmp_path, monkeypatch):
    """A checkpoint whose bytes were changed (CRC-32), or one written by another store (run_id), is not
    trusted: the run starts from event 0 and its catalog is still the uninterrupted one."""
    from bifurcation.store.catalog import Checkpoints

    path = tmp_path / "bad-ck.zarr"
    run_id = create_store(path, workflow)["run_id"]
    tile = next(t for t in iter_tiles(workflow) if t.index == (0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0))
    original = Checkpoints.save

    def dying(self, i, *args, **kwargs):
        original(self, i, *args, **kwargs)
        raise KeyboardInterrupt("killed")

    monkeypatch.setattr(Checkpoints, "save", dying)
    with pytest.raises(KeyboardInterrupt):
        compute_tile(tile, tile_checkpoints(path, run_id, tile))
    monkeypatch.undo()
    (file,) = (path / "checkpoints").glob("*.npz")
    with np.load(file) as data:
        assert json.loads(str(data["meta"]))["events"] == 8
    good = file.read_bytes()
    with np.load(file) as data:   # flip one bit of the state (σ), keep the metadata
        arrays = {k: data[k].copy() for k in data.files}
    arrays["sigma"][3] ^= 1
    np.savez(file, **arrays)
    assert tile_checkpoints(path, run_id, tile).load(0) is None
    file.write_bytes(good)
    assert tile_checkpoints(path, run_id, tile).load(0)["events"] == 8       # the sound one is trusted
    assert tile_checkpoints(path, "another-store", tile).load(0) is None   # ... by its own store only
    np.savez(file, **arrays)
    values = compute_tile(tile, tile_checkpoints(path, run_id, tile))
    assert values["resumed"].ravel()[0] == 0
    for k, got in enumerate(values["potency"].ravel()):
        assert_same(got, serial["potency"][tile.region].ravel()[k], "potency")


@pytest.mark.slow   # 4-5 s: kills and resumes real runs; the checkpoint's bit-identical resume is tested fast in process
@pytest.mark.distributed
def test_a_killed_submit_is_resumed_by_the_next_from_the_checkpoint(tmp_path):
    """`bifurcation submit` on its embedded cluster killed (-9, the whole process group: submitter and its
    workers) after the run's first checkpoint; the next submit of the same workflow finds the checkpoint,
    resumes the run from it, and the catalog equals the uninterrupted run bit for bit."""
    from _proc import bifurcation, start, stop, wait_until

    wf = tmp_path / "kill.toml"
    wf.write_text(KILL)
    store = tmp_path / "killed.zarr"
    proc = start(bifurcation("submit", wf, "--store", store, "--workers", "1"), tmp_path, "submit")
    try:
        wait_until(lambda: (store / "checkpoints" / "0.npz").exists(), 120, "the first checkpoint", proc=proc,
                   detail=lambda: (tmp_path / "submit.log").read_text())
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(10)
    finally:
        stop(proc)
    assert not open_store(store)["done"].values.any()
    result = CliRunner().invoke(cli, ["submit", str(wf), "--store", str(store), "--workers", "1", "--json"])
    assert result.exit_code == 0, result.output
    cat = read_catalog(store, law="carlson-langer")
    assert 0 < cat["run"]["resumed"] < 4000 and cat["run"]["resumed"] % 200 == 0
    reference = compute_serial(parse_workflow(KILL))
    for name in CATALOG:
        assert_same(cat[name], reference[name].reshape(-1)[0], name)


def test_netcdf_export_holds_the_catalogs_as_cf_ragged_arrays(store, serial, workflow, tmp_path):
    """`bifurcation export` to netCDF: per-run variables as for every model, and the catalogs as CF
    contiguous ragged arrays (run_count with sample_dimension = "event", runs in C order)."""
    import xarray as xr

    out = tmp_path / "chain.nc"
    result = CliRunner().invoke(cli, ["export", "--store", str(store), "--out", str(out)])
    assert result.exit_code == 0, result.output
    ds = xr.open_dataset(out)
    assert ds["run_count"].attrs["sample_dimension"] == "event"
    counts = ds["run_count"].values
    np.testing.assert_array_equal(counts, serial["events_done"].ravel())
    offsets = np.concatenate([[0], np.cumsum(counts)])
    for run, index in enumerate(np.ndindex(workflow.shape)):
        for name in CATALOG:
            assert_same(ds[f"event_{name}"].values[offsets[run]:offsets[run + 1]], serial[name][index], name)
    assert_same(ds["t_end"].values, serial["t_end"], "t_end")
