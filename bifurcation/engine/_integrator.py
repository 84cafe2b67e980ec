"""One compiled Taylor integrator per (model, law, precision), reused for every point.

The model declares the system (``Model.equations``: state, right-hand sides, event functions) and
what each event does (``Model.events``); this module compiles them with heyoka and records, per
terminal event index, its action and what it records, so the one event loop (``cycle.run_cycle``
and ``_batch.run_batch``) serves every model. Runtime parameters are named slots
(``bifurcation.models.Slots``): the model's ``parameters``, then one one-hot selector per piece of a
piecewise law. For the single block (docs/physics.md, ``bifurcation.models.single_block``) the slots
are ν, ν_f and the forcing switch c, and every event function is O(1) in the scaled variables while
the block slips (a switching function of size 1e12 spoils the location of the other events).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import heyoka as hy
import numpy as np

from ..laws import FrictionLaw
from ..models import Model
from ..models.single_block import SINGLE_BLOCK

__all__ = ["COOLDOWN", "Compiled", "EventKind", "LaneActions", "LaneRecorder", "build", "compiled", "fp_info"]

_CACHE: dict = {}

#: Cooldown of the terminal events. heyoka's automatic one scales with the error estimate of the event
#: equation, which follows the state: at ν ≤ 3e-17 (W ~ 1e17) it outlasted the two time units between
#: the up- and down-crossings of the kink of Eq. (12), the second switch was missed and Δ came out 0.6 %
#: wrong. 1e-12 is far above the restart offset (a few ulps of t ≲ 1e3) and far below the shortest
#: time between events (~ln 2/(2α) ≈ 7e-5 at ν_f = 1e-4).
COOLDOWN = 1e-12


class EventKind(Enum):
    """What a terminal event does in the event loop (from the model's ``Event.action``)."""

    STOP = "end"              # the run of this point ends
    MAX_VELOCITY = "maximum"  # a running maximum of a state variable is updated
    REACH_NU_F = "first"      # the time of a first occurrence is recorded
    SWITCH = "switch"         # the piece selector moves one piece up or down
    SET = "set"               # runtime slots are set to the values the system gives
    RUNG = "step"             # ends a Taylor step, nothing else (a rung of a ladder: _fading)


_KINDS = {kind.value: kind for kind in EventKind}
_DIRECTIONS = {"negative": "negative", "positive": "positive", "any": "any"}


@dataclass(frozen=True)
class Compiled:
    """A compiled integrator and the meaning of its terminal events.

    Per terminal event index: ``kinds`` (its ``EventKind``), ``records`` (the raw outcome a "first" or
    "maximum" event writes, "" otherwise), ``state_of`` (the state index whose maximum a "maximum"
    event records, -1 otherwise) and ``breakpoint_of`` (the breakpoint of a switch, -1 otherwise).
    ``first_alias`` maps a breakpoint index to the "first" record its up-crossing also makes (the
    single block's x = 1 breakpoint is t1); later crossings of it are kept in order (``crossings``).
    """

    law: FrictionLaw
    precision: str
    integrator: object
    kinds: tuple
    breakpoint_of: tuple
    n_pieces: int
    batch_size: int
    recorder: "LaneRecorder | None" = None  # batch mode: where maxima and first times are recorded
    dtype: type = np.float64                # numpy type of the integrator's numbers
    switch_at_one: int = -1                 # the breakpoint that carries a "first" record (-1 if none)
    model: object = None
    slots: object = None
    records: tuple = ()
    state_of: tuple = ()
    first_records: tuple = ()               # every "first" record name of the model
    max_records: tuple = ()                 # (record name, state index) of every "maximum" event
    first_alias: tuple = ("", -1)           # (record, breakpoint index) carried by a switch
    state_names: tuple = ()                 # the system's state variables, in order
    initial: tuple = ()                     # the model's initial state for this structure
    sets_of: tuple = ()                     # per terminal event: ((slot index, value), ...) of a "set"
    max_start: tuple = ()                   # (record, start value) of each maximum from ``initial``
    info: dict = None                       # the system's facts for ``classify`` (``System.info``)
    actions: "LaneActions | None" = None    # batch mode: switches, sets and rungs acted on in callbacks


def fp_info(precision: str):
    """(heyoka fp_type or None for double, numpy dtype, constant maker) for a precision name."""
    if precision == "double":
        return None, np.float64, lambda v: hy.expression(float(v))
    if precision == "quad":
        return hy.real128, hy.real128, lambda v: hy.expression(hy.real128(str(v)))
    raise ValueError(precision)


class LaneRecorder:
    """What "maximum" and "first" events record per batch lane: running maxima and first times.

    Written by the events' callbacks (``LaneActions.record``): the events are terminal, so the step
    ends exactly at the event and the state there is the integrator's own, but the callback lets the
    integration go on (a return would stop every lane of the batch).
    """

    def __init__(self, lanes: int, first=(), maxima=()) -> None:
        # Python lists, not arrays: a callback reads and writes Python floats (~0.1 µs each, a numpy
        # scalar costs several times that)
        self.values = {name: [math.nan] * lanes for name in first}
        self.values.update({name: [0.0] * lanes for name, _ in maxima})
        self.first, self.maxima = tuple(first), tuple(maxima)

    def __deepcopy__(self, memo) -> "LaneRecorder":
        # heyoka deep-copies each event callback on construction; all of them must record here.
        return self

    def reset(self, lane: int) -> None:
        for name in self.first:
            self.values[name][lane] = math.nan
        for name, _ in self.maxima:
            self.values[name][lane] = 0.0


class LaneActions:
    """Batch mode: the terminal events that only change a lane's run (switches, sets, rungs, maxima and
    first times) act in heyoka's event callback and let the integration go on (the callback returns True), so they no
    longer return control to Python for the whole batch. The step still ends exactly at the event
    and the next step starts on the new piece, as after a return: the same bits. ``runs`` (one
    ``_actions.Run`` per lane) is set by the batch loop; an action that ends the run (a switch out of
    order) leaves its status in ``ended[lane]`` and stops the integration (returns False)."""

    def __init__(self) -> None:
        self.compiled, self.runs, self.ended = None, (), {}
        self.fired = []   # (lane, event index) of each stopping event since the batch loop last looked
        self.park = None  # the batch loop's lane -> bool for an end: go on with the lane parked (True)

    def __deepcopy__(self, memo) -> "LaneActions":
        return self   # heyoka deep-copies each event callback on construction

    def callback(self, index: int):
        from ._actions import act

        def on_event(ta, d_sgn, lane) -> bool:
            status = act(self.compiled, index, self.runs[lane])
            if status is None:
                return True
            self.ended[lane] = status
            self.fired.append((lane, index))
            return False

        return on_event

    def record(self, kind: EventKind, values, of: int = -1):
        """The callback of a "maximum" (of state ``of``) or "first" event: ``act``'s record, written
        straight into the recorder's array ``values`` (no ``act`` dispatch, no ``LaneRecords``: ~1 µs a
        point), and the integration goes on. Terminal like a rung, so the step ends at the event and the
        state there is the integrator's own (no dense output to update: ~2 µs a point), and the steps
        are the scalar loop's, where these events are terminal too."""
        if kind is EventKind.MAX_VELOCITY:
            def on_maximum(ta, d_sgn, lane) -> bool:
                value = self.runs[lane].state.item(of)
                if value > values[lane]:
                    values[lane] = value
                return True

            return on_maximum

        def on_first(ta, d_sgn, lane) -> bool:
            if values[lane] != values[lane]:   # NaN: the first time only
                values[lane] = float(self.runs[lane].clock())
            return True

        return on_first

    def end(self, index: int):
        """The callback of an end event: note the lane, stop the integration (the batch loop reloads
        the lane; only there can its time be reset). The loop then reads only the noted lanes. With a
        ``park`` hook (the batch loop's) the hook does both: it parks the lane and says whether the
        integration goes on."""
        fired = self.fired

        def on_end(ta, d_sgn, lane) -> bool:
            park = self.park
            if park is None:
                fired.append((lane, index))
                return False
            return park(lane)

        return on_end


#: Terminal events whose action a batch callback takes without returning (``LaneActions``).
_IN_CALLBACK = (EventKind.SWITCH, EventKind.SET, EventKind.RUNG)
#: Terminal events whose record a batch callback writes without returning (``LaneActions.record``).
_RECORDS = (EventKind.MAX_VELOCITY, EventKind.REACH_NU_F)


def _events(model, system, law: FrictionLaw, fp_type, recorder: LaneRecorder | None, slots,
            actions: LaneActions | None = None):
    """Terminal events with their meanings (every event is terminal; in batch mode most act in heyoka's
    callback and let the integration go on: ``LaneActions``)."""
    batch = recorder is not None
    make = hy.t_event_batch if batch else hy.t_event
    fp = {"fp_type": fp_type} if fp_type is not None else {}
    cooldown = fp_type(COOLDOWN) if fp_type is not None else COOLDOWN
    state_names = [str(v) for v in system.state]

    def direction(name):
        return getattr(hy.event_direction, _DIRECTIONS[name])

    events, kinds, bp_of, records, state_of, sets_of = [], [], [], [], [], []
    for event in model.events:
        if event.name not in system.events:
            continue
        found = system.events[event.name]
        instances = list(found) if event.per_piece else [found]
        for j, (expression, way) in enumerate(instances):
            index = state_names.index(event.of) if event.action == "maximum" else -1
            kind = _KINDS[event.action]
            if actions is not None and kind in _RECORDS:
                fp["callback"] = actions.record(kind, recorder.values[event.records], index)
            elif actions is not None and kind in _IN_CALLBACK:
                fp["callback"] = actions.callback(len(events))
            elif actions is not None and kind is EventKind.STOP:
                fp["callback"] = actions.end(len(events))
            events.append(make(expression, direction=direction(way), cooldown=cooldown, **fp))
            fp.pop("callback", None)
            kinds.append(kind)
            bp_of.append(j if event.per_piece else -1)
            records.append(event.records)
            state_of.append(index)
            sets = system.sets.get(event.name, ()) if event.action == "set" else ()
            sets_of.append(tuple((slots.index(k), v) for k, v in sets[j].items()) if sets else ())
    return events, tuple(kinds), tuple(bp_of), tuple(records), tuple(state_of), tuple(sets_of)


def _declared(model) -> Model:
    """``model`` itself: the engine is handed a declaration and never looks one up by name (None: the
    single block, whose ``slip``/``limit`` live in this package)."""
    if model is None:
        return SINGLE_BLOCK
    if not isinstance(model, Model):
        raise TypeError(f"the engine takes a bifurcation.models.Model, not {model!r} "
                        "(look a name up with bifurcation.models.get_model)")
    return model


def compiled(law: FrictionLaw, precision: str = "double", batch_size: int = 1, model=None,
             structure=None) -> Compiled:
    """The cached compiled integrator for ``law`` under ``model`` (a ``Model``; None: the single block)
    and the values ``structure`` of its structural axes."""
    model = _declared(model)
    structure = dict(structure or {})
    key = (model.name, law.name, law.formula, precision, batch_size, tuple(sorted(structure.items())))
    hit = _CACHE.get(key)
    if hit is None:
        hit = _CACHE[key] = build(law, precision, batch_size, model=model, structure=structure)
    return hit


def build(law: FrictionLaw, precision: str = "double", batch_size: int = 1, model=None,
          structure=None) -> Compiled:
    """Compile a new integrator for ``law`` (uncached; the benchmark's naive baseline uses this)."""
    model = _declared(model)
    structure = dict(structure or {})
    fp_type, dtype, num = fp_info(precision)
    slots = model.slots(len(law.pieces))
    system = model.equations(law, slots, num, precision=precision, **structure)
    names = tuple(str(v) for v in system.state)
    batch = batch_size > 1
    first = tuple(e.records for e in model.events if e.action == "first")
    maxima = tuple((e.records, names.index(e.of)) for e in model.events if e.action == "maximum")
    recorder = LaneRecorder(batch_size, first, maxima) if batch else None
    actions = LaneActions() if batch else None
    events, kinds, bp_of, records, state_of, sets_of = _events(model, system, law, fp_type, recorder, slots,
                                                               actions)
    kwargs = dict(t_events=events, compact_mode=precision == "quad")
    if fp_type is not None:
        kwargs["fp_type"] = fp_type
    n_state = len(system.state)
    if batch:
        ta = hy.taylor_adaptive_batch(list(zip(system.state, system.rhs)), np.zeros((n_state, batch_size)),
                                      pars=np.zeros((slots.size, batch_size)), **kwargs)
    else:
        ta = hy.taylor_adaptive(list(zip(system.state, system.rhs)), np.zeros(n_state, dtype=dtype),
                                pars=np.zeros(slots.size, dtype=dtype), **kwargs)
    alias = system.first_on_switch
    c = Compiled(law, precision, ta, kinds, bp_of, len(law.pieces), batch_size, recorder, dtype, alias[1],
                 model=model, slots=slots, records=records, state_of=state_of, first_records=first,
                 max_records=maxima, first_alias=alias, state_names=names, initial=model.start(structure),
                 sets_of=sets_of,
                 max_start=tuple((name, dtype(model.start(structure)[i])) for name, i in maxima),
                 info=dict(system.info), actions=actions)
    if actions is not None:
        actions.compiled = c
    return c
