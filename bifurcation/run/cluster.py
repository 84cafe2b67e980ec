"""Where the tiles run: an embedded local cluster, or an existing Dask scheduler.

* no ``scheduler`` and no ``DASK_SCHEDULER_ADDRESS`` (dask config ``scheduler-address``): a
  ``LocalCluster`` of processes in this machine, ``workers`` of them (default: the number of cores),
  one thread each (the engine is single-threaded and holds the GIL);
* ``scheduler`` an address (``tcp://host:8786``, ``host:8786``) or the path of a scheduler file written
  by ``dask scheduler --scheduler-file`` or dask-jobqueue: ``Client`` to that scheduler; with ``workers``,
  wait until that many workers are connected;
* ``scheduler`` a ``distributed.Client``: used as it is and left open (several submits, one cluster).
"""

from __future__ import annotations

import logging
import os
from contextlib import contextmanager
from pathlib import Path

from ..errors import InputError

__all__ = ["WORKERS_TIMEOUT", "check_scheduler", "check_workers", "check_workers_timeout", "connect", "describe",
           "max_embedded_workers", "wait_for_workers"]

_CONNECT_TIMEOUT = "10s"
#: Seconds ``--workers N`` waits for N workers to connect to an existing scheduler before giving up.
WORKERS_TIMEOUT = 120.0


def check_scheduler(scheduler) -> tuple[str, object, str] | None:
    """``(kind, where, source)`` with kind "address", "file" or "client" (``where`` is then the
    ``distributed.Client`` itself), or None (embedded).

    Checked before anything is written; ``source`` names where it came from, for error messages.
    """
    if hasattr(scheduler, "submit") and hasattr(scheduler, "scheduler_info"):   # a distributed.Client
        return ("client", scheduler, "scheduler")
    if scheduler is None:
        import dask

        address = dask.config.get("scheduler-address", None)
        if not address:
            _check_temporary_directory()
            return None
        text = str(address).strip()   # checked as --scheduler is ('garbage' was a traceback after 20 s)
        host, _, port = text.rpartition(":")
        if "://" not in text and not (host and port.isdigit()):
            raise InputError("DASK_SCHEDULER_ADDRESS", text, "is not a scheduler address",
                             "set it to tcp://HOST:PORT, or unset it for the embedded cluster")
        _check_port(text, "DASK_SCHEDULER_ADDRESS")
        return ("address", str(address), "DASK_SCHEDULER_ADDRESS")
    text = str(scheduler).strip()
    if "://" in text:
        _check_port(text)
        return ("address", text, "--scheduler")
    path = Path(text)
    if path.is_file():
        _check_scheduler_file(path)
        return ("file", str(path), "--scheduler")
    host, _, port = text.rpartition(":")
    if host and port.isdigit():
        _check_port(text)
        return ("address", f"tcp://{text}", "--scheduler")
    raise InputError("--scheduler", text, "is neither a scheduler address nor an existing scheduler file",
                     "give tcp://HOST:PORT or the path written by `dask scheduler --scheduler-file`")


def _check_temporary_directory() -> None:
    """Dask's ``temporary-directory`` (DASK_TEMPORARY_DIRECTORY), where an embedded cluster's workers keep
    their files, is a directory this process can write: one in /proc or missing was a 77-line traceback
    from LocalCluster once the store was made (issue 21 walk 3)."""
    import dask

    where = dask.config.get("temporary-directory", None)
    if not where:
        return
    path = Path(str(where)).expanduser().absolute()
    while not path.exists() and path != path.parent:   # distributed creates it (os.makedirs) if it can
        path = path.parent
    try:   # os.access says yes to root in /proc: make (and remove) an empty directory there instead
        import tempfile

        os.rmdir(tempfile.mkdtemp(prefix=".bifurcation-probe-", dir=path))
    except OSError:
        raise InputError("DASK_TEMPORARY_DIRECTORY", str(where), "is not a writable directory (Dask's "
                         "temporary-directory setting)", "create it, set it to one you can write, or unset it") from None


