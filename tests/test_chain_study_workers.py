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
pool = _pool(2)
list(pool.map(time.sleep, [0.2, 0.2]))           # both workers started
print(*pool._processes, flush=True)
time.sleep(120)
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
