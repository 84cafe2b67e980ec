"""One writer per store: a lock file inside the store, held by the submitting process (the coordinator).

``StoreLock(path).acquire(run)`` creates ``<store>/.bifurcation.lock`` with ``O_CREAT | O_EXCL`` (one
atomic create: of two processes that try at once, exactly one succeeds) and writes into it who holds it:
run id, host, pid, the process's start time and the lock's start time (UTC). It is removed when the
submit ends, also on an exception or Ctrl-C. A second ``submit``, ``--new-store`` or ``verify --repair``
on a store being written is refused in one line naming the holder.

Stale locks. A lock left by a process that died (``kill -9``) is recognised when it was taken on this
host and its pid is gone, or that pid now belongs to a process started at another time (pid reuse): it
is broken and taken over. A lock taken on another host is never broken automatically (its pid means
nothing here); the message says how to remove it once that run is known to be dead.

Filesystems. ``O_EXCL`` creation is atomic on local filesystems (ext4, xfs, btrfs, tmpfs, APFS), on
NFSv3 and later (the server performs the exclusive create), Lustre, GPFS and CephFS, so the lock holds
for workers and coordinators on several machines sharing the store there. On NFSv2 and on some
FUSE/object-store mounts (s3fs, gcsfuse) ``O_EXCL`` is not atomic: two coordinators that start within
the same instant may both believe they hold the lock. Even then tiles stay correct: every tile write
checks the store's ``run_id`` first (``zarr_store.write_tile``), so a worker of a replaced store never
writes into its successor.

Tile writers (workers) do not take this lock: the coordinator holds it for the whole run, and the
writers only write their own tile's chunks after checking the run id.
"""

from __future__ import annotations

import errno
import json
import os
import socket
import time
import uuid
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError

__all__ = ["LOCK_NAME", "LockHolder", "StoreLock", "detached_alive", "holder", "lock_path"]

LOCK_NAME = ".bifurcation.lock"
#: Seconds after which a lock file that holds no readable holder counts as stale (its writer fills it
#: within microseconds of creating it).
_UNREADABLE_GRACE = 60.0


def lock_path(store) -> Path:
    return Path(store) / LOCK_NAME


def _process_start(pid: int) -> float | None:
    """Start time of process ``pid`` (seconds since the epoch), None if there is no such process."""
    import psutil

    try:
        return psutil.Process(pid).create_time()
    except (psutil.NoSuchProcess, psutil.ZombieProcess):
        return None
    except psutil.AccessDenied:   # exists, owned by someone else: alive
        return -1.0


#: Seconds to wait for an answer of the scheduler named in a detached lock.
_ASK_TIMEOUT = 10.0


def _has_task(dask_scheduler=None, key: str = "") -> bool:
    return key in dask_scheduler.tasks


def detached_alive(scheduler: str, key: str) -> bool:
    """Whether the scheduler at ``scheduler`` still holds the detached run's finalize task ``key``.

    An unreachable scheduler counts as not alive: without it no tile of that run can be started, and a
    tile still being written by a worker of it writes the same numbers a resume would.
    """
    from distributed import Client

    try:
        with Client(scheduler, timeout=_ASK_TIMEOUT, set_as_default=False) as client:
            return bool(client.run_on_scheduler(_has_task, key=key))
    except (OSError, TimeoutError):
        return False


@dataclass(frozen=True)
class LockHolder:
    """What a lock file says about the process that holds it."""

    run: str
    host: str
    pid: int
    process_start: float
    since: str
    command: str = ""
    scheduler: str = ""   # a detached run (run.detach): the scheduler that runs it
    task: str = ""        # and the key of its finalize task there

    def describe(self) -> str:
        if self.scheduler:
            return f"detached run {self.run} (on scheduler {self.scheduler}, since {self.since})"
        return f"run {self.run} (pid {self.pid} on host {self.host}, since {self.since})"

    def alive(self) -> bool | None:
        """True / False on this host or for a detached run (its scheduler is asked); None when it was
        taken on another host (cannot be told)."""
        if self.scheduler:
            return detached_alive(self.scheduler, self.task)
        if self.host != socket.gethostname():
            return None
        if self.pid < 0:   # an unreadable lock file: its writer died within a second of creating it
            return time.time() - self.process_start < _UNREADABLE_GRACE
        start = _process_start(self.pid)
        if start is None:
            return False
        if start < 0 or self.process_start <= 0:
            return True
        return abs(start - self.process_start) < 1.0   # a reused pid started at another time


