"""How far a study is: ``bifurcation status --store S``, read from the store alone.

Nothing but the store is needed (no cluster, no submitting process): the ``done`` mask gives the
progress per label of the first axis, ``status`` the outcomes, the lock file who is writing, and the
modification times of the ``done`` chunks (each written last by its tile's writer) the rate and the ETA.
"""

from __future__ import annotations

import json
import time
from dataclasses import asdict, dataclass, field
from datetime import datetime
from pathlib import Path

import numpy as np

from ..errors import shown_path

__all__ = ["StudyStatus", "format_eta", "study_status"]

#: Outcomes that are results, not failures (any other status of a done point is counted as a failure).
_RESULTS = ("stick-slip", "creep", "complete", "steady-sliding", "limit-cycle", "unbounded-growth",
            "no-hopf-point", "periodic-orbit", "past-end")
#: The rate is measured over the tiles the current writer finished in the last this many seconds.
_RATE_WINDOW = 300.0


def format_rate(rate: float) -> str:
    """Points per second with the digits that say something: '0 points/s' was printed for 0.26 (a slow model)."""
    return f"{rate:.0f} points/s" if rate >= 10 or rate == 0 else f"{rate:.2g} points/s"


def format_eta(seconds: float) -> str:
    """``"42 s"``, ``"12 min"``, ``"3.2 h"``: an ETA to read at a glance."""
    if seconds != seconds or seconds == float("inf"):
        return "unknown"
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


@dataclass(frozen=True)
class StudyStatus:
    """Progress of the study in one store. Times are seconds since the epoch."""

    store: str
    study: str
    axis: str                     # the first dimension: progress is given per label of it
    points: int
    done: int
    per_label: dict               # label → {"points", "done", "statuses": {name: count}}
    statuses: dict                # status name → count, over the done points
    failed: int                   # done points whose status is not a result (no-stop, nonfinite, …)
    writer: dict | None           # the lock holder while a submit writes the store, else None
    last_write: float | None      # newest tile completion
    rate: float | None            # points/s over the recent tiles (None: too few to tell)
    eta: float | None             # seconds to finish at that rate, while a writer is active
    submits: list = field(default_factory=list)
    #: status reads only the done and status arrays: the other chunks' checksums are verify's job
    integrity: str = "not checked (only the done and status arrays are read): `bifurcation verify` reads every chunk"

    @property
    def complete(self) -> bool:
        return self.done == self.points

    def to_dict(self) -> dict:
        return asdict(self)

    def __str__(self) -> str:
        from .integrity import _written_by, repair_fix

        percent = 100.0 * self.done / self.points if self.points else 100.0
        width = max([len(self.axis)] + [len(str(k)) for k in self.per_label])
        lines = [f"study {self.study} ({shown_path(self.store)}): {self.done}/{self.points} points done ({percent:.1f}%), "
                 f"{self.failed} failed",
                 f"  {self.axis:{width}s}  {'done/points':>17s}  {'%':>6s}  outcomes"]
        for label, row in self.per_label.items():
            share = 100.0 * row["done"] / row["points"] if row["points"] else 100.0
            outcomes = ", ".join(f"{k} {v}" for k, v in row["statuses"].items()) or "-"
            count = f"{row['done']}/{row['points']}"
            lines.append(f"  {str(label):{width}s}  {count:>17s}  {share:6.1f}  {outcomes}")
        if self.writer is not None:
            rate = "rate not known yet" if self.rate is None else format_rate(self.rate)
            eta = "" if self.eta is None else f", ETA {format_eta(self.eta)}"
            lines.append(f"being written by {self.writer['describe']}: {rate}{eta}")
        elif self.complete:
            lines.append(f"complete: all {self.points} points computed and no submit is writing it; read it "
                         f"with `bifurcation query --store {shown_path(self.store)}` or `bifurcation report`")
        elif _written_by(self.store):   # written whole (rate-state continue): points missing are damage
            lines.append(f"{self.points - self.done} points not done in a store written whole: "
                         f"{repair_fix(self.store)}")
        else:
            lines.append(f"no submit is writing it: submit the same workflow again to compute the "
                         f"{self.points - self.done} remaining points")
        # a flipped bit in a result chunk is not seen here: say so rather than imply the data are sound
        lines.append(f"chunks not checked for damage (status reads only the done and status arrays): "
                     f"`bifurcation verify --store {shown_path(self.store)}` checks every one")
        return "\n".join(lines)


