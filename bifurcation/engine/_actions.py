"""What a terminal event does to one run: the one implementation behind the scalar loop
(``cycle._run``) and the lanes of the batch loop (``_batch.run_batch``).

The compiled system says, per terminal event index, its kind and what it records (``Compiled``); a
``Run`` holds what an event may change in one run (one point): its runtime parameters, its piece of
the friction law, its records. In batch mode a ``Run`` is one lane: its parameters and state are
column views of the batch's arrays and its records are the lane's entries of the recorder's arrays;
"maximum" and "first" events write them in their own callbacks there (``LaneActions.record``, the
same record without the dispatch), so ``act`` sees only ends, switches, sets and rungs (the last
three from heyoka's event callback, ``_integrator.LaneActions``).
"""

from __future__ import annotations

import heyoka as hy

from ._integrator import Compiled, EventKind
from .result import Status

__all__ = ["LaneRecords", "Run", "act", "limit"]

_NONFINITE = hy.taylor_outcome.err_nf_state
_STOP, _MAXIMUM, _FIRST, _SWITCH, _SET = (EventKind.STOP, EventKind.MAX_VELOCITY, EventKind.REACH_NU_F,
                                          EventKind.SWITCH, EventKind.SET)


class LaneRecords:
    """One batch lane's entries of the recorder's arrays, by record name (``values[name][lane]``)."""

    __slots__ = ("values", "lane")

    def __init__(self, values: dict, lane: int) -> None:
        self.values, self.lane = values, lane

    def __getitem__(self, name: str):
        return self.values[name][self.lane]

    def __setitem__(self, name: str, value) -> None:
        self.values[name][self.lane] = value


class Run:
    """What terminal events change in one run: ``pars`` (its runtime parameters, a live 1-D view),
    ``piece`` (of the law, selected by one-hot parameters), ``found`` (the first times), ``maxima``
    (running maxima of ``state``), ``crossings`` (later crossings of the breakpoint that carries a
    first record) and the ``message`` of an abnormal end. ``clock()`` is the run's time now."""

    __slots__ = ("pars", "state", "piece", "found", "maxima", "crossings", "clock", "message")

    def __init__(self, pars, state, found, maxima, clock) -> None:
        self.pars, self.state, self.found, self.maxima, self.clock = pars, state, found, maxima, clock
        self.piece, self.crossings, self.message = 0, [], ""

    def start(self, c: Compiled) -> None:
        """A new run (``found`` and ``maxima`` are the caller's): every start is on piece 0 (rest at
        x = 0, the manifold below the first breakpoint)."""
        self.piece, self.crossings, self.message = 0, [], ""
        if c.n_pieces > 1:
            first = c.slots.piece0
            self.pars[first:first + c.n_pieces] = 0
            self.pars[first] = 1


def act(c: Compiled, index: int, run: Run) -> Status | None:
    """Apply terminal event ``index`` of ``c`` to ``run``: None if the run goes on, else its status
    (``run.message`` says why when it is not a normal end)."""
    kind = c.kinds[index]
    if kind is _STOP:
        return Status.STICK_SLIP
    if kind is _MAXIMUM:
        name = c.records[index]
        value = run.state[c.state_of[index]]
        if value > run.maxima[name]:
            run.maxima[name] = value
    elif kind is _FIRST:
        name = c.records[index]
        if run.found[name] != run.found[name]:   # NaN: the first time only
            run.found[name] = run.clock()
    elif kind is _SET:
        pars = run.pars
        for slot, value in c.sets_of[index]:
            pars[slot] = value
    elif kind is _SWITCH:
        return _switch(c, c.breakpoint_of[index], run)
    return None   # a rung: the step ended there, nothing to record


def _switch(c: Compiled, j: int, run: Run) -> Status | None:
    """A switch at breakpoint j: the upper end of this piece means up, the lower means down."""
    piece = run.piece
    up = j == piece
    if not up and j != piece - 1:   # cannot happen with ordered breakpoints; be explicit
        run.message = f"switch event {j} seen in piece {piece}"
        return Status.NONFINITE
    first, pars = c.slots.piece0, run.pars
    pars[first + piece] = 0
    piece = run.piece = piece + 1 if up else piece - 1
    pars[first + piece] = 1
    alias_record, alias = c.first_alias
    if j == alias:
        found = run.found
        if up and found[alias_record] != found[alias_record]:
            found[alias_record] = run.clock()
        else:
            run.crossings.append(run.clock())
    return None


def limit(outcome, time, steps: int, t_max: float, max_steps: int) -> tuple[Status, str]:
    """Status and message of a run that returned without a terminal event: a non-finite state, or no
    stop within the bounds (``time`` and ``steps`` where it returned)."""
    if outcome == _NONFINITE:
        return Status.NONFINITE, f"non-finite state at t = {float(time):.17g}"
    return Status.NO_STOP, (f"no stop before t_max = {t_max:g} / max_steps = {max_steps} "
                            f"(t = {float(time):.6g}, steps = {steps})")
