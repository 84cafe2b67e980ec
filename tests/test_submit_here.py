"""submit on the embedded default: small studies run in this process, large ones hand the rest to a
local cluster; the store is the same bit for bit either way (and equals the serial reference)."""

from __future__ import annotations

import os

import numpy as np
import pytest

import bifurcation.run.submission as submission
from bifurcation.run import submit
from bifurcation.run.tiles import compute_serial, tile_count
from bifurcation.workflow import Workflow

from _store_helpers import assert_store_equals


@pytest.fixture(autouse=True)
def no_scheduler(monkeypatch):
    # the embedded default only: no DASK_SCHEDULER_ADDRESS from the environment
    import dask

    monkeypatch.delenv("DASK_SCHEDULER_ADDRESS", raising=False)
    with dask.config.set({"scheduler-address": None}):
        yield


def workflow(**changes) -> Workflow:
    options = dict(name="here-test", laws=("piecewise-linear", "carlson-langer"),
                   nu=(1e-3, 1e-6, 1e-9, 1e-12, 1e-15), nu_f=tuple(round(0.05 * k, 2) for k in range(1, 20)),
                   tiles=(5, 3))
    options.update(changes)
    return Workflow(**options)


def test_a_small_study_runs_in_this_process(tmp_path, monkeypatch):
    w = workflow()
    started = []
    monkeypatch.setattr(submission, "connect", lambda *a, **k: started.append(a) or pytest.fail("cluster"))
    summary = submit(w, store=tmp_path / "s.zarr", workers=2, progress=False)
    assert summary.complete and summary.computed == w.n_points and summary.cluster == "this process"
    assert summary.tiles == tile_count(w) and not started
    assert_store_equals(tmp_path / "s.zarr", compute_serial(w))
    # the store's history says where it ran
    again = submit(w, store=tmp_path / "s.zarr", progress=False)
    assert (again.computed, again.skipped) == (0, w.n_points)


def test_a_tile_that_raises_is_retried_then_reported(tmp_path, monkeypatch):
    w = workflow(laws=("carlson-langer",))
    calls = []
    real = submission.run_tile

    def flaky(tile, store, run_id):
        calls.append(tile.name)
        if tile.name == "0-0-0" and calls.count("0-0-0") <= 2:
            raise OSError("disk hiccup")
        if tile.name == "0-5-0":
            raise ValueError("always broken")
        return real(tile, store, run_id)

    monkeypatch.setattr(submission, "run_tile", flaky)
    summary = submit(w, store=tmp_path / "s.zarr", progress=False, retries=2)
    assert calls.count("0-0-0") == 3 and calls.count("0-5-0") == 3
    assert summary.failed == 5 * 3 and summary.computed == w.n_points - 15 and not summary.complete
    assert summary.errors == ("tile 0-5-0 (carlson-langer): ValueError: always broken",)
    monkeypatch.setattr(submission, "run_tile", real)   # a resubmit computes the failed tile only
    again = submit(w, store=tmp_path / "s.zarr", progress=False)
    assert again.complete and again.computed == 15
    assert_store_equals(tmp_path / "s.zarr", compute_serial(w))


@pytest.mark.slow   # ~10-20 s: starts two helper processes, twice
@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="a hand-over needs 2 cores")
def test_a_large_study_hands_the_rest_to_the_embedded_cluster(tmp_path, monkeypatch):
    # A study made "large" by a zero threshold: after two tiles here (the first compiles, the second
    # measures) 3 - 1 = 2 real helper processes start and share the rest with this process (the tiles
    # queued to them are theirs, however long they take to start); both write tiles, and the store
    # equals the serial run bit for bit.
    monkeypatch.setattr(submission, "HANDOVER_CPU_SECONDS", 0.0)
    where = []
    real = submission.run_tile
    monkeypatch.setattr(submission, "run_tile", lambda *a: where.append(os.getpid()) or real(*a))
    w = workflow(nu_f=tuple(round(0.01 * k, 2) for k in range(1, 100)))   # 66 tiles
    for writer in ("workers", "client"):
        where.clear()
        summary = submit(w, store=tmp_path / f"{writer}.zarr", workers=3, progress=False, writer=writer)
        assert summary.complete and summary.computed == w.n_points and not summary.errors
        assert summary.cluster == "this process and an embedded local cluster of 2 worker processes"
        assert summary.tiles == tile_count(w) and 2 <= len(where) < tile_count(w)   # both computed tiles
        assert_store_equals(tmp_path / f"{writer}.zarr", compute_serial(w))


def test_one_worker_never_starts_a_cluster(tmp_path, monkeypatch):
    monkeypatch.setattr(submission, "HANDOVER_CPU_SECONDS", 0.0)
    monkeypatch.setattr(submission, "connect", lambda *a, **k: pytest.fail("cluster"))
    w = workflow(laws=("carlson-langer",))
    summary = submit(w, store=tmp_path / "s.zarr", workers=1, progress=False)
    assert summary.complete and summary.cluster == "this process"
    assert_store_equals(tmp_path / "s.zarr", compute_serial(w))


