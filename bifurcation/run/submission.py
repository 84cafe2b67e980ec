"""Submit a workflow: its missing tiles run on a Dask cluster and stream into the store.

The submitting process is the coordinator: it checks the workflow against the store, creates the
store (metadata only), hands tiles to the cluster a window at a time and consolidates the metadata at
the end. On the embedded default it computes the tiles itself, and starts a local cluster to share them
only when the work left is worth one (a small study never starts one: issue 18 measured 3.8 s of fixed
CPU and 4x the memory per submit). Each tile is written into its own chunk by exactly one writer, data
first and ``done`` last.

Faults. A task that raises is retried (``retries``); a task whose worker dies (``kill -9``) is
rescheduled by the scheduler on another worker, and a later write of the same tile writes the same
numbers. If the submitting process dies, every tile whose ``done`` chunk was written stays done; the
next submit of the same workflow to the same store computes only the rest.
"""

from __future__ import annotations

import time
import uuid
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from ..errors import InputError, shown_path
from .tiles import Tile, compute_tile, iter_tiles
from ..workflow import Workflow, load_workflow
from ..store.status import format_rate
from .cluster import check_scheduler, check_workers, check_workers_timeout, connect, describe
from .progress import Progress

__all__ = ["WRITERS", "Summary", "submit"]

#: Who writes a finished tile: the worker that computed it (the store must be on a filesystem that
#: every worker sees at the same path), or the submitting process (no shared filesystem needed).
WRITERS = ("workers", "client")


@dataclass(frozen=True)
class Summary:
    """What a submit did. ``points_per_second`` counts computed points over the whole wall time."""

    study: str
    store: str
    points: int                 # points in the grid
    computed: int               # points computed by this submit
    skipped: int                # points already done before it
    failed: int                 # points of tiles that failed after all retries (resubmit to retry)
    tiles: int                  # tiles handed to the cluster
    wall_time: float            # seconds, the whole submit (cluster start-up included)
    compute_time: float         # seconds, from the first task to the last result
    statuses: dict = field(default_factory=dict)   # status name → computed points
    cluster: str = ""
    errors: tuple = ()
    repaired: int = 0           # damaged or half-written tiles found on resume, cleared and recomputed
    detached: bool = False      # handed to the scheduler (run.detach): the workers compute it after this

    @property
    def points_per_second(self) -> float:
        return self.computed / self.wall_time if self.wall_time > 0 else 0.0

    @property
    def complete(self) -> bool:
        return not self.detached and self.failed == 0 and self.computed + self.skipped == self.points

    def to_dict(self) -> dict:
        out = asdict(self)
        out["errors"] = list(self.errors)
        out["points_per_second"] = self.points_per_second
        return out

    def __str__(self) -> str:
        if self.detached:
            return (f"study {self.study} → {shown_path(self.store)}\n"
                    f"detached: {self.points - self.skipped} points in {self.tiles} tiles handed to the "
                    f"{self.cluster.removeprefix('detached on ')} scheduler ({self.skipped} already done); this "
                    f"process may exit. Follow it with `bifurcation status --store {shown_path(self.store)}`")
        statuses = ", ".join(f"{k} {v}" for k, v in self.statuses.items()) or "-"
        lines = [
            f"study {self.study} → {shown_path(self.store)}",
            f"points: {self.points} in the grid, {self.computed} computed, {self.skipped} skipped "
            f"(already done), {self.failed} failed",
            f"statuses of computed points: {statuses}",
            (f"wall time {self.wall_time:.2f} s ({self.compute_time:.2f} s computing), "
             f"{format_rate(self.points_per_second)}, {self.tiles} tiles on {self.cluster}")
            if self.tiles else "nothing to compute: every point of the grid is already done",
        ]
        if self.repaired:
            lines.append(f"damaged or half-written tiles found in the store and recomputed: {self.repaired}")
        lines += [f"error: {e}" for e in self.errors]
        if self.failed:
            lines.append("some tiles failed: submit the same workflow again to compute the rest")
        return "\n".join(lines)


#: status counts are kept for every int8 code: a model may declare codes beyond ``Status`` (rs-chain's
#: ``steady`` = 8), and a tile's bincount longer than the tally broke the submit
_CODES = 128


def _report(values: dict) -> list[int]:
    """Status counts of the computed points of a tile (small: what a worker sends back)."""
    return np.bincount(values["status"][values["done"]].astype(np.int64), minlength=_CODES).tolist()


