"""Benchmark of the whole pipeline against the in-memory engine on the same points.

(a) ``slip`` over the grid in this process, no store (the engine alone, one core);
(b) ``submit`` of the same grid to a local cluster of ``workers`` processes, store writes, metadata
    and consolidation included. The cluster is started first (workers preloaded with the package,
    then warmed by a small untimed submit) and timed apart (``cluster_start_s``): ``ratio`` = (a) / (b)
    is the throughput gain of the pipeline, ``cold_pipeline_s`` adds the start.
CPU seconds of both are reported too (``cpu_efficiency`` = serial CPU / pipeline CPU, workers and
coordinator): on a shared machine the wall-clock ratio depends on the other load, these much less.
Worker memory is the peak RSS (``ru_maxrss``) of each worker process after the run.

(c) ``bench_embedded``: ``submit`` on the embedded default (no scheduler: this process computes, and a
    local cluster shares the rest when it is worth one) against one process computing the same grid,
    each in a fresh Python process: the rate per computing process and the peak RSS against one process.
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

__all__ = ["bench_pipeline", "bench_workflow"]


def bench_workflow(points: int, *, law: str = "carlson-langer", tiles=(128, 64), batch: int = 1):
    """A grid of about ``points`` points: 64 ν log-spaced over 1e-3 … 1e-15, ν_f evenly over (0, 1)."""
    from ..workflow import Workflow
    from ..workflow._axes import linear_points, log_points

    n_nu = 64
    n_nu_f = max(2, math.ceil(points / n_nu))
    return Workflow(name=f"bench-{points}", laws=(law,), nu=log_points(1e-3, 1e-15, n_nu),
                    nu_f=linear_points(1e-3, 0.999, n_nu_f), tiles=tuple(tiles), batch=batch,
                    description="bifurcation.bench.pipeline grid")


def _peak_rss() -> int:
    """Peak resident memory of this process in bytes: Linux's VmHWM, which a new program image starts
    afresh. (``ru_maxrss`` survives exec: a worker or benchmark child started from a 400 MB parent
    reported the parent's 400 MB.)"""
    import resource

    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024   # kB
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024   # Linux: kB


def bench_pipeline(points: int = 100_000, workers: int = 2, *, law: str = "carlson-langer",
                   tiles=(128, 64), writer: str = "workers", serial: bool = True, store=None) -> dict:
    """Time (a) the in-memory engine and (b) the pipeline on one grid; returns a dict of numbers.

    ``serial=False`` skips (a) (for 10^6 points it takes a minute on one core). ``store`` defaults to a
    temporary directory, removed afterwards. Tiles of 128 × 64 = 8192 points (~0.3 s a task): writing a
    tile costs ~10–20 ms of zarr overhead whatever its size, so big grids want big tiles.
    """
    import importlib
    import logging

    from distributed import Client, LocalCluster

    from ..engine.cycle import slip
    from ..run.submission import submit

    for module in ("dask.array", "xarray", "zarr"):   # process start-up, like the cluster start, is not timed
        importlib.import_module(module)

    workflow = bench_workflow(points, law=law, tiles=tiles)
    out = {"points": workflow.n_points, "workers": workers, "law": law, "tiles": list(workflow.tiles),
           "writer": writer}
    if serial:
        nu_f, nu = np.meshgrid(np.asarray(workflow.nu_f), np.asarray(workflow.nu), indexing="ij")
        slip(law, nu=1e-3, nu_f=0.3, batch=workflow.batch)   # compile outside the timing, as every worker does
        t0, cpu0 = time.perf_counter(), time.process_time()
        slip(law, nu=nu.ravel(), nu_f=nu_f.ravel(), batch=workflow.batch)   # what the tiles compute
        out["serial_s"] = time.perf_counter() - t0
        out["serial_cpu_s"] = time.process_time() - cpu0
        out["serial_points_per_s"] = workflow.n_points / out["serial_s"]
    with tempfile.TemporaryDirectory(prefix="bifurcation-bench-") as tmp:
        path = Path(store) if store is not None else Path(tmp) / "bench.zarr"
        t0 = time.perf_counter()
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR, preload=["bifurcation.run.submission"])
        client = Client(cluster, set_as_default=False)
        out["cluster_start_s"] = time.perf_counter() - t0
        try:
            client.wait_for_workers(workers)
            # warm the workers (first zarr writes, first tasks) on a small grid of the same law, untimed
            warm = bench_workflow(workers * 2 * tiles[0] * tiles[1], law=law, tiles=tiles)
            submit(warm, store=Path(tmp) / "warm.zarr", scheduler=client, progress=False)
            workers_cpu0, cpu0 = client.run(time.process_time), time.process_time()
            summary = submit(workflow, store=path, scheduler=client, progress=False,
                             new_store=True, writer=writer)
            coordinator_cpu = time.process_time() - cpu0
            workers_cpu = sum(client.run(time.process_time).values()) - sum(workers_cpu0.values())
            rss = client.run(_peak_rss)
        finally:
            client.close()
            cluster.close()
    out["pipeline_s"] = summary.wall_time
    out["pipeline_points_per_s"] = workflow.n_points / summary.wall_time
    out["cold_pipeline_s"] = out["cluster_start_s"] + summary.wall_time
    out["complete"] = summary.complete
    # CPU seconds spent by the pipeline (workers + coordinator, which also hosts the scheduler): on a
    # shared machine the wall-clock ratio swings with the other load, these much less
    out["pipeline_cpu_s"] = workers_cpu + coordinator_cpu
    out["coordinator_cpu_s"] = coordinator_cpu
    out["worker_peak_rss_mb"] = max(rss.values()) / 2**20
    out["coordinator_peak_rss_mb"] = _peak_rss() / 2**20
    if serial:
        out["ratio"] = out["serial_s"] / out["pipeline_s"]
        out["cpu_efficiency"] = out["serial_cpu_s"] / out["pipeline_cpu_s"]
    return out