@pytest.mark.slow   # two fresh Python processes that import heyoka and compile: ~5-10 s
def test_bench_embedded_smoke():
    from bifurcation.bench.pipeline import bench_embedded

    out = bench_embedded(points=2000, workers=1, tiles=(8, 64))
    assert out["complete"] and out["where"] == "this process" and out["processes_computing"] == 1
    assert out["points"] == 32 * 64
    # VmHWM of fresh processes: ~100-250 MB each (numpy, heyoka, and for the submit xarray and zarr);
    # the bounds catch a unit error (kB taken as MB or bytes: a factor 1024) and the inherited peak of
    # the parent that ru_maxrss reported, not small changes
    assert 50 < out["serial_peak_rss_mb"] < 1000 and 50 < out["submit_peak_rss_mb"] < 1000
    assert out["serial_cpu_s"] > 0 and out["submit_cpu_s"] > 0


@pytest.mark.slow   # ~5-10 s: starts a helper process and kills it
@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="a hand-over needs 2 cores")
def test_a_killed_helper_leaves_its_tiles_to_this_process(tmp_path, monkeypatch):
    # kill -9 of a helper breaks the pool: the tiles it held or had queued come back and are computed
    # here; the study completes, no tile is reported failed, and the store equals the serial run
    import signal
    import time

    monkeypatch.setattr(submission, "HANDOVER_CPU_SECONDS", 0.0)
    killed = []

    class Killer(submission._Helpers):
        def submit(self, *args):
            future = super().submit(*args)
            if not killed:
                deadline = time.monotonic() + 60
                while not self.pool._processes and time.monotonic() < deadline:   # spawned on first submit
                    time.sleep(0.01)
                pid = next(iter(self.pool._processes))
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
            return future

    monkeypatch.setattr(submission, "_Helpers", Killer)
    w = workflow(nu_f=tuple(round(0.01 * k, 2) for k in range(1, 100)))   # 66 tiles
    summary = submit(w, store=tmp_path / "k.zarr", workers=2, progress=False)
    assert killed and summary.complete and summary.computed == w.n_points and not summary.errors
    assert summary.failed == 0 and summary.cluster == "this process"   # the helper finished no tile
    assert_store_equals(tmp_path / "k.zarr", compute_serial(w))


_ORPHAN = """
import bifurcation.run.submission as submission
from bifurcation.run import submit
from bifurcation.workflow import Workflow
if __name__ == "__main__":
    submission.HANDOVER_CPU_SECONDS = 0.0
    w = Workflow(name="orphan", laws=("carlson-langer",), nu=tuple(10.0 ** -k for k in range(3, 16)),
                 nu_f=tuple(round(1e-4 * k, 4) for k in range(1, 9999)), tiles=(64, 13))
    submit(w, store={store!r}, workers=2, progress=False)
"""


@pytest.mark.slow   # ~5-20 s: a real submit whose helper is orphaned by kill -9
@pytest.mark.skipif(not os.path.isdir("/proc") or (os.cpu_count() or 1) < 2, reason="reads /proc; needs 2 cores")
def test_a_helper_exits_when_its_submitting_process_is_killed(tmp_path):
    # kill -9 of the submitting process: its helper (blocked on the pool's pipe, or in a tile) exits
    # within about a second instead of living on as an orphan (``submission._helper_start``)
    import signal
    import subprocess
    import sys
    import time

    import _proc

    script = tmp_path / "parent.py"
    script.write_text(_ORPHAN.format(store=str(tmp_path / "o.zarr")))
    env = {k: v for k, v in os.environ.items() if not k.startswith("DASK_")}
    parent = subprocess.Popen([sys.executable, str(script)], cwd=tmp_path, env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def helpers() -> list[int]:
        found = []
        for entry in os.listdir("/proc"):
            try:
                with open(f"/proc/{entry}/stat") as f:
                    ppid = int(f.read().rsplit(")", 1)[1].split()[1])
                with open(f"/proc/{entry}/cmdline", "rb") as f:
                    spawned = b"spawn_main" in f.read()
            except (OSError, ValueError, IndexError):
                continue
            if ppid == parent.pid and spawned:
                found.append(int(entry))
        return found

    pids = []
    try:
        deadline = time.monotonic() + 120
        while not (pids := helpers()):
            assert parent.poll() is None, "the submit ended before its helper started"
            assert time.monotonic() < deadline, "no helper within 120 s"
            time.sleep(0.05)
        time.sleep(1.0)   # the helper is in its first tiles (or still importing)
        parent.send_signal(signal.SIGKILL)
        parent.wait(10)
        deadline = time.monotonic() + 30
        alive = pids
        while alive and time.monotonic() < deadline:
            time.sleep(0.1)
            alive = [pid for pid in pids if _proc.alive(pid)]
        assert not alive, f"helper(s) {alive} still running 30 s after their submitting process was killed"
    finally:
        if parent.poll() is None:
            parent.kill()
        for pid in pids:   # a failed check leaves no process behind
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