def _submit_tile(client, tile: Tile, store: str, run_id: str, writer: str, key: str, retries: int):
    """A tile as a Dask task: computed and written by the worker, or (``writer="client"``) only computed."""
    if writer == "workers":
        return client.submit(run_tile, tile, store, run_id, key=key, retries=retries, pure=False)
    return client.submit(compute_tile, tile, key=key, retries=retries, pure=False)


def _tile_counts(future, tile: Tile, store: str, run_id: str, writer: str) -> list[int]:
    """The status counts of a finished tile task; with ``writer="client"`` its values are written here."""
    from ..store import write_tile

    if writer == "workers":
        return future.result()
    values = future.result()
    write_tile(store, tile, values, run_id)
    return _report(values)


def _tile_error(tile: Tile, exc: BaseException) -> str:
    return f"tile {tile.name} ({tile.law}): {type(exc).__name__}: {exc}".splitlines()[0]


def run_tile(tile: Tile, store: str, run_id: str) -> list[int]:
    """Worker task: compute a tile and write it into its chunk of the store."""
    from ..models import get_model
    from ..store import write_tile

    checkpoints = None
    if get_model(tile.model).checkpoint:   # long runs save their state into the store as they go
        from ..store.catalog import tile_checkpoints

        checkpoints = tile_checkpoints(store, run_id, tile)
    values = compute_tile(tile, checkpoints)
    write_tile(store, tile, values, run_id)
    return _report(values)


def submit(workflow, store=None, scheduler=None, workers=None, progress=None, new_store: bool = False, *,
           writer: str = "workers", retries: int = 3, command: str | None = None, only=None,
           workers_timeout: float | None = None, dashboard: bool = False, detach: bool = False) -> Summary:
    """Compute the missing points of ``workflow`` into ``store``; returns a ``Summary``.

    Parameters
    ----------
    workflow : Workflow, str or Path
        A ``Workflow`` or the path of its TOML file.
    store : str or Path, optional
        The Zarr store; default ``results/<study name>.zarr``. An existing store must hold the same
        workflow (same ``fingerprint``) unless ``new_store``, which replaces it.
    scheduler : str or distributed.Client, optional
        A scheduler address or scheduler file, or a ``Client`` (left open: several submits can share
        one cluster); default ``DASK_SCHEDULER_ADDRESS`` or else the embedded default: tiles run in
        this process, and once the work left, measured on the tiles so far, exceeds
        ``HANDOVER_CPU_SECONDS``, a local cluster of ``workers - 1`` processes shares the rest with it
        (``_run_here``). The store is the same bit for bit either way.
    workers : int, optional
        Embedded: the number of processes that compute, this one included (default: the number of
        cores; 1: everything runs in this process). With a scheduler: wait for that many workers, at
        most ``workers_timeout`` seconds (default ``cluster.WORKERS_TIMEOUT``), saying so on stderr.
    progress : None, bool or callable
        See ``bifurcation.run.progress.Progress`` (default: a bar on a terminal, else a plain line
        every 30 s and one at the end, on stderr).
    writer : {"workers", "client"}
        Who writes finished tiles (``WRITERS``).
    retries : int
        Retries of a task that raises.
    only : list of region tuples, optional
        Compute only the points of these (law, ν_f, ν) regions that are not done (``verify --repair``).
    dashboard : bool
        Serve Dask's dashboard from the embedded cluster (port 8787 or the next free one); its link
        is printed with the progress.
    detach : bool
        Hand the study to an existing scheduler and return at once (``bifurcation.run.detach``): the
        workers finish it and release the store; ``bifurcation status`` follows it. Needs a scheduler
        and ``writer="workers"``. A submit that finds a detached run on the store joins it (waits).

    Examples
    --------
    A script that starts the embedded cluster must guard its entry point (Dask starts worker
    processes that re-import the script)::

        from bifurcation import submit

        if __name__ == "__main__":
            print(submit("workflows/paper-fig3.toml", workers=2))

    One submit writes a store at a time: a second one (or ``--new-store``) on a store being written
    is refused naming the running one (``bifurcation.store.lock``).
    """
    started = time.perf_counter()
    if not isinstance(workflow, Workflow):
        workflow = load_workflow(workflow)
    target = check_scheduler(scheduler)
    workers = check_workers(workers, embedded=target is None)
    workers_timeout = check_workers_timeout(workers_timeout)
    if workers_timeout is not None and target is None:   # silently ignored before (issue 21 walk)
        raise InputError("--workers-timeout", workers_timeout, "applies to an existing scheduler's workers; the "
                         "embedded cluster starts its own", "drop --workers-timeout, or pass --scheduler ADDRESS")
    if dashboard and target is not None and target[0] != "client":   # was ignored after a 10 s connect
        raise InputError("--dashboard", True, "serves the embedded cluster's dashboard; an existing scheduler "
                         "serves its own", "drop --dashboard and open the scheduler's (http://HOST:8787 by default)")
    if isinstance(retries, bool) or not isinstance(retries, int) or retries < 0:
        raise InputError("retries", retries, "is not a number of retries", "give an integer >= 0 such as 3")
    if writer not in WRITERS:
        raise InputError("writer", writer, "is not a writer", f"use one of {', '.join(WRITERS)}")
    # each names the flag at fault with its value (was "--detach=''", issue 21 walk)
    if detach and target is None:
        raise InputError("--detach", True, "needs an existing scheduler, and no --scheduler was given",
                         "pass --scheduler ADDRESS (a `dask scheduler` that outlives this process), or drop --detach")
    if detach and writer != "workers":
        raise InputError("--write-from", writer, "cannot be used with --detach: a detached run's workers write "
                         "the store", "leave --write-from at workers, or drop --detach")
    path = Path(store) if store is not None else workflow.default_store
    from ..store import store_kind
    from ..store.layout import command_line
    from ..store.lock import StoreLock

    if store_kind(path) == "other":
        raise InputError("--store", str(path), "exists and is not a bifurcation store",
                         "choose another --store path (it is never overwritten)")
    command = command if command is not None else command_line()
    existed = path.exists()
    # the parents the lock's directory will create: removed with it when the first submit fails (a
    # refused --scheduler left --store's new parent directory behind, issue 21 walk)
    made = [p for p in [path.absolute(), *path.absolute().parents] if not p.exists()]
    if existed and not new_store:
        from .detach import wait_for_detached

        wait_for_detached(path, Progress(progress, 0))   # a live detached run: join it, then resume
    lock = StoreLock(path).acquire(command=command)   # one writer per store (store.lock)
    try:
        return _submit_locked(workflow, path, target, workers, progress, new_store, writer, retries, command,
                              started, only, workers_timeout, dashboard, lock if detach else None)
    finally:
        lock.release()   # a no-op once a detached run holds it
        if not existed:
            for directory in made:   # the store's directory first, then its new parents
                _remove_if_empty(directory)