def _read(path: Path) -> LockHolder | None:
    """The holder written in the lock file at ``path``; None if there is no such file."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return None
    except UnicodeDecodeError:   # garbage: an unknown holder, as an empty file (a traceback before, walk 6)
        text = ""
    except OSError as exc:   # a directory, or unreadable: "Is a directory", exit 1 before (walk 6)
        raise InputError("--store", str(path.parent), f"has a lock file {path.name} that cannot be read "
                         f"({exc.strerror or type(exc).__name__})",
                         f"remove {path} if no submit is writing the store, and run this command again") from None
    try:
        data = json.loads(text)
        return LockHolder(run=str(data["run"]), host=str(data["host"]), pid=int(data["pid"]),
                          process_start=float(data["process_start"]), since=str(data["since"]),
                          command=str(data.get("command", "")), scheduler=str(data.get("scheduler", "")),
                          task=str(data.get("task", "")))
    except (ValueError, KeyError, TypeError):
        # a holder that died between the create and the write leaves an empty file: unknown holder
        # on this host, judged by the file's age in StoreLock.acquire
        try:
            written = path.stat().st_mtime
        except FileNotFoundError:
            return None
        return LockHolder(run="unknown", host=socket.gethostname(), pid=-1, process_start=written,
                          since="unknown")


def holder(store) -> LockHolder | None:
    """The live holder of the store's lock, or None if nobody holds it (a stale lock counts as free)."""
    found = _read(lock_path(store))
    if found is None or found.alive() is False:
        return None
    return found


def _busy(store, found: LockHolder, argument: str) -> InputError:
    where = lock_path(store)
    if found.scheduler:
        fix = (f"follow it with `bifurcation status --store {store}`; a submit of the same workflow joins "
               "it (waits for it, then resumes what is left)")
        return InputError(argument, str(store), f"is being written by {found.describe()}", fix)
    if found.alive() is None:
        fix = (f"wait for it to end; if that process is dead (it was started on another host), "
               f"remove {where} and retry")
    else:
        fix = "wait for it to end (or stop that process), then run this command again"
    return InputError(argument, str(store), f"is being written by {found.describe()}", fix)


class StoreLock:
    """The one-writer lock of the store at ``path`` (a context manager once acquired)."""

    def __init__(self, path, *, argument: str = "--store") -> None:
        self.path = Path(path)
        self.file = lock_path(path)
        self.argument = argument
        self.token = uuid.uuid4().hex
        self.held = False

    def acquire(self, run: str = "", command: str = "") -> "StoreLock":
        """Take the lock (creating the store's directory if needed); ``InputError`` if it is held."""
        from .layout import utc_now

        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(self.argument, str(self.path), f"cannot be created ({exc.strerror or exc})",
                             "choose a --store path in a writable directory") from None
        me = {"run": run or self.token, "host": socket.gethostname(), "pid": os.getpid(),
              "process_start": _process_start(os.getpid()) or 0.0, "since": utc_now(), "command": command,
              "token": self.token}
        for _ in range(3):
            try:
                fd = os.open(self.file, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                found = _read(self.file)
                if found is None:          # released in between: try again
                    continue
                if found.alive() is not False:
                    raise _busy(self.path, found, self.argument) from None
                self._break(found)
                continue
            except OSError as exc:
                raise InputError(self.argument, str(self.path),
                                 f"cannot be locked for writing ({exc.strerror or exc})",
                                 "choose a --store path in a writable directory") from None
            try:
                os.write(fd, json.dumps(me).encode())
                os.fsync(fd)
            finally:
                os.close(fd)
            self.held = True
            return self
        found = _read(self.file) or LockHolder("unknown", "unknown", -1, 0.0, "unknown")
        raise _busy(self.path, found, self.argument)

    def _break(self, stale: LockHolder) -> None:
        """Remove a stale lock, unless another process replaced it meanwhile."""
        aside = self.file.with_name(f"{LOCK_NAME}.stale-{self.token}")
        try:
            os.rename(self.file, aside)
        except FileNotFoundError:
            return
        moved = _read(aside)
        if moved is not None and moved != stale:
            # another process broke the same stale lock and took the lock in between: give it back
            try:
                os.link(aside, self.file)
            except FileExistsError:
                pass
        aside.unlink(missing_ok=True)

    def release(self) -> None:
        if not self.held:
            return
        self.held = False
        try:
            data = json.loads(self.file.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return
        if data.get("token") == self.token:   # never remove a lock that is not ours
            try:
                self.file.unlink()
            except FileNotFoundError:
                pass
            except OSError as exc:
                if exc.errno not in (errno.EROFS, errno.EACCES):
                    raise

    def __enter__(self) -> "StoreLock":
        if not self.held:
            self.acquire()
        return self

    def __exit__(self, *exc) -> None:
        self.release()
