"""The chain study's worker processes end with the study (found at review: after a kill -9 of
`bifurcation study chain` its forked pool workers stayed alive, idle, ~200 MB each, for good)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from _proc import alive as _alive

SCRIPT = """
import sys, time
from bifurcation.models.chain.study import _pool
with _pool(2) as pool:
    list(pool.map(time.sleep, [0.2, 0.2]))           # both workers started
    print(*pool._processes, flush=True)
    time.sleep(120)
"""

#: A study stopped (Ctrl-C, SIGTERM) while runs are queued, with the CLI's handler for SIGTERM (which the forked
#: workers inherited): the SIGINT of `study chain` after 86 s printed "interrupted" and then hung for good.
STOPPED = """
import signal, time
from bifurcation.models.chain.study import _pool

def stop(signum, frame):
    raise SystemExit(128 + signum)

signal.signal(signal.SIGTERM, stop)
with _pool(2) as pool:
    futures = [pool.submit(time.sleep, 60) for _ in range(4)]
    time.sleep(1.0)
    print(*pool._processes, flush=True)
    raise KeyboardInterrupt
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_pool_workers_end_when_the_study_is_killed():
    parent = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, text=True)
    try:
        workers = [int(p) for p in parent.stdout.readline().split()]
        assert workers and all(_alive(p) for p in workers)
        parent.send_signal(signal.SIGKILL)
        parent.wait()
        deadline = time.monotonic() + 10   # the watch polls once a second
        while any(_alive(p) for p in workers) and time.monotonic() < deadline:
            time.sleep(0.2)
        left = [p for p in workers if _alive(p)]
        assert not left, f"workers {left} outlived the killed study"
    finally:
        parent.kill()
        for p in workers if "workers" in locals() else []:
            try:
                os.kill(p, signal.SIGKILL)
            except ProcessLookupError:
                pass


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_pool_workers_end_when_the_study_is_stopped():
    """Before: the 60 s runs were waited for (the subprocess's 120 s timeout failed the test)."""
    started = time.monotonic()
    done = subprocess.run([sys.executable, "-c", STOPPED], capture_output=True, text=True, timeout=120)
    elapsed = time.monotonic() - started
    workers = [int(p) for p in done.stdout.split()]
    assert len(workers) == 2 and "KeyboardInterrupt" in done.stderr, (done.stdout, done.stderr[-500:])
    assert elapsed < 30, f"{elapsed:.0f} s: the queued 60 s runs were waited for"   # 1.6 s measured
    deadline = time.monotonic() + 5
    while any(_alive(p) for p in workers) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not [p for p in workers if _alive(p)]
