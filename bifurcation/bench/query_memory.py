"""Peak memory and time of an unfiltered ``bifurcation query`` of a 10^6-point store, per format.

    python -m bifurcation.bench.query_memory [--points 1000000] [--formats table,csv,json]

The store (1 law × 15625 ν_f × 64 ν, tiles 64 × 64: 245 tiles) is filled with synthetic values
(random floats, status stick-slip, done) through ``write_tile``: what is measured is reading and
printing, whatever the numbers. Each query runs as a subprocess with stdout to /dev/null; its peak
RSS is ``ru_maxrss`` of that child alone (``os.wait4``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np


def build(path: Path, points: int):
    from bifurcation.store import create_store, write_tile
    from bifurcation.store.layout import VARIABLES
    from bifurcation.run.tiles import iter_tiles
    from bifurcation.workflow import Workflow
    from bifurcation.workflow._axes import linear_points, log_points

    n_nu = 64
    w = Workflow(name="query-memory", laws=("carlson-langer",), nu=log_points(1e-3, 1e-15, n_nu),
                 nu_f=linear_points(1e-3, 0.999, points // n_nu), tiles=(64, 64))
    run_id = create_store(path, w)["run_id"]
    rng = np.random.default_rng(0)
    for tile in iter_tiles(w):
        values = {name: rng.random(tile.shape).astype(dtype) if dtype.kind == "f" else np.ones(tile.shape, dtype)
                  for name, dtype in VARIABLES.items()}
        values["steps"] = rng.integers(100, 10_000, tile.shape)
        write_tile(path, tile, values, run_id)
    return w


_LAUNCHER = """
import os, subprocess, sys, tempfile, time
t0 = time.perf_counter()
with tempfile.TemporaryFile() as sink:
    child = subprocess.Popen(sys.argv[1:], stdout=sink)
    _, status, usage = os.wait4(child.pid, 0)
    size = sink.seek(0, os.SEEK_END)
print(os.waitstatus_to_exitcode(status), time.perf_counter() - t0, usage.ru_utime + usage.ru_stime,
      usage.ru_maxrss, size)
"""


def measure(path: Path, fmt: str, python: str | None = None) -> dict:
    """One query in a child process: its own peak RSS, wall and CPU time, output size.

    The query is started by a small launcher process, not by this one: Linux counts in a child's
    ``ru_maxrss`` the memory of the parent it was forked from, and this process holds the store builder.
    """
    env = dict(os.environ)
    if python is not None:   # another checkout (e.g. the code before issue 8) for a side-by-side figure
        env["PYTHONPATH"] = python
    out = subprocess.run([sys.executable, "-c", _LAUNCHER, sys.executable, "-m", "bifurcation", "query", "--store",
                          str(path), "--format", fmt], capture_output=True, text=True, env=env, check=True)
    code, wall, cpu, rss, size = out.stdout.split()
    return {"format": fmt, "code": python or "this checkout", "exit": int(code), "wall_s": round(float(wall), 1),
            "cpu_s": round(float(cpu), 1), "peak_rss_mb": round(int(rss) / 1024, 1),
            "output_mb": round(int(size) / 2**20, 1)}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--formats", default="table,csv,json")
    parser.add_argument("--baseline", default=None, help="PYTHONPATH of another checkout to run too")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bifurcation-query-") as tmp:
        path = Path(tmp) / "q.zarr"
        w = build(path, args.points)
        rows = [measure(path, fmt) for fmt in args.formats.split(",")]
        if args.baseline:
            rows += [measure(path, fmt, args.baseline) for fmt in args.formats.split(",")]
    print(json.dumps({"points": w.n_points, "runs": rows}, indent=2))


if __name__ == "__main__":
    main()
