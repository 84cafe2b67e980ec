"""Real processes for the tests (`dask scheduler`, `dask worker`, `bifurcation submit`), imported as ``_proc``.

Every process is started in its own session (``start_new_session``), so it and its children (a nanny's
worker, a submit's helper processes) form one process group that ``stop`` ends as a whole; ``running``
does that in a ``finally``, so a failed assertion leaves no process behind. pytest's default ``prepend``
import mode puts this directory on ``sys.path`` (as for ``_store_helpers``).
"""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path

__all__ = ["BIN", "alive", "bifurcation", "env", "free_port", "group_alive", "running", "start", "stop",
           "wait_until"]

#: The virtual environment's scripts: ``bifurcation``, ``dask``.
BIN = Path(sys.executable).parent


def bifurcation(*args) -> list[str]:
    """The command line of ``bifurcation ARGS`` from this environment."""
    return [str(BIN / "bifurcation"), *map(str, args)]


def env() -> dict:
    """This environment without ``DASK_*`` (a user's scheduler address or config must not leak in), and
    unbuffered Python output, so a log shows what a killed process printed."""
    out = {k: v for k, v in os.environ.items() if not k.startswith("DASK_")}
    out["PYTHONUNBUFFERED"] = "1"
    return out


def free_port() -> int:
    """A TCP port free on 127.0.0.1 now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(args, cwd: Path, log: str | None = None, **kwargs) -> subprocess.Popen:
    """``args`` in a new session (its own process group) in ``cwd``. With ``log``, stdout and stderr go to
    ``cwd/<log>.log``; otherwise ``kwargs`` say where (``stdout=subprocess.PIPE``, ``text=True``, ...)."""
    if log is not None:
        with open(Path(cwd) / f"{log}.log", "wb") as out:   # the child keeps its own descriptor
            return subprocess.Popen(args, stdout=out, stderr=subprocess.STDOUT, cwd=cwd, env=env(),
                                    start_new_session=True, **kwargs)
    return subprocess.Popen(args, cwd=cwd, env=env(), start_new_session=True, **kwargs)


def stop(proc: subprocess.Popen, first: int = signal.SIGTERM, grace: float = 10) -> None:
    """End ``proc``'s process group: ``first`` (SIGTERM: a clean stop), then SIGKILL if it has not ended
    within ``grace`` seconds, then SIGKILL to what is left of the group (a nanny's worker, a helper), and
    wait (as long again, at least 1 s) until none of them runs: signals are delivered asynchronously. Safe
    to call twice, and on a process that has ended."""
    for sig in (first, signal.SIGKILL):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(grace)
            break
        except subprocess.TimeoutExpired:
            continue
    try:   # children left in the group
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    try:
        proc.wait(grace)   # reaped: no zombie
    except subprocess.TimeoutExpired:
        pass
    deadline = time.monotonic() + max(grace, 1.0)   # a signal is delivered asynchronously: see them end
    while group_alive(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.01)
    for stream in (proc.stdout, proc.stderr):
        if stream is not None:
            stream.close()


@contextmanager
def running(args, cwd: Path, log: str | None = None, **kwargs):
    """``start`` as a context: the process group is ended (``stop``) on leaving, whatever happened."""
    proc = start(args, cwd, log, **kwargs)
    try:
        yield proc
    finally:
        stop(proc)


def wait_until(predicate, timeout: float, what: str, *, proc: subprocess.Popen | None = None,
               interval: float = 0.01, detail=None) -> None:
    """Poll ``predicate`` every ``interval`` s until it is true; fail naming ``what`` after ``timeout`` s,
    or as soon as ``proc`` (if given) has ended, with ``detail()`` (e.g. its log) in the message."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if proc is not None and proc.poll() is not None:
            raise AssertionError(f"the process ended (status {proc.returncode}) before {what}{_more(detail)}")
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}{_more(detail)}")
        time.sleep(interval)


def _more(detail) -> str:
    return f": {detail()}" if detail is not None else ""


def alive(pid: int) -> bool:
    """The process ``pid`` exists and has not ended (a zombie has ended; Linux: reads /proc)."""
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (FileNotFoundError, IndexError):
        return False


def group_alive(pgid: int) -> bool:
    """Some process of the group ``pgid`` has not ended. A zombie has ended (an orphan's waits for init
    to reap it, measured up to ~2 s here, and ``killpg(pgid, 0)`` still finds it); Linux reads /proc,
    elsewhere ``killpg`` answers."""
    if not os.path.isdir("/proc"):
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return False
        return True
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as fh:
                    state, _, pgrp = fh.read().rsplit(")", 1)[1].split()[:3]
            except (OSError, IndexError, ValueError):
                continue
            if int(pgrp) == pgid and state != "Z":
                return True
    return False