def _remove_if_empty(path: Path) -> None:
    """Remove the directory a refused or failed first submit made for its lock, if nothing else is in it."""
    try:
        path.rmdir()
    except OSError:
        pass


def _submit_locked(workflow, path, target, workers, progress, new_store, writer, retries, command, started,
                   only, workers_timeout, dashboard, detach_lock=None) -> Summary:
    from ..store import check_store, create_store, record_submit, store_kind

    kind = store_kind(path)   # again, under the lock
    if kind == "other":
        raise InputError("--store", str(path), "exists and is not a bifurcation store",
                         "choose another --store path (it is never overwritten)")
    fresh = kind == "missing" or new_store
    attrs = None
    repaired = 0
    if not fresh:
        attrs = check_store(path, workflow)   # refuses another workflow: nothing is written
        if only is None:   # a resume checks every chunk first and recomputes damaged tiles (verify --repair)
            from .repair import clear_damage

            repaired = clear_damage(path, workflow)
        done = _read_done(path)
        if only is not None:   # verify --repair: only these regions are to compute
            keep = np.ones_like(done)
            for region in only:
                keep[region] = done[region]
            done = keep
    else:
        done = np.zeros(workflow.shape, dtype=bool)
    skipped = int(np.count_nonzero(done))
    todo = workflow.n_points - skipped
    statuses = np.zeros(_CODES, dtype=np.int64)
    computed = failed = n_tiles = 0
    errors: list[str] = []
    compute_time = 0.0
    cluster_name = "nothing to compute"
    progress = Progress(progress, todo)
    if todo and target is None and not dashboard:
        # Small studies do not pay for a cluster: tiles run in this process, and a local cluster shares
        # the rest only once the remaining work is measured to be worth one (_run_here).
        progress.note(f"{todo} points to compute ({skipped} already done), in this process")
        if fresh:
            attrs = create_store(path, workflow, command=command, overwrite=new_store)
            fresh = False
        t0 = time.perf_counter()
        progress.begin()
        computed, failed, n_tiles, cluster_name = _run_here(workflow, path, str(attrs["run_id"]), done, statuses,
                                                            errors, progress, retries, workers, writer)
        compute_time = time.perf_counter() - t0
        todo = 0
    if todo:   # fresh stores always have work; the cluster comes first so a bad one writes nothing
        progress.note(f"{todo} points to compute ({skipped} already done); connecting to "
                      f"{describe(target)}" + (f" of {workers} workers" if workers and target is None else ""))
        with connect(target, workers, workers_timeout, dashboard=dashboard) as client:
            # asked for, or the user's own scheduler (which serves one); a client handed in by the caller
            # (reproduce's embedded cluster, started without a dashboard) has none worth a line
            if dashboard or (target is not None and target[0] != "client"):
                progress.note(f"dashboard: {client.dashboard_link}")
            if fresh:
                attrs = create_store(path, workflow, command=command, overwrite=new_store)
            cluster_name = describe(target)
            run_id = str(attrs["run_id"])
            if detach_lock is not None:
                from .detach import run_detached

                handed = run_detached(client, workflow, path, run_id, done, detach_lock, command, skipped)
                return Summary(study=workflow.name, store=str(path), points=workflow.n_points, computed=0,
                               skipped=skipped, failed=0, tiles=handed["tiles"],
                               wall_time=time.perf_counter() - started, compute_time=0.0,
                               cluster=f"detached on {handed['scheduler']}", repaired=repaired, detached=True)
            t0 = time.perf_counter()
            progress.begin()
            computed, failed, n_tiles = _run(client, workflow, path, run_id, done, statuses, errors,
                                             progress, writer, retries)
            compute_time = time.perf_counter() - t0
    wall = time.perf_counter() - started
    summary = Summary(study=workflow.name, store=str(path), points=workflow.n_points, computed=computed,
                      skipped=skipped, failed=failed, tiles=n_tiles, wall_time=wall,
                      compute_time=compute_time,
                      statuses={workflow.spec.status_name(i): int(n) for i, n in enumerate(statuses) if n},
                      cluster=cluster_name, errors=tuple(errors[:5]), repaired=repaired)
    try:
        record_submit(path, {"command": command, "computed": computed, "skipped": skipped, "failed": failed,
                             "wall_time": round(wall, 3), "cluster": cluster_name})
    except OSError as exc:   # disk full at the end: the tiles written are kept; say so, do not lose the summary
        summary = replace(summary, errors=(*summary.errors, f"store history not updated: {exc.strerror or exc}"))
    return summary


