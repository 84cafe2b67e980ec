"""Many slip cycles through heyoka's batch (SIMD) integrator, one point per lane, lanes refilled.

A terminal event that stops the integration in any lane returns control for the whole batch (heyoka's
batch semantics); the lanes without an event have just finished a step and continue at the next call.
So only a point's end returns (a callback notes its lane): switches, sets, rungs, velocity maxima and
t1 are terminal too (the step ends exactly there, as in the scalar loop: the same steps) but act in
heyoka's callback and let the integration go on (``_integrator.LaneActions``; maxima and t1 are
written into ``LaneRecorder``). ``cycle.batch_order`` queues alike points together, so that lanes often end in the
same step and share a return (~10 µs); for the single block an ended lane is parked at rest until all
the lanes have ended (``PARK_SHARE``), so one return finishes and reloads them all, by whole-row numpy
operations while the lanes hold a block of consecutive points (no per-lane Python). A lane whose point
has stopped is loaded with the next point at the next return (its own time, state and parameters), so the SIMD
width stays busy until the queue is empty. Every lane keeps its double-length time exactly
(``dtime``/``set_dtime``), so a point gives the same bits whichever lane and neighbours it had.
"""

from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from ._actions import LaneRecords, Run, act, limit
from ._integrator import Compiled
from .result import Status

__all__ = ["run_batch"]

_SUCCESS = hy.taylor_outcome.success
#: The share of the lanes that ends (parked) before the batch returns to reload them (``run_batch``; 0: no
#: parking). Measured (single block, 16 lanes, 2 000 points, CPU time per point, against no parking):
#: 1/8 and 1/4 are slower (more lanes idle than returns saved), 3/4 is 4-9 % faster, all lanes about
#: the same as 3/4. Once the returns' bookkeeping and the callbacks were cheaper (issue 18), all lanes
#: (1.0) beat 3/4 (best of 9 alternating runs, 2 000 points, CPU time per point): Carlson-Langer 11.5 ->
#: 11.0 µs on the bench grid and 11.6 -> 11.0 on random points, piecewise-linear 9.4 -> 9.6 and 10.1 ->
#: 9.9 µs: lanes reloaded together start alike points together, so fewer wait parked for a laggard.
PARK_SHARE = 1.0
_IDLE = 1 << 62   # the step clock's start of a lane without a point: never the oldest


