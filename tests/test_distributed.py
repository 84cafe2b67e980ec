"""Real processes: `dask scheduler` + two `dask worker`s on loopback, a worker killed with -9 mid-run, the
submitting process killed mid-run. Every store must equal the serial in-process engine bit for bit.

Processes are started in their own sessions and killed (whole process group) in ``finally`` blocks (``_proc``).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time

import numpy as np
import pytest

from bifurcation.run import submit
from bifurcation.store import read_done
from bifurcation.run.tiles import OUTPUTS, compute_serial

from _proc import BIN, env, free_port, start, stop, wait_until
from _store_helpers import assert_store_equals

pytestmark = pytest.mark.distributed

# 2 laws × 48 ν_f × 256 ν = 24576 points (~1 s of one core) in 24 tiles of 16 × 64
TOML = """
[study]
name = "distributed-test"

[engine]
laws = ["piecewise-linear", "carlson-langer"]

[grid.nu]
log = { start = 1e-3, stop = 1e-15, num = 256 }

[grid.nu_f]
ranges = [{ start = 0.02, stop = 0.96, num = 48 }]

[tiles]
nu_f = 16
nu = 64
"""


@pytest.fixture(scope="module")
def workflow_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("wf") / "distributed.toml"
    path.write_text(TOML)
    return path


@pytest.fixture(scope="module")
def reference(workflow_file):
    from bifurcation.workflow import load_workflow

    w = load_workflow(workflow_file)
    assert w.n_points == 24576
    return w, compute_serial(w)


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory):
    """`dask scheduler` and two `dask worker` processes on 127.0.0.1; yields (address, scheduler file)."""
    from distributed import Client

    tmp = tmp_path_factory.mktemp("cluster")
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    scheduler_file = tmp / "scheduler.json"
    procs = []
    try:
        procs.append(start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                            "--no-dashboard", "--scheduler-file", str(scheduler_file)], tmp, "scheduler"))
        for i in range(2):
            procs.append(start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1",
                                "--host", "127.0.0.1", "--no-dashboard", "--name", f"w{i}",
                                "--death-timeout", "60"], tmp, f"worker{i}"))
        with Client(address, timeout="60s", set_as_default=False) as client:
            client.wait_for_workers(2, timeout=90)
        yield address, scheduler_file
    finally:
        for proc in reversed(procs):
            stop(proc)


def test_real_scheduler_and_workers_equal_serial(dask_cluster, workflow_file, reference, tmp_path):
    address, _ = dask_cluster
    w, expected = reference
    store = tmp_path / "real.zarr"
    out = subprocess.run([str(BIN / "bifurcation"), "submit", str(workflow_file), "--scheduler", address,
                          "--workers", "2", "--store", str(store), "--json"],
                         capture_output=True, text=True, timeout=120, env=env(), cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert (summary["computed"], summary["failed"], summary["tiles"]) == (w.n_points, 0, 24)
    assert summary["cluster"] == f"address {address}"
    assert_store_equals(store, expected)


def test_worker_killed_mid_run_still_completes(dask_cluster, reference, workflow_file, tmp_path):
    from distributed import Client

    _, scheduler_file = dask_cluster
    w, expected = reference

    def tile_transitions(dask_scheduler) -> list[tuple]:   # runs in the scheduler (local: pickled by value)
        return [(t.key, t.start, t.finish, t.timestamp) for t in dask_scheduler.transition_log
                if str(t.key).startswith("bifurcation-tile-")]

    # The kill races the tile's end: the scheduler may still say "processing" while the victim has finished
    # its tile. Then nothing was lost and the path under test was not exercised; try again (a fresh store,
    # the nanny's new worker), at most 3 times, and require that one attempt lost a tile.
    for attempt in range(3):
        store = tmp_path / f"kill{attempt}.zarr"
        with Client(scheduler_file=str(scheduler_file), set_as_default=False) as client:
            client.wait_for_workers(2, timeout=60)
            address, victim = min(client.run(os.getpid).items(), key=lambda item: item[1])
            killed = []   # the time of the kill

            def kill_while_it_holds_a_tile(done, total):
                # after the first tile both workers hold tiles; kill the victim while the scheduler says so
                if not killed and client.processing(workers=[address])[address]:
                    killed.append(time.time())
                    os.kill(victim, signal.SIGKILL)

            summary = submit(workflow_file, store=store, scheduler=str(scheduler_file),
                             progress=kill_while_it_holds_a_tile)
            transitions = client.run_on_scheduler(tile_transitions)
            workers = client.scheduler_info()["workers"]
        (kill_time,) = killed
        with pytest.raises(ProcessLookupError):
            os.kill(victim, 0)
        assert address not in workers   # the scheduler removed the dead worker (its nanny starts a new one)
        # every attempt completes and equals the serial run, whatever the kill hit
        assert (summary.computed, summary.failed) == (w.n_points, 0) and summary.complete
        assert_store_equals(store, expected)
        # tasks lost with the worker: processing → released after the kill (nothing else releases a tile
        # task before its result); each was then run again to the end (→ memory)
        lost = {key: when for key, start, finish, when in transitions
                if when >= kill_time and (start, finish) == ("processing", "released")}
        rerun = {key for key, _, finish, when in transitions if key in lost and finish == "memory" and when > lost[key]}
        if lost:
            break
    assert lost and rerun == set(lost)


@pytest.mark.slow   # 3-6 s each; real scheduler = serial and a killed worker stay fast
def test_submitting_process_killed_mid_run_then_resumed(dask_cluster, reference, tmp_path):
    from bifurcation.workflow import load_workflow

    address, _ = dask_cluster
    grid, expected = reference
    # The grid of the other tests (so the same serial reference) in 96 tiles of 8 × 32, computed by one
    # worker: the submit then needs ~2.5 s after its first two tiles (measured; ~1 s with 24 tiles and
    # two workers), so the 10 ms poll below kills it mid-run even on a loaded machine.
    workflow_file = tmp_path / "small-tiles.toml"
    workflow_file.write_text(TOML.replace("nu_f = 16\nnu = 64", "nu_f = 8\nnu = 32"))
    w = load_workflow(workflow_file)
    assert (w.laws, w.nu_f, w.nu, w.tiles) == (grid.laws, grid.nu_f, grid.nu, (8, 32))
    store = tmp_path / "client.zarr"
    # the embedded default: no --scheduler, no DASK_SCHEDULER_ADDRESS → a local cluster in that process
    proc = start([str(BIN / "bifurcation"), "submit", str(workflow_file), "--store", str(store), "--workers", "1"],
                 tmp_path, "submit")
    try:
        done_chunks = store / "done" / "c"
        wait_until(lambda: done_chunks.exists() and sum(1 for p in done_chunks.rglob("*") if p.is_file()) >= 2, 90,
                   "two finished tiles (the submit finished before it could be killed?)", proc=proc)
        assert proc.poll() is None, "the submit finished before it could be killed"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(10)
    finally:
        stop(proc)   # and its orphaned worker processes
    done = read_done(store)
    n_done = int(done.sum())
    assert 0 < n_done < w.n_points
    # whole tiles: nothing half written claims to be done
    assert all(_tile_done(done, w.tiles, tile) or not done[_tile_region(w.tiles, tile)].any()
               for tile in np.ndindex(_tile_grid(done.shape, w.tiles)))
    finished = {}   # chunk files of the finished tiles, with their modification times
    for name in OUTPUTS:
        root = store / name / "c"
        for p in root.rglob("*"):
            if p.is_file() and _tile_done(done, w.tiles, p.relative_to(root).parts):
                finished[p] = p.stat().st_mtime_ns
    assert finished

    summary = submit(workflow_file, store=store, scheduler=address, progress=False)
    assert (summary.computed, summary.skipped, summary.failed) == (w.n_points - n_done, n_done, 0)
    assert all(p.stat().st_mtime_ns == t for p, t in finished.items())   # nothing finished recomputed
    assert_store_equals(store, expected)


def _tile_grid(shape, tiles) -> tuple[int, int, int]:
    """Tiles along (law, ν_f, ν)."""
    law, nu_f, nu = shape
    return (law, -(-nu_f // tiles[0]), -(-nu // tiles[1]))


def _tile_region(tiles, tile) -> tuple[int, slice, slice]:
    """The points of chunk ``tile`` (its (law, ν_f, ν) chunk indices) in the (law, ν_f, ν) arrays."""
    law, i, j = (int(k) for k in tile)
    return (law, slice(i * tiles[0], (i + 1) * tiles[0]), slice(j * tiles[1], (j + 1) * tiles[1]))


def _tile_done(done: np.ndarray, tiles, tile) -> bool:
    return bool(done[_tile_region(tiles, tile)].all())


@pytest.mark.slow   # 3-6 s each; real scheduler = serial and a killed worker stay fast
def test_detached_submit_completes_after_the_client_is_killed(dask_cluster, reference, workflow_file, tmp_path):
    """`submit --detach` to a real scheduler, the client killed (-9) right after it hands the run over:
    the workers finish the study, the finalize task records it and releases the lock, `status` shows it,
    and the store equals the serial run bit for bit."""
    from click.testing import CliRunner

    from bifurcation.cli import cli
    from bifurcation.store import read_attrs
    from bifurcation.store.lock import lock_path
    from bifurcation.store.status import study_status

    address, _ = dask_cluster
    w, expected = reference
    store = tmp_path / "detached.zarr"
    log = tmp_path / "client.log"
    client = start([str(BIN / "bifurcation"), "submit", str(workflow_file), "--scheduler", address,
                    "--store", str(store), "--detach"], tmp_path, "client")
    try:
        wait_until(lambda: b"detached:" in log.read_bytes() or client.poll() is not None, 120,
                   "the client to hand the run over", interval=0.5)
        assert b"detached:" in log.read_bytes(), log.read_text()
    finally:
        stop(client, signal.SIGKILL)   # killed (-9, the group) right after (or as) it returns
    wait_until(lambda: study_status(store).complete and not lock_path(store).exists(), 300,
               "the detached run to finish", interval=0.5)
    assert_store_equals(store, expected)
    [entry] = read_attrs(store)["submits"]
    assert entry["computed"] == w.n_points and entry["failed"] == 0
    assert entry["cluster"] == f"detached on {address}"
    result = CliRunner().invoke(cli, ["status", "--store", str(store)])
    # the last line says the study is complete and how to read it (issue 21: no bare "complete")
    lines = result.output.rstrip().splitlines()   # (then the line that names verify for the chunks)
    assert result.exit_code == 0 and lines[-2].startswith("complete:") and "verify" in lines[-1], result.output


@pytest.mark.slow   # 3-6 s each; real scheduler = serial and a killed worker stay fast
def test_a_submit_joins_a_live_detached_run(dask_cluster, reference, workflow_file, tmp_path, capsys):
    """A submit that finds a detached run alive on its store waits for it (joins), then resumes."""
    import json as _json
    import socket as _socket

    from distributed import Client, fire_and_forget

    from bifurcation.store import create_store
    from bifurcation.store.lock import holder, lock_path

    address, _ = dask_cluster
    w, expected = reference
    store = tmp_path / "joined.zarr"
    create_store(store, w)
    key = "bifurcation-finalize-test-join"
    with Client(address, timeout="60s", set_as_default=False) as c:
        fire_and_forget(c.submit(time.sleep, 4.0, key=key, pure=False))
        wait_until(lambda: c.run_on_scheduler(lambda dask_scheduler: key in dask_scheduler.tasks), 30,
                   "the stand-in run", interval=0.5)
    lock_path(store).write_text(_json.dumps({
        "run": "stand-in", "host": _socket.gethostname(), "pid": -2, "process_start": 0.0,
        "since": "2026-01-01T00:00:00+00:00", "command": "test", "token": "t", "scheduler": address,
        "task": key}))
    assert holder(store) is not None and holder(store).scheduler == address   # alive: the task is there
    started = time.monotonic()
    summary = submit(workflow_file, store=store, scheduler=address, progress=True)
    waited = time.monotonic() - started
    assert "joining detached run stand-in" in capsys.readouterr().err
    assert waited > 1.0                       # it waited for the stand-in to end
    assert summary.complete and summary.computed == w.n_points
    assert_store_equals(store, expected)
    assert not lock_path(store).exists()
