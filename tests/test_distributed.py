"""Real processes: `dask scheduler` + two `dask worker`s on loopback, a worker killed with -9 mid-run, the
submitting process killed mid-run. Every store must equal the serial in-process engine bit for bit.

Processes are started in their own sessions and killed (whole process group) by the fixtures' finalizers.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from bifurcation.run import submit
from bifurcation.store import open_store, read_done
from bifurcation.tiles import OUTPUTS, compute_serial

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
BIN = Path(sys.executable).parent


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _env() -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith("DASK_")}
    env["PYTHONUNBUFFERED"] = "1"
    return env


def _start(args, tmp: Path, name: str) -> subprocess.Popen:
    log = open(tmp / f"{name}.log", "wb")
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, cwd=tmp, env=_env(), start_new_session=True)


def _stop(proc: subprocess.Popen) -> None:
    for sig, wait in ((signal.SIGTERM, 10), (signal.SIGKILL, 10)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(wait)
            break
        except subprocess.TimeoutExpired:
            continue
    try:   # children (nanny → worker) left in the group
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


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
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    scheduler_file = tmp / "scheduler.json"
    procs = []
    try:
        procs.append(_start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                             "--no-dashboard", "--scheduler-file", str(scheduler_file)], tmp, "scheduler"))
        for i in range(2):
            procs.append(_start([str(BIN / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1",
                                 "--host", "127.0.0.1", "--no-dashboard", "--name", f"w{i}",
                                 "--death-timeout", "60"], tmp, f"worker{i}"))
        with Client(address, timeout="60s", set_as_default=False) as client:
            client.wait_for_workers(2, timeout=90)
        yield address, scheduler_file
    finally:
        for proc in reversed(procs):
            _stop(proc)


def assert_store_equals(path, reference) -> None:
    ds = open_store(path)
    for name in OUTPUTS:
        stored, expected = np.asarray(ds[name].values), reference[name]
        if stored.dtype.kind == "f":
            stored, expected = stored.view(np.int64), expected.view(np.int64)
        np.testing.assert_array_equal(stored, expected, err_msg=name)


def test_real_scheduler_and_workers_equal_serial(dask_cluster, workflow_file, reference, tmp_path):
    address, _ = dask_cluster
    w, expected = reference
    store = tmp_path / "real.zarr"
    out = subprocess.run([str(BIN / "bifurcation"), "submit", str(workflow_file), "--scheduler", address,
                          "--workers", "2", "--store", str(store), "--json"],
                         capture_output=True, text=True, timeout=120, env=_env(), cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    summary = json.loads(out.stdout)
    assert (summary["computed"], summary["failed"], summary["tiles"]) == (w.n_points, 0, 24)
    assert summary["cluster"] == f"address {address}"
    assert_store_equals(store, expected)


def test_worker_killed_mid_run_still_completes(dask_cluster, reference, workflow_file, tmp_path):
    from distributed import Client

    _, scheduler_file = dask_cluster
    w, expected = reference
    with Client(scheduler_file=str(scheduler_file), set_as_default=False) as client:
        pids = client.run(os.getpid)
    victim = sorted(pids.values())[0]
    killed = []

    def kill_after_first_tile(done, total):
        if not killed:   # both workers are busy with their next tiles: kill one of them mid-task
            os.kill(victim, signal.SIGKILL)
            killed.append(done)

    summary = submit(workflow_file, store=tmp_path / "kill.zarr", scheduler=str(scheduler_file),
                     progress=kill_after_first_tile)
    assert killed and killed[0] < w.n_points
    with pytest.raises(ProcessLookupError):
        os.kill(victim, 0)
    assert (summary.computed, summary.failed) == (w.n_points, 0) and summary.complete
    assert_store_equals(tmp_path / "kill.zarr", expected)


def test_submitting_process_killed_mid_run_then_resumed(dask_cluster, reference, workflow_file, tmp_path):
    address, _ = dask_cluster
    w, expected = reference
    store = tmp_path / "client.zarr"
    # the embedded default: no --scheduler, no DASK_SCHEDULER_ADDRESS → a local cluster in that process
    proc = _start([str(BIN / "bifurcation"), "submit", str(workflow_file), "--store", str(store), "--workers", "2"],
                  tmp_path, "submit")
    try:
        deadline = time.monotonic() + 90
        done_chunks = store / "done" / "c"
        while time.monotonic() < deadline and proc.poll() is None:
            if done_chunks.exists() and sum(1 for p in done_chunks.rglob("*") if p.is_file()) >= 2:
                break
            time.sleep(0.01)
        assert proc.poll() is None, "the submit finished before it could be killed"
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(10)
    finally:
        _stop(proc)   # and its orphaned worker processes
    done = read_done(store)
    n_done = int(done.sum())
    assert 0 < n_done < w.n_points
    assert n_done % (16 * 64) == 0   # whole tiles: nothing half written claims to be done
    finished = {}   # chunk files of the finished tiles, with their modification times
    for name in OUTPUTS:
        root = store / name / "c"
        for p in root.rglob("*"):
            if p.is_file() and _tile_done(done, p.relative_to(root).parts):
                finished[p] = p.stat().st_mtime_ns
    assert finished

    summary = submit(workflow_file, store=store, scheduler=address, progress=False)
    assert (summary.computed, summary.skipped, summary.failed) == (w.n_points - n_done, n_done, 0)
    assert all(p.stat().st_mtime_ns == t for p, t in finished.items())   # nothing finished recomputed
    assert_store_equals(store, expected)


def _tile_done(done: np.ndarray, parts) -> bool:
    law, i, j = (int(k) for k in parts)
    return bool(done[law, i * 16:(i + 1) * 16, j * 64:(j + 1) * 64].all())
