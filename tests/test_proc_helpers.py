"""tests/_proc.py ends what it starts: a failed assertion inside ``running`` leaves no process of the
group behind, children included (a `dask worker`'s nanny has one, a submit its helpers)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from _proc import alive, group_alive, running, stop, wait_until

# a parent that starts a child in its own group and then waits: the child prints its pid first
FAMILY = [sys.executable, "-c", "import subprocess, sys, time\n"
          "child = subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(60)'])\n"
          "print(child.pid, flush=True); time.sleep(60)"]


def test_a_failure_inside_running_leaves_no_process(tmp_path):
    seen = {}
    with pytest.raises(AssertionError, match="the test failed here"):
        with running(FAMILY, tmp_path, stdout=subprocess.PIPE, text=True) as proc:
            seen["parent"], seen["child"] = proc.pid, int(proc.stdout.readline())
            assert alive(seen["child"]) and group_alive(proc.pid)
            raise AssertionError("the test failed here")
    assert not alive(seen["parent"]) and not alive(seen["child"])
    assert not group_alive(seen["parent"])


def test_a_process_that_ignores_sigterm_is_killed(tmp_path):
    stubborn = [sys.executable, "-c", "import signal, time; signal.signal(signal.SIGTERM, signal.SIG_IGN); "
                "print('ready', flush=True); time.sleep(60)"]
    with running(stubborn, tmp_path, stdout=subprocess.PIPE, text=True) as proc:
        assert proc.stdout.readline().strip() == "ready"
        stop(proc, grace=0.5)   # SIGTERM ignored: SIGKILL after the grace
        assert proc.returncode == -9


def test_wait_until_fails_when_the_process_ends_first(tmp_path):
    with running([sys.executable, "-c", "print('bye')"], tmp_path, log="short") as proc:
        with pytest.raises(AssertionError, match=r"the process ended \(status 0\) before a file: bye"):
            wait_until(lambda: False, 30, "a file", proc=proc, detail=lambda: (tmp_path / "short.log").read_text().strip())
    with pytest.raises(AssertionError, match="timed out after 0.05 s waiting for nothing"):
        wait_until(lambda: False, 0.05, "nothing")