def _check_port(address: str, source: str = "--scheduler") -> None:
    """A TCP address has a host and a port in 1-65535 (tcp://host:99999 waited 10 s to fail connecting;
    tcp://host without a port was a traceback from distributed after 20 s; issue 21 walk)."""
    scheme, sep, rest = address.partition("://")
    rest = rest if sep else address   # (a trailing / is a traceback in distributed: refused here)
    host, _, port = rest.rpartition(":")
    fix = "give tcp://HOST:PORT with the scheduler's port (8786 by default)"
    if scheme.lower() in ("tcp", "tls", "ws", "wss") or not sep:
        if not host or not port.isdigit():
            raise InputError(source, address, "has no HOST:PORT", fix)
        if not 1 <= int(port) <= 65535:
            raise InputError(source, address, f"has port {port}, outside 1-65535", fix)


def _check_scheduler_file(path: Path) -> None:
    """A scheduler file is the JSON that ``dask scheduler --scheduler-file`` writes, with the scheduler's
    ``address``; any other file is refused here (distributed would fail an assertion, then time out)."""
    import json

    fix = "give the file written by `dask scheduler --scheduler-file PATH`, or tcp://HOST:PORT"
    try:
        with open(path, "rb") as fh:
            data = json.loads(fh.read(1 << 20))
    except OSError as exc:
        raise InputError("--scheduler", str(path), f"cannot be read ({exc.strerror or exc})", fix) from None
    except ValueError:   # not JSON, not UTF-8, or cut at 1 MB: not a scheduler file
        data = None
    if not isinstance(data, dict) or not isinstance(data.get("address"), str) or "://" not in data["address"]:
        raise InputError("--scheduler", str(path), "is a file but not a scheduler file (JSON with the "
                         "scheduler's address)", fix)
    try:   # a file naming port 0 or 99999 waited 10 s to fail connecting, as such an address did
        _check_port(data["address"])
    except InputError as exc:
        raise InputError("--scheduler", str(path), f"names the address {data['address']!r}, which {exc.problem}",
                         "give the file the running `dask scheduler --scheduler-file PATH` wrote, or tcp://HOST:PORT") from None


#: The most worker processes of an embedded cluster: each holds a core and ~200 MB, so more than a few per
#: core only costs memory (10^5 asked for tried to start them all). More workers: start a `dask scheduler`
#: and `dask worker`s (on other machines too) and pass --scheduler.
def max_embedded_workers() -> int:
    return 4 * (os.cpu_count() or 1)


def check_workers(workers, *, embedded: bool = False) -> int | None:
    """``workers`` if it is None or a positive integer (at most ``max_embedded_workers()`` for an
    ``embedded`` cluster); ``InputError`` otherwise."""
    if workers is None:
        return None
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError("--workers", workers, "is not a positive number of workers", "give a whole number such as --workers 2")
    if embedded and workers > max_embedded_workers():
        raise InputError("--workers", workers, f"is more than {max_embedded_workers()} worker processes, 4 per core "
                         f"of this machine ({os.cpu_count()} cores) for the embedded cluster",
                         "give fewer, or start a `dask scheduler` and `dask worker`s and pass --scheduler ADDRESS")
    return workers


def check_workers_timeout(timeout) -> float | None:
    """Seconds to wait for workers: None (the default) or a finite number in (0, 86400]."""
    import math

    if timeout is None:
        return None
    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or not math.isfinite(timeout) \
            or not 0 < timeout <= 86400:
        raise InputError("--workers-timeout", timeout, "is not a time in (0, 86400] seconds",
                         "give seconds such as 120")
    return float(timeout)


def describe(target) -> str:
    if target is None:
        return "embedded local cluster"
    if target[0] == "client":
        return f"client of {target[1].scheduler.address}"
    return f"{target[0]} {target[1]}"


