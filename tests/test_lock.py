"""One writer per store: the lock file, stale locks, the run id checked on every tile write, and two real
`bifurcation submit` processes on one store."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from bifurcation.errors import InputError
from bifurcation.run import submit
from bifurcation.store import create_store, write_tile
from bifurcation.store.lock import LOCK_NAME, StoreLock, holder
from bifurcation.store.zarr_store import StoreReplacedError
from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles
from bifurcation.workflow import Workflow

from _proc import bifurcation, running, wait_until
from _store_helpers import assert_store_equals

W = Workflow(name="lock-test", laws=("carlson-langer",), nu=(1e-3, 1e-6), nu_f=(0.3, 0.4, 0.6), tiles=(2, 1))


def test_a_second_lock_is_refused_naming_the_holder(tmp_path):
    path = tmp_path / "s.zarr"
    with StoreLock(path).acquire(command="first"):
        found = holder(path)
        assert (found.pid, found.host) == (os.getpid(), socket.gethostname())
        with pytest.raises(InputError, match=rf"^--store=.*is being written by run \w+ \(pid {os.getpid()} on host "):
            StoreLock(path).acquire()
        with pytest.raises(InputError, match=r"is being written by"):   # --new-store is refused too
            submit(W, store=path, new_store=True, progress=False)
    assert not (path / LOCK_NAME).exists() and holder(path) is None


def test_verify_and_repair_wait_for_the_writer(tmp_path):
    from bifurcation.run.repair import verify

    path = tmp_path / "s.zarr"
    create_store(path, W)
    with StoreLock(path).acquire():
        for repair in (False, True):   # its tiles in progress are not damage: no verdict while it runs
            with pytest.raises(InputError, match=r"is being written by run .*verify it when that run has ended"):
                verify(path, repair=repair)
    assert verify(path).ok


def test_a_stale_lock_of_a_dead_process_is_taken_over(tmp_path):
    path = tmp_path / "s.zarr"
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    path.mkdir()
    (path / LOCK_NAME).write_text(json.dumps({"run": "old", "host": socket.gethostname(), "pid": dead.pid,
                                              "process_start": time.time() - 5, "since": "earlier"}))
    assert holder(path) is None
    with StoreLock(path).acquire() as lock:
        assert json.loads((path / LOCK_NAME).read_text())["token"] == lock.token


def test_a_lock_of_another_host_is_never_broken(tmp_path):
    path = tmp_path / "s.zarr"
    path.mkdir()
    (path / LOCK_NAME).write_text(json.dumps({"run": "r1", "host": "elsewhere.example", "pid": 1,
                                              "process_start": 1.0, "since": "2026-01-01T00:00:00+00:00"}))
    with pytest.raises(InputError, match=rf"pid 1 on host elsewhere.example.*remove {path / LOCK_NAME}"):
        StoreLock(path).acquire()


def test_the_run_id_is_checked_on_every_write_not_only_the_first(tmp_path):
    path = tmp_path / "s.zarr"
    old = create_store(path, W)["run_id"]
    tiles = list(iter_tiles(W))
    write_tile(path, tiles[0], compute_tile(tiles[0]), old)   # the writer now caches its array handles
    other = Workflow(name="other", laws=("piecewise-linear",), nu=(1e-3, 1e-6), nu_f=(0.3, 0.4, 0.6),
                     tiles=(2, 1))
    create_store(path, other, overwrite=True)                 # replaced under the same path
    before = sorted(p for p in path.rglob("*") if p.is_file())
    with pytest.raises(StoreReplacedError, match="not the one this run created"):
        write_tile(path, tiles[1], compute_tile(tiles[1]), old)
    assert sorted(p for p in path.rglob("*") if p.is_file()) == before   # nothing written


TOML = """
[study]
name = "two-writers"

[engine]
laws = ["piecewise-linear", "carlson-langer"]

[grid.nu]
log = { start = 1e-3, stop = 1e-15, num = 256 }

[grid.nu_f]
ranges = [{ start = 0.02, stop = 0.96, num = 96 }]

[tiles]
nu_f = 8
nu = 64
"""


@pytest.mark.slow   # 7 s: two real submits; the lock's refusal is tested fast above
@pytest.mark.distributed
def test_two_real_submits_on_one_store(tmp_path):
    """A second `submit` and a `--new-store` while the first runs: both refused in one line naming it."""
    (tmp_path / "w.toml").write_text(TOML)
    (tmp_path / "b.toml").write_text(TOML.replace('"two-writers"', '"other"').replace("num = 48", "num = 12"))
    store = tmp_path / "s.zarr"
    with running(bifurcation("submit", "w.toml", "--store", store, "--workers", "1", "--json"), tmp_path,
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as first:
        # the lock is taken before the cluster starts; then ~50 000 points (several seconds of one
        # core) are computed: both others start (concurrently) well inside that window
        wait_until(lambda: (store / LOCK_NAME).exists(), 120, "the first submit's lock", proc=first)
        assert first.poll() is None, "the first submit ended before the others could start"
        with running(bifurcation("submit", "w.toml", "--store", store, "--workers", "1"), tmp_path,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as second, \
                running(bifurcation("submit", "b.toml", "--new-store", "--store", store, "--workers", "1"), tmp_path,
                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as third:
            runs = [subprocess.CompletedProcess(p.args, p.wait(120), *p.communicate()) for p in (second, third)]
        out, err = first.communicate(timeout=600)
    assert first.returncode == 0, err
    summary = json.loads(out)
    assert (summary["computed"], summary["failed"]) == (2 * 256 * 96, 0)
    for run in runs:
        assert run.returncode == 2 and run.stdout == ""
        (line,) = run.stderr.strip().splitlines()
        assert line.startswith(f"bifurcation: error: --store='{store}': is being written by run ")
        assert f"(pid {first.pid} on host {socket.gethostname()}" in line
    from bifurcation.workflow import load_workflow

    assert_store_equals(store, compute_serial(load_workflow(tmp_path / "w.toml")))
    assert not (store / LOCK_NAME).exists()
    assert np.all(json.loads((store / "zarr.json").read_text())["attributes"]["title"] == "two-writers")