def _read_done(path: Path) -> np.ndarray:
    """The done mask; a mask that cannot be read is damage: one line and the repair command."""
    from ..store import read_done
    from ..store.integrity import repair_command

    try:
        return read_done(path)
    except Exception as exc:  # noqa: BLE001 — a missing or corrupt done array, whatever zarr raises
        raise InputError("--store", str(path), f"has a damaged done mask ({type(exc).__name__})",
                         f"run `{repair_command(path)}`") from None


#: Measured CPU seconds of remaining work above which the embedded default starts helper processes to
#: share the rest. A helper costs ~2 s of CPU to start (a fresh Python importing numpy, heyoka, zarr and
#: compiling the law), so on 2 cores it saves time only when the work left is well above that.
HANDOVER_CPU_SECONDS = 10.0


def _pool_tile(tile: Tile, store: str, run_id: str, writer: str):
    """A helper process's task: ``run_tile`` (it writes the tile), or with ``writer="client"`` only
    ``compute_tile`` (the submitting process writes). Module-level: pickled by name."""
    if writer == "workers":
        return run_tile(tile, store, run_id)
    return compute_tile(tile)


def _helper_start(parent: int) -> None:
    """A helper process's start: Ctrl-C, SIGTERM and SIGHUP are for the submitting process (it stops the
    pool: queued tiles cancelled, running ones finished and written), and a helper whose submitting
    process died (``kill -9``) exits instead of waiting on the pool's pipe for ever. (A batch job's
    SIGTERM reaches every process of the job: a helper that died of it mid-tile left data without its
    done mask, which ``verify`` reports as damage.)"""
    import os
    import signal
    import threading

    for stop in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(stop, signal.SIG_IGN)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)   # a tile being written is left without its done mask: the next submit recomputes it

    threading.Thread(target=watch, daemon=True, name="bifurcation-helper-watch").start()