def _chunk_files(array_dir: Path, meta: dict) -> dict:
    """Chunk grid index → modification time, for the chunk files of one array that exist."""
    encoding = meta.get("chunk_key_encoding", {"name": "default"})
    separator = encoding.get("configuration", {}).get("separator", "/")
    prefix = "c" + separator if encoding.get("name", "default") == "default" else ""
    out = {}
    root = array_dir
    for file in root.rglob("*"):
        if not file.is_file() or file.name == "zarr.json":
            continue
        key = file.relative_to(root).as_posix().replace("/", separator)
        if not key.startswith(prefix):
            continue
        try:
            index = tuple(int(p) for p in key[len(prefix):].split(separator))
        except ValueError:
            continue
        out[index] = file.stat().st_mtime
    return out


def _since(text: str) -> float | None:
    try:
        return datetime.fromisoformat(text).timestamp()
    except (TypeError, ValueError):
        return None


def _read(path: Path, group, name: str):
    """The whole array ``name``; a chunk that does not decode (checksum, truncation) or a lost array is
    one line naming it and the repair command, never a traceback."""
    from ..errors import InputError
    from .integrity import repair_fix

    try:
        return group[name][...]
    except Exception as exc:  # noqa: BLE001 — whatever zarr raises for a damaged or missing array
        raise InputError("--store", str(path), f"has a damaged {name} array ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else 'unreadable'})",
                         f"see the damage with `bifurcation verify --store {shown_path(path)}`, then "
                         f"{repair_fix(path)}") from None


def study_status(path) -> StudyStatus:
    """The progress of the study in the store at ``path`` (``InputError`` if it is not a store)."""
    import zarr

    from .lock import holder
    from .zarr_store import _quiet, check_store

    path = Path(path)
    attrs = check_store(path, None)
    with _quiet():
        group = zarr.open_group(str(path), mode="r", use_consolidated=False)
        done = np.asarray(_read(path, group, "done"), dtype=bool)
        status = np.asarray(_read(path, group, "status"))
    meta = json.loads((path / "done" / "zarr.json").read_text(encoding="utf-8"))
    dims = meta.get("dimension_names") or [f"dim_{i}" for i in range(done.ndim)]
    # CF flags: meaning i belongs to flag_values[i] (codes need not be 0..n−1: unresolved is 7)
    flag_attrs = group["status"].attrs
    meanings = (flag_attrs.get("flag_meanings") or "").split()
    by_code = dict(zip((int(v) for v in flag_attrs.get("flag_values") or range(len(meanings))), meanings))
    name_of = (lambda code: by_code.get(code, f"code {code}"))

    def outcomes(mask, where=()) -> dict:
        codes, counts = np.unique(status[where][mask], return_counts=True)
        return {name_of(int(c)): int(n) for c, n in zip(codes, counts)}

    labels = np.asarray(group[dims[0]][...]) if dims[0] in group else np.arange(done.shape[0])
    per_label = {}
    for i, label in enumerate(labels):
        key = label.item() if hasattr(label, "item") else label
        per_label[str(key)] = {"points": int(done[i].size), "done": int(done[i].sum()),
                               "statuses": outcomes(done[i], i)}
    statuses = outcomes(done)
    failed = sum(n for k, n in statuses.items() if k not in _RESULTS)

    # completion times: one per done chunk (the tile's writer writes done last)
    chunks = tuple(meta["chunk_grid"]["configuration"]["chunk_shape"])
    finished = []
    for index, mtime in _chunk_files(path / "done", meta).items():
        block = tuple(slice(i * c, (i + 1) * c) for i, c in zip(index, chunks))
        n = int(done[block].sum())
        if n:
            finished.append((mtime, n))
    finished.sort()
    last = finished[-1][0] if finished else None
    found = holder(path)
    writer = None if found is None else {"describe": found.describe(), "run": found.run, "host": found.host,
                                         "pid": found.pid, "since": found.since}
    rate = eta = None
    if found is not None:   # points finished by this writer within the window, over the window's length
        now = time.time()
        since = max(_since(found.since) or now, now - _RATE_WINDOW)
        recent = sum(n for t, n in finished if t >= since)
        if recent and now > since:
            rate = recent / (now - since)
            eta = (done.size - int(done.sum())) / rate
    return StudyStatus(store=str(path), study=str(attrs.get("title", "?")), axis=dims[0], points=int(done.size),
                       done=int(done.sum()), per_label=per_label, statuses=statuses, failed=failed,
                       writer=writer, last_write=last, rate=rate, eta=eta,
                       submits=list(attrs.get("submits", [])))
