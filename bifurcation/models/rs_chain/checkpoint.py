"""Snapshot and restore of a rate-and-state chain run between two Taylor steps, for checkpoints.

A run is one ``propagate_until`` of a cached heyoka integrator whose events are all non-terminal (no
cooldowns): the step taken from a state depends only on the state vector, the time and the parameters,
so a run that sets the same state, the same double-length time (heyoka's ``dtime`` pair, not the rounded
``time``) and the same parameters and goes on takes the same steps and finds the same roots, bit for bit.
A snapshot is taken at the end of a step callback (after the step's crossings are assembled and P is
reset), and it holds, besides the integrator's state and time, the event bookkeeping of ``simulate._Events``
(which blocks are above v_th, the open event, the end of the last one), the two step counters, the whole
rows of the events past the last full catalog chunk, and of the per-event values the store's catalog does
not keep (stress drop, balance) only what the store's outputs need of the events before: the largest
balance (``balance_max``). So a checkpoint's size no longer grows with the events done (it held 16 bytes
per event so far: 480 MB at the bound N × events ≤ 3·10^7 with N = 1, rewritten at every chunk); a resumed
run's result gives NaN stress drop and balance for the restored events and carries their largest balance
(``RSChainResult.restored_balance_max``). tests/test_rs_chain_checkpoint.py checks a resumed run against a
straight one bit for bit.

``arrays()`` gives numpy arrays whose bytes ``Checkpoints`` stores (CRC-checked);
``Snapshot.from_saved`` rebuilds one from those bytes and the catalog read back from the store.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ROW", "Snapshot"]

#: The columns of one event row of ``simulate._Events.rows``, in order.
ROW = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity", "stress_drop", "balance")
_INTS = ("hypocentre", "n_blocks")
_OPEN = ("t_start", "hypocentre", "vmax", "p0", "s0")   # the open event's numbers (its blocks apart)


@dataclass(frozen=True)
class Snapshot:
    """A run between two steps: integrator state and time, event bookkeeping, counters, event rows."""

    state: np.ndarray       # the integrator's state vector (float64)
    dtime: tuple            # heyoka's double-length time (hi, lo)
    steps: tuple            # (total Taylor steps, steps since the last event ended)
    above: np.ndarray       # bool per block: above v_th now
    current: dict | None    # the open event (t_start, hypocentre, blocks, vmax, p0, s0), None between events
    t_last: float           # the end of the last event
    rows: list              # every event row so far (ROW tuples; NaN stress drop and balance if restored)
    balance_max: float = float("nan")   # the largest balance of restored rows (NaN: none restored)

    def boundary(self, every: int) -> int:
        """The events of the last full catalog chunk (what the store keeps of the catalog)."""
        return len(self.rows) // every * every

    def catalog(self, fields, upto: int, first: int = 0) -> dict:
        """Events ``first`` … ``upto`` as catalog arrays (the store's dtypes: int64 counts, float64 else);
        a checkpoint passes only those since the last one (``Checkpoints.save(..., first=)``)."""
        cols = _columns(self.rows[first:upto])
        return {name: cols[name] for name in fields}

    def arrays(self, every: int) -> dict[str, np.ndarray]:
        """Arrays that own their data: what a checkpoint file holds besides the stored catalog chunks."""
        cut = self.boundary(every)
        head = [row[-1] for row in self.rows[:cut] if row[-1] == row[-1]]     # balances, NaN (restored) out
        head_max = max(head, default=float("nan"))
        if self.balance_max == self.balance_max:
            head_max = self.balance_max if head_max != head_max else max(head_max, self.balance_max)
        c = self.current
        return {
            "state": np.array(self.state, dtype=np.float64, copy=True),
            "dtime": np.array(self.dtime, dtype=np.float64),
            "steps": np.array(self.steps, dtype=np.int64),
            "above": np.array(self.above, dtype=np.uint8),
            "t_last": np.array([self.t_last], dtype=np.float64),
            "open": np.array([c is not None], dtype=np.uint8),
            "open_values": np.array([c[k] for k in _OPEN] if c is not None else [], dtype=np.float64),
            "open_blocks": np.array(sorted(c["blocks"]) if c is not None else [], dtype=np.int64),
            # of the events in the full chunks, what the store's outputs need and the catalog does not keep
            "events": np.array([len(self.rows)], dtype=np.int64),
            "balance_max": np.array([head_max], dtype=np.float64),
            # the events past the last full chunk (not yet in the store), every column
            "tail": np.array([[float(v) for v in row] for row in self.rows[cut:]],
                             dtype=np.float64).reshape(-1, len(ROW)),
        }

    @classmethod
    def from_saved(cls, blobs: dict, catalog: dict) -> "Snapshot":
        """From a checkpoint's state bytes (``arrays()``) and the stored catalog of its full chunks."""
        def get(name, dtype):
            value = blobs[name]
            return np.frombuffer(value, dtype=dtype).copy() if isinstance(value, bytes) else np.asarray(value, dtype)

        tail = get("tail", np.float64).reshape(-1, len(ROW))
        head = {name: np.asarray(catalog[name]) for name in ROW[:6]}
        cut = head["t_start"].size
        nan = float("nan")
        if "events" in blobs:
            events = int(get("events", np.int64)[0])
            drops, balances = np.full(cut, nan), np.full(cut, nan)
            balance_max = float(get("balance_max", np.float64)[0])
        else:   # a checkpoint written before 2026-11-26: stress drop and balance of every event
            drops, balances = get("stress_drop", np.float64), get("balance", np.float64)
            events = drops.size if drops.size == balances.size else -1
            balance_max = nan
        if cut + tail.shape[0] != events:
            raise ValueError(f"checkpoint holds {events} events, its catalog {cut} + {tail.shape[0]}")
        rows = []
        for e in range(cut):
            rows.append((*(_scalar(name, head[name][e]) for name in ROW[:6]), float(drops[e]), float(balances[e])))
        for row in tail:
            rows.append(tuple(_scalar(name, row[c]) for c, name in enumerate(ROW)))
        current = None
        if get("open", np.uint8)[0]:
            values = get("open_values", np.float64)
            current = dict(zip(_OPEN, (float(v) for v in values)))
            current["hypocentre"] = int(values[1])
            current["blocks"] = {int(j) for j in get("open_blocks", np.int64)}
        hi, lo = (float(v) for v in get("dtime", np.float64))
        total, since = (int(v) for v in get("steps", np.int64))
        return cls(state=get("state", np.float64), dtime=(hi, lo), steps=(total, since),
                   above=get("above", np.uint8).astype(bool), current=current,
                   t_last=float(get("t_last", np.float64)[0]), rows=rows, balance_max=balance_max)


def _scalar(name, value):
    return int(value) if name in _INTS else float(value)


def _columns(rows) -> dict[str, np.ndarray]:
    cols = list(zip(*rows)) if rows else [()] * len(ROW)
    return {name: np.array(col, dtype=np.int64 if name in _INTS else np.float64) for name, col in zip(ROW, cols)}