class _Helpers:
    """Helper processes of the embedded default: a pool of ``n_workers`` fresh Python processes
    (``spawn``: no state or threads of this process are inherited) that take tiles while this process
    goes on computing its own.

    A plain process pool, not a Dask cluster: no scheduler and client threads in this process and no
    event loop, nanny or heartbeats beside the computation in the helpers, and tiles go over a pipe.
    Measured at 10^6 single-block points, 2 processes, CPU time of all of them: 42.1 s with a Dask
    LocalCluster as helper, 33.5-34.4 s with this pool, 31.1-31.6 s for one process without a store. A helper that dies (``kill -9``) breaks the pool: its tiles and those queued come back
    here and are computed in this process (``lost``), and no more go to the pool.
    """

    def __init__(self, n_workers: int) -> None:
        import multiprocessing
        import os
        from concurrent.futures import ProcessPoolExecutor

        self.n = n_workers
        self.error = None
        self.broken = False
        try:
            self.pool = ProcessPoolExecutor(max_workers=n_workers, mp_context=multiprocessing.get_context("spawn"),
                                            initializer=_helper_start, initargs=(os.getpid(),))
        except (OSError, ValueError) as exc:  # no processes here (a sandbox, a limit): this process computes
            self.pool, self.error = None, exc

    def ready(self):
        return self.pool if self.pool is not None and not self.broken else None

    def submit(self, tile: Tile, store: str, run_id: str, writer: str):
        """The tile's future, or None if the pool cannot take it (its processes did not start, or one
        died): then this process computes it, and every later tile."""
        try:
            return self.pool.submit(_pool_tile, tile, store, run_id, writer)
        except Exception as exc:  # noqa: BLE001 — BrokenProcessPool, or no process could be started
            self.broken = True
            if self.error is None and not isinstance(exc, RuntimeError):   # (BrokenProcessPool: said below)
                self.error = exc
            return None

    def close(self, cancel: bool = False) -> None:
        if self.pool is not None:
            self.pool.shutdown(wait=True, cancel_futures=cancel)