# -- the embedded default against one process, each in a fresh process -----------------------------------
_SERIAL_CHILD = """
import json, resource, sys, time
import numpy as np
from bifurcation.bench.pipeline import bench_workflow
from bifurcation.engine.solve import solve
w = bench_workflow({points}, law={law!r}, tiles={tiles!r}, batch={batch})
nu_f, nu = np.meshgrid(np.asarray(w.nu_f), np.asarray(w.nu), indexing="ij")
t0, c0 = time.perf_counter(), time.process_time()
solve(w.spec, {law!r}, {{"nu_f": nu_f, "nu": nu}}, batch=w.batch)   # compiles first, as a fresh script does
from bifurcation.bench.pipeline import _peak_rss
out = dict(wall_s=time.perf_counter() - t0, cpu_s=time.process_time() - c0, peak_rss_mb=_peak_rss() / 2**20)
print(json.dumps(out))
"""

_SUBMIT_CHILD = """
import json, resource, sys, time
from bifurcation.bench.pipeline import bench_workflow
from bifurcation.run.submission import submit
import dask.array, xarray, zarr   # imports are not timed (create_store and write_tile need them)
w = bench_workflow({points}, law={law!r}, tiles={tiles!r}, batch={batch})
if __name__ == "__main__":
    c0 = time.process_time()
    s = submit(w, store={store!r}, workers={workers}, progress=False, new_store=True)
    from bifurcation.bench.pipeline import _peak_rss
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)   # the helper processes, once they have ended
    own = time.process_time() - c0
    out = dict(wall_s=s.wall_time, complete=s.complete, cluster=s.cluster, tiles=s.tiles,
               cpu_s=own + kids.ru_utime + kids.ru_stime, own_cpu_s=own, peak_rss_mb=_peak_rss() / 2**20)
    print(json.dumps(out))
"""


def _child(code: str, cwd: str) -> dict:
    import json
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if not k.startswith("DASK_")}   # the embedded default
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=cwd,
                          timeout=1800)
    if proc.returncode:
        raise RuntimeError(f"benchmark child failed: {proc.stderr.strip().splitlines()[-1:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _best(key: str, a, b):
    if not isinstance(a, float):
        return a
    return max(a, b) if key == "peak_rss_mb" else min(a, b)


def bench_embedded(points: int = 100_000, workers: int = 2, *, law: str = "carlson-langer",
                   tiles=(128, 64), repeat: int = 1, batch: int = 1) -> dict:
    """``submit`` on the embedded default (no scheduler) against one process computing the same grid
    (``solve`` with the workflow's batch, as the store does), each in a fresh Python process, imports
    untimed, compilation timed in both. Returns wall and CPU seconds, the rate per core (points per
    second per process that computes: 1 when the study stayed in the submitting process, else the
    workers), and the submitting process's peak RSS (a worker's is not read here: ``bench_pipeline``
    reads it on an explicit cluster). ``repeat``: pairs of runs taken alternately (one process, submit,
    one process, ...), each figure the best of its side, so that load on a shared machine hits both
    alike. ``batch``: the workflow's SIMD lanes (1: the workflows' default, the scalar loop).
    """
    import os

    serial = run = None
    with tempfile.TemporaryDirectory(prefix="bifurcation-bench-") as tmp:
        for _ in range(repeat):
            one = _child(_SERIAL_CHILD.format(points=points, law=law, tiles=tuple(tiles), batch=batch), tmp)
            two = _child(_SUBMIT_CHILD.format(points=points, law=law, tiles=tuple(tiles), batch=batch, workers=workers,
                                              store=str(Path(tmp) / "embedded.zarr")), tmp)
            # times: the best of each side; peak RSS: the largest (it hardly varies: the conservative one)
            serial = one if serial is None else {k: _best(k, v, one[k]) for k, v in serial.items()}
            run = two if run is None else {k: _best(k, v, two[k]) for k, v in run.items()}
    n = bench_workflow(points, law=law, tiles=tiles).n_points
    here = run["cluster"] == "this process"
    cores = 1 if here else min(workers, os.cpu_count() or 1)
    serial_rate = n / serial["wall_s"]
    rate = n / run["wall_s"]
    return {"points": n, "workers": workers, "where": run["cluster"], "tiles": run["tiles"],
            "complete": run["complete"], "serial_s": serial["wall_s"], "serial_cpu_s": serial["cpu_s"],
            "serial_peak_rss_mb": serial["peak_rss_mb"], "submit_s": run["wall_s"], "submit_cpu_s": run["cpu_s"],
            "speedup": serial["wall_s"] / run["wall_s"], "processes_computing": cores,
            "rate_per_core_ratio": rate / cores / serial_rate,
            "cpu_efficiency": serial["cpu_s"] / run["cpu_s"],
            "submit_peak_rss_mb": run["peak_rss_mb"], "peak_rss_ratio": run["peak_rss_mb"] / serial["peak_rss_mb"],
            # the submitting process's own CPU (the rest: helpers); with the other, what the speed-up on
            # idle cores is bounded by (CPU seconds the busiest process spends), and the load it ran in
            "submit_own_cpu_s": run["own_cpu_s"],
            "cpu_speedup_bound": serial["cpu_s"] / max(run["own_cpu_s"], run["cpu_s"] - run["own_cpu_s"]),
            "load_average": os.getloadavg()[0]}