def wait_for_workers(client, workers: int, where: str, timeout: float | None = None, stream=None) -> None:
    """Wait until ``workers`` workers are connected, saying so on stderr; ``InputError`` after ``timeout``."""
    import sys

    timeout = WORKERS_TIMEOUT if timeout is None else timeout
    connected = len(client.nthreads())
    if connected >= workers:
        return
    stream = stream or sys.stderr
    stream.write(f"bifurcation: waiting for {workers} workers at {where} ({connected} connected), "
                 f"up to {timeout:g} s\n")
    stream.flush()
    try:
        client.wait_for_workers(workers, timeout=timeout)
    except (TimeoutError, OSError):
        connected = len(client.nthreads())
        raise InputError("--workers", workers, f"only {connected} workers connected to {where} within "
                         f"{timeout:g} s", f"start more `dask worker {where}` processes, or pass --workers "
                         f"{max(connected, 1)} (or --workers-timeout longer)") from None


def _close_half_built(exc: BaseException) -> None:
    """Close the ``Client`` whose constructor raised ``exc`` (found in its traceback), with a short timeout:
    left to its ``__del__``, its close waits 20 s and prints an ignored TimeoutError."""
    import contextlib

    from distributed import Client

    tb = exc.__traceback__
    while tb is not None:
        half = tb.tb_frame.f_locals.get("self")
        if isinstance(half, Client):
            with contextlib.suppress(Exception):
                half.close(timeout=2)
            return
        tb = tb.tb_next


@contextmanager
def connect(target, workers: int | None = None, timeout: float | None = None, *, dashboard: bool = False):
    """A ``distributed.Client`` for ``target`` (from ``check_scheduler``); closes what it started.

    ``dashboard``: the embedded cluster serves Dask's dashboard (bokeh) on port 8787, or the next free
    one; an existing scheduler serves its own (``client.dashboard_link``). ``timeout``: seconds to wait
    for ``workers`` workers on an existing scheduler (``wait_for_workers``).
    """
    from distributed import Client, LocalCluster

    if target is None:
        n = workers or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=":8787" if dashboard else None,
                               # without a dashboard the scheduler still serves its HTTP routes (health,
                               # metrics), by default on 8787: on a free loopback port instead, so a busy
                               # 8787 is no "Port 8787 is already in use" warning nobody asked about
                               scheduler_kwargs=None if dashboard else {"dashboard_address": "127.0.0.1:0"},
                               # a failed task (disk full, a bad tile) is reported once in the summary;
                               # the workers' own "Compute Failed" tracebacks would reach the user's stderr
                               silence_logs=logging.CRITICAL)
        try:
            with Client(cluster, set_as_default=False) as client:
                yield client
        finally:
            cluster.close()
        return
    kind, where, source = target
    if kind == "client":
        if workers:
            wait_for_workers(where, workers, where.scheduler.address, timeout)
        yield where
        return
    try:
        if kind == "file":
            client = Client(scheduler_file=where, timeout=_CONNECT_TIMEOUT, set_as_default=False)
        else:
            client = Client(where, timeout=_CONNECT_TIMEOUT, set_as_default=False)
    except (OSError, TimeoutError) as exc:
        raise InputError(source, where, f"cannot connect ({type(exc).__name__}: {exc})",
                         "start `dask scheduler` there or check the address / scheduler file") from None
    except Exception as exc:   # noqa: BLE001 — something answered, not a dask scheduler (an HTTP server such
        # as the dashboard's port 8787: distributed read its reply as a 3 EiB frame, a MemoryError traceback,
        # then waited 20 s in the half-built Client's __del__): closed here, quickly, and said in one line
        _close_half_built(exc)
        raise InputError(source, where, f"answered, but not as a dask scheduler ({type(exc).__name__})",
                         "give the scheduler's own address (tcp://HOST:8786 by default; 8787 is its dashboard)"
                         ) from None
    try:
        if workers:
            wait_for_workers(client, workers, where, timeout)
        yield client
    finally:
        client.close()