def _run_here(workflow, path: Path, run_id: str, done, statuses, errors, progress, retries, workers,
              writer: str = "workers"):
    """The embedded default: compute tiles in this process; once the work left, measured on the tiles
    so far (the fastest tile per point: the first one compiles), exceeds ``HANDOVER_CPU_SECONDS`` and
    more than one process is allowed, start ``workers - 1`` helper processes (``_Helpers``) and share
    the rest with them (this process keeps computing: their start is overlapped and no core waits on a
    coordinator). Returns (computed, failed, tiles, where).

    The store is the same bit for bit wherever a tile runs: ``run_tile`` is the same pure function the
    helpers run, data first and ``done`` last. A tile that raises is retried ``retries`` times here (a
    helper's failure comes back and is retried here), then reported. Where a tile runs depends on
    timing; what is stored does not.
    """
    import os
    from concurrent.futures.process import BrokenProcessPool

    store = str(path.resolve())
    processes = workers or os.cpu_count() or 1
    remaining = workflow.n_points - int(np.count_nonzero(done))
    computed = failed = n_tiles = here = 0
    per_point = float("inf")
    helpers = None
    pending: list = []   # (future, tile) in submission order
    lost: list = []      # tiles a helper did not finish: computed here
    shared = 0           # tiles the helpers finished

    def record(tile, counts=None, exc=None):
        nonlocal computed, failed
        if exc is not None:
            failed += tile.n_todo
            errors.append(_tile_error(tile, exc))
        else:
            statuses[:] += np.asarray(counts, dtype=np.int64)
            computed += tile.n_todo
        progress.update(tile.n_todo)

    def harvest(block: bool) -> None:
        nonlocal shared
        if block and pending:   # the oldest task (they finish about in order)
            pending[0][0].exception()
        for item in [item for item in pending if item[0].done()]:
            pending.remove(item)
            future, tile = item
            try:
                result = future.result()
                counts = result if writer == "workers" else _write_here(store, tile, result, run_id)
            except BrokenProcessPool:   # a helper died: its tiles (and the queued ones) are done here
                helpers.broken = True
                lost.append(tile)
            except Exception:  # noqa: BLE001 — a tile that raised in a helper: retried here
                lost.append(tile)
            else:
                shared += 1
                record(tile, counts)

    def compute_here(tile) -> None:
        for attempt in range(retries + 1):
            try:
                counts = run_tile(tile, store, run_id)
            except Exception as exc:  # noqa: BLE001 — retried, then reported
                if attempt == retries:
                    record(tile, exc=exc)
            else:
                record(tile, counts)
                break

    tiles = iter_tiles(workflow, done)
    try:
        while True:
            pool = helpers.ready() if helpers is not None else None
            if pool is not None:
                harvest(block=False)
                # one task running and one queued per helper: a short tail when the tiles run out
                while len(pending) < 2 * helpers.n and helpers.ready() is not None:
                    tile = next(tiles, None)
                    if tile is None:
                        break
                    n_tiles += 1
                    future = helpers.submit(tile, store, run_id, writer)
                    if future is None:
                        lost.append(tile)
                        break
                    pending.append((future, tile))
            if lost:
                compute_here(lost.pop(0))
                continue
            tile = next(tiles, None)
            if tile is None:
                if not pending:
                    break
                harvest(block=True)
                continue
            n_tiles += 1
            here += 1
            cpu = time.process_time()
            compute_here(tile)
            per_point = min(per_point, (time.process_time() - cpu) / max(tile.n_todo, 1))
            remaining -= tile.n_todo
            if (helpers is None and processes > 1 and here >= 2
                    and per_point * remaining > HANDOVER_CPU_SECONDS):
                progress.note(f"about {per_point * remaining:.0f} CPU s left: starting {processes - 1} helper "
                              f"process(es) beside this one")
                helpers = _Helpers(processes - 1)
    except BaseException:
        if helpers is not None:
            helpers.close(cancel=True)
        raise
    finally:
        progress.close()
        if helpers is not None:
            helpers.close()
            if helpers.error is not None:
                errors.append(f"the helper processes did not start ({type(helpers.error).__name__}: "
                              f"{helpers.error}); this process computed their share")
    where = "this process"
    if helpers is not None and shared:
        n = processes - 1
        where = f"this process and an embedded local cluster of {n} worker process{'es' if n > 1 else ''}"
    return computed, failed, n_tiles, where


def _write_here(store: str, tile: Tile, values: dict, run_id: str) -> list[int]:
    """``writer="client"``: a helper's computed tile written by this process."""
    from ..store import write_tile

    write_tile(store, tile, values, run_id)
    return _report(values)


def _window(client) -> int:
    # Enough tasks queued that no worker waits for the coordinator, few enough that memory stays
    # bounded however big the grid (tiles are generated lazily).
    return max(8, 3 * sum(client.nthreads().values()))


def _run(client, workflow, path: Path, run_id: str, done, statuses, errors, progress, writer, retries):
    from distributed import as_completed

    store = str(path.resolve())
    token = uuid.uuid4().hex[:8]
    tiles = iter_tiles(workflow, done)
    pending: dict = {}
    stream = as_completed(loop=client.loop)
    computed = failed = n_tiles = 0
    window, checked = _window(client), time.monotonic()

    def top_up():
        nonlocal n_tiles
        while len(pending) < window:
            tile = next(tiles, None)
            if tile is None:
                return
            future = _submit_tile(client, tile, store, run_id, writer, f"bifurcation-tile-{tile.name}-{token}",
                                  retries)
            pending[future.key] = (future, tile)
            stream.add(future)
            n_tiles += 1

    try:
        top_up()
        for future in stream:
            _, tile = pending.pop(future.key)
            try:
                counts = _tile_counts(future, tile, store, run_id, writer)
            except Exception as exc:  # noqa: BLE001 — a failed tile is reported, the rest goes on
                failed += tile.n_todo
                errors.append(_tile_error(tile, exc))
            else:
                statuses += np.asarray(counts, dtype=np.int64)
                computed += tile.n_todo
            finally:
                future.release()
            progress.update(tile.n_todo)
            if time.monotonic() - checked > 2:   # clusters grow (adaptive, jobqueue): widen the window
                window, checked = _window(client), time.monotonic()
            top_up()
    finally:
        progress.close()
        if pending:   # interrupted: do not leave work behind on a shared scheduler
            client.cancel([future for future, _ in pending.values()])
    return computed, failed, n_tiles