def run_batch(c: Compiled, values: dict, n_points: int, *, t_max: float, max_steps: int) -> dict:
    """Raw outcomes (arrays over the points, as ``cycle._scalar_points``) for flat arrays of runtime
    ``values`` (slot name → values)."""
    ta = c.integrator
    lanes = c.batch_size
    slots = c.slots
    names = list(c.state_names)
    out_time = np.full(n_points, math.nan)
    out_state = {name: np.full(n_points, math.nan) for name in names}
    recorded = c.recorder.values   # written by the maximum and first events' callbacks
    out_records = {name: np.full(n_points, math.nan) for name in recorded}
    out_steps = np.zeros(n_points, dtype=np.int64)
    out_status = np.zeros(n_points, dtype=np.int8)
    messages = {}

    # Python lists and live views in the loop: at ~0.4 returns per point, numpy's per-call cost on
    # 8-element arrays (where, flatnonzero, any, copies of dtime) was ~40 % of a batch run's time.
    point = [-1] * lanes
    steps = [0] * lanes
    hi, lo = ta.dtime            # read-only views of the lanes' double-length times, live
    new_hi, new_lo = np.zeros(lanes), np.zeros(lanes)   # what set_dtime gets when lanes are reloaded
    target = np.full(lanes, float(t_max))
    state = ta.state
    pars = ta.pars
    head = 0   # the queue: points head, head + 1, ... are still to be loaded
    initial = np.asarray(c.initial, dtype=float)
    slot_values = [(slots.index(name), np.asarray(values[name], dtype=float).tolist()) for name in slots.names]
    first_values = [recorded[name] for name in c.recorder.first]            # NaN until recorded
    max_values = [recorded[name] for name, _ in c.recorder.maxima]          # 0 until recorded
    # each lane as one run of the event actions (``_actions``): column views of the batch's parameters
    # and state (heyoka never reallocates them), its entries of the recorder's arrays, its time
    runs = []
    for lane in range(lanes):
        records = LaneRecords(recorded, lane)
        runs.append(Run(pars[:, lane], state[:, lane], records, records, lambda lane=lane: hi[lane]))

    actions = c.actions   # switches, sets and rungs: acted on in heyoka's callbacks, no return
    actions.runs, ended = runs, actions.ended
    ended.clear()

    # a lane parked at the model's rest state is at its initial state already when they are the same
    rest_is_start = not np.any(initial)
    fresh = [True] * lanes   # a lane's first load: its piece slots hold 1.0, not a one-hot piece 0

    def load(lane: int) -> bool:
        """Next point into ``lane`` (time 0); False when the queue is empty (the lane idles)."""
        nonlocal head
        i = head if head < n_points else -1
        head += 1
        point[lane] = i
        new_hi[lane] = new_lo[lane] = 0.0
        if not (rest_is_start and is_parked[lane]):
            state[:, lane] = initial
        if i < 0:
            # an idle lane rests at the start, time 0 = its target: it does not move, and a lane left
            # non-finite by its last point (time or state NaN) cannot poison this call or the next
            target[lane] = 0.0
            return False
        ta.reset_cooldowns(lane)  # the previous point's cooldowns must not reach this one
        run = runs[lane]
        column = run.pars
        for index, given in slot_values:   # Python floats into the lane's column view: the same doubles
            column[index] = given[i]
        if run.piece or fresh[lane]:
            run.start(c)
            fresh[lane] = False
        else:   # on piece 0 already, and its one-hot slots say so (``_actions._switch`` keeps both)
            run.crossings, run.message = [], ""
        steps[lane] = 0
        for column in first_values:   # LaneRecorder.reset, inlined
            column[lane] = math.nan
        for column in max_values:
            column[lane] = 0.0
        return True

    def finish(lane: int, status: Status, message: str = "") -> None:
        i = point[lane]
        out_time[i], out_steps[i], out_status[i] = hi[lane], steps[lane], int(status)
        for k, name in enumerate(names):
            out_state[name][i] = state[k, lane]
        for name, column in recorded.items():
            out_records[name][i] = column[lane]
        if message:
            messages[i] = message

    # Parking (a model that declares a rest_slot, the single block's forcing): an ended lane is parked in
    # the end event's callback at the model's rest state with that slot at 0 (W = V = 0 stays exactly
    # there: its one next step runs to t_max and it is done, counting that step), its time and state at
    # the end kept in ``stop_hi`` and ``stop_state``, and the integration goes on until ``park_at`` lanes
    # have ended; they are then finished and reloaded together, one return for several points.
    parked = []
    is_parked = [False] * lanes
    forcing = slots.index(c.model.rest_slot) if c.model is not None and c.model.rest_slot else -1
    park_at = max(2, int(PARK_SHARE * lanes)) if forcing >= 0 and PARK_SHARE > 0 else 0
    stop_hi = [0.0] * lanes
    stop_state = [[0.0] * lanes for _ in names]

    stick_slip = int(Status.STICK_SLIP)
    out_columns = [out_state[name] for name in names]
    record_columns = [(column, out_records[name]) for name, column in recorded.items()]

    if park_at:
        state_rows = [(row, state[k]) for k, row in enumerate(stop_state)]   # row views, live
        rest_row = pars[forcing]
        columns = [run.state for run in runs]

        def park(lane: int) -> bool:
            # the end of a point (a stick-slip stop): its time and state kept, the lane parked (~1 µs)
            if is_parked[lane]:   # (at rest, x = 0 identically: no sign change, never seen; be explicit)
                return True
            stop_hi[lane] = hi.item(lane)
            for kept, row in state_rows:
                kept[lane] = row.item(lane)
            columns[lane].fill(0.0)   # (a slice assignment of a column view costs twice as much)
            rest_row[lane] = 0.0
            is_parked[lane] = True
            parked.append(lane)
            return len(parked) < park_at

        actions.park = park

    def finish_parked(lane: int, n_steps: int) -> None:
        i = point[lane]
        out_time[i], out_steps[i], out_status[i] = stop_hi[lane], n_steps, stick_slip
        for out, kept in zip(out_columns, stop_state):
            out[i] = kept[lane]
        for values_, out in record_columns:
            out[i] = values_[lane]

    # Blocks (parking only): while the queue holds a whole batch and every lane ended at the last return,
    # the lanes hold consecutive points ``block`` .. ``block + lanes - 1``, all loaded at one clock, and
    # are finished and reloaded by whole-row numpy operations, not lane by lane (the same values: the
    # same bits). Anything else (an abnormal end, a slow return, the last partial batch) takes the
    # per-lane path below.
    n_named = len(slots.names)
    named = np.array([np.asarray(values[name], dtype=float) for name in slots.names]).reshape(n_named, n_points)
    contiguous = [slots.index(name) for name in slots.names] == list(range(n_named))
    one_hot = None
    if c.n_pieces > 1:
        one_hot = np.zeros((c.n_pieces, 1))
        one_hot[0] = 1.0
    block = -1
    record_resets = [(values_, [math.nan] * lanes) for values_ in first_values] + \
                    [(values_, [0.0] * lanes) for values_ in max_values]

    def load_block(parked_all: bool) -> None:
        """The next ``lanes`` points of the queue into every lane (time set by the caller): ``load`` for
        each lane, by rows."""
        nonlocal block, head
        block = first = head
        head += lanes
        pars[:n_named] = named[:, first:first + lanes]
        if one_hot is not None:   # piece 0 (``Run.start``)
            pars[n_named:n_named + c.n_pieces] = one_hot
        if not (rest_is_start and parked_all):
            state[:] = initial[:, None]
        ta.reset_cooldowns()
        for run in runs:
            if run.piece or run.crossings or run.message:
                run.piece, run.crossings, run.message = 0, [], ""
        for values_, fresh_values in record_resets:
            values_[:] = fresh_values
        for lane in range(lanes):
            point[lane] = first + lane
            is_parked[lane] = False
            fresh[lane] = False

    n_events = len(c.kinds)
    # A lane that never gets a point (fewer points than lanes) must still have a finite right side:
    # ν = ν_f = 0 gave 0/0, a NaN time step and a ValueError from heyoka for the whole batch.
    pars[:, :] = 1.0
    blocks = park_at and contiguous
    if blocks and n_points >= lanes:
        load_block(False)
        live = list(range(lanes))
    else:
        live = [lane for lane in range(lanes) if load(lane)]
    ta.set_dtime(new_hi, new_lo)
    success, step_limit = int(_SUCCESS), int(hy.taylor_outcome.step_limit)
    fired = actions.fired   # (lane, event index) of the ending actions (and unparked ends) of a call
    # Steps by a clock: heyoka steps every lane once per iteration of a call, and a lane that is
    # neither done nor non-finite counts each of them, so a point's steps are the clock's advance
    # since its load; the loop then reads only the lanes that fired, and looks at every lane (slow
    # path) only when one of them counted less (a non-finite state, t_max) or is near max_steps.
    clock = 0
    start = [0 if lane in live else _IDLE for lane in range(lanes)]
    oldest = 0
    t_near = float(t_max) * (1 - 1e-12)
    while live:
        fired.clear()
        parked.clear()
        # at most until the oldest point reaches max_steps: a point without a stop gets exactly
        # max_steps steps, whichever neighbours it had
        ta.propagate_until(target, max_steps=max(max_steps - (clock - oldest), 1))
        counts = [r[3] for r in ta.propagate_res]
        it = max(counts)
        before, clock = clock, clock + it
        times = hi.tolist()
        if block >= 0 and len(parked) == lanes and not fired and clock - oldest < max_steps:
            # the usual return: every lane of the block parked at a stop. A parked lane counted one
            # step to t_max after its stop unless it parked in the call's last iteration.
            where = slice(block, block + lanes)
            out_time[where] = stop_hi
            out_status[where] = stick_slip
            for out, kept in zip(out_columns, stop_state):
                out[where] = kept
            for values_, out in record_columns:
                out[where] = values_
            out_steps[where] = np.subtract(counts, np.not_equal(times, stop_hi)) + (before - oldest)
            if n_points - head >= lanes:
                load_block(True)
                start = [clock] * lanes
                oldest = clock
                ta.set_dtime(0.0, 0.0)
                continue
            # the last, partial batch: lane by lane (``done`` is every lane, all finished)
            block = -1
            done = list(range(lanes))
        else:
            block = -1
            done = []
            for lane in parked:   # finished here (kept in the callback); it counted its step to t_max
                steps[lane] = n = before + counts[lane] - start[lane] - (times[lane] != stop_hi[lane])
                finish_parked(lane, n)
                done.append(lane)
            for lane, index in fired:
                status = ended.pop(lane, None) or act(c, index, runs[lane])
                if status is not None:
                    steps[lane] = before + counts[lane] - start[lane]
                    finish(lane, status, runs[lane].message)
                    done.append(lane)
            # (a lane that reached t_max in the call's last iteration counted it all: seen by its time)
            slow = it == 0 or clock - oldest >= max_steps
            if not slow and not parked:
                slow = counts.count(it) != len(live) or max(times) >= t_near
            elif not slow:
                slow = any(counts[lane] != it or times[lane] >= t_near for lane in live if lane not in done)
            if slow:
                results = ta.propagate_res
                for lane in live:
                    if lane in done:
                        continue
                    outcome = results[lane][0]
                    steps[lane] = before + counts[lane] - start[lane]
                    code = int(outcome)
                    # stopped because another lane had an event or by the call's step budget (code i ≥ 0:
                    # its last step ended at event i, acted on in the callback)
                    if code == success or code >= 0 or code == step_limit:
                        if steps[lane] >= max_steps:
                            finish(lane, Status.NO_STOP, f"no stop within max_steps = {max_steps}")
                            done.append(lane)
                        continue
                    if not 0 <= -code - 1 < n_events:   # time or step limit, non-finite state
                        finish(lane, *limit(outcome, hi[lane], steps[lane], t_max, max_steps))
                        done.append(lane)
        if done:
            # every live lane ended (the usual return, all lanes parked): all times restart at 0 (idle
            # lanes rest at 0), set by one scalar (~0.1 µs; the arrays cost ~8 µs a return)
            everyone = len(done) == len(live)
            if blocks and everyone and len(live) == lanes and n_points - head >= lanes:
                load_block(all(is_parked))   # back to blocks (a lane that did not park is reset)
                start = [clock] * lanes
                oldest = clock
                ta.set_dtime(0.0, 0.0)
                continue
            if not everyone:
                new_hi[:] = hi
                new_lo[:] = lo
            for lane in done:
                start[lane] = clock
                if not load(lane):
                    live.remove(lane)
                    start[lane] = _IDLE
                is_parked[lane] = False
            if everyone:
                ta.set_dtime(0.0, 0.0)
            else:
                ta.set_dtime(new_hi, new_lo)
            oldest = min(start)   # an idle lane's start is _IDLE
    actions.park = None
    out = {"time": out_time, **out_state, **out_records, "steps": out_steps, "status": out_status,
           "messages": messages, "info": c.info}
    for r in c.first_records:
        out[f"time_after_{r}"] = out_time - out_records[r]
    return out
