"""Several rs-chain runs of one structure at once, in the SIMD lanes of one heyoka batch integrator.

The runs of a grid that share a structure (state law, N, inertia, ends, damping) differ only in their
runtime parameters and start; heyoka's batch mode (``taylor_adaptive_batch``) integrates ``lanes`` of them
in the lanes of the CPU's vector registers, each lane with its own step sizes, events and parameters.
Each lane's crossings and maxima are the scalar engine's (``_system``: the same equations, the same
event functions, the same tolerance) and are assembled by the scalar engine's ``simulate._Events``; only
the arithmetic is vectorised, so a lane's catalog equals the scalar run's to rounding, not bit for bit
(tests/test_rs_chain_batch.py measures it, against the scalar engine and the mpmath references).

Measured (aging, ℓ = 3, η = 1e-3, k = 0.1, A = 1, seeds 1-4, propagation with every event, CPU time, in
one process on the shared AVX2 machine): 4 lanes take 1/2.9 the time of 4 scalar runs at N = 4 and
N = 16, 1/2.1 at N = 64; ``bifurcation bench --suite rs-chain`` reports it against the compiled DOP853.

A lane whose chain has its events takes the next chain waiting: the propagation stops (heyoka refuses a
time changed inside its callback), that lane's time is set back to 0 and its state and parameters to the
next chain's, and all lanes go on (a lane's steps do not depend on the other lanes). With no chain
waiting it idles, integrated but no longer read, until the last lane ends. Checkpoints per lane
(``every``, ``save``, ``resume``: those of ``simulate.run``; the store's runner with ``[engine] batch``);
no ``crossings``.
Massless undamped chains (M = 0, η = 0) blow up in finite time below the critical stiffness and would stop
all lanes: they are refused (run them with ``simulate.run``).
"""

from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from ...errors import InputError
from ..rate_state.laws import resolve_state_law
from ._system import COMPACT_ABOVE, EXACT_TOL, MAXIMUM_EVENT_SCALE, PARAMETERS, Layout, rhs_expressions
from .result import RSChainStatus
from .checkpoint import Snapshot
from .simulate import LOOSEST_TOL, RSChainResult, RSChainSpec, _Events, _number, _Steady

__all__ = ["LANES", "run_batch"]

#: Lanes of one batch integrator: 4 doubles fill an AVX2 register (8 would fill AVX-512's; measured here
#: on AVX2 only).
LANES = 4

_CACHE: dict = {}


class _LaneCallback:
    """Records (lane, time, kind, block): kind ±1 for a crossing of v_th (``maximum=False``), 0 for a maximum."""

    def __init__(self, buffer: list, j: int, maximum: bool) -> None:
        self.buffer, self.j, self.maximum = buffer, j, maximum

    def __call__(self, ta, time, d_sgn, lane) -> None:
        kind = 0 if self.maximum else (1 if d_sgn > 0 else -1)
        self.buffer.append((int(lane), float(time), kind, self.j))

    def __deepcopy__(self, memo) -> "_LaneCallback":
        return self   # heyoka deep-copies callbacks; every copy must record here


def _compiled(key: tuple):
    hit = _CACHE.get(key)
    if hit is None:
        law_name, n, inertial, periodic, damped, maxima, tol, lanes = key
        law = resolve_state_law(law_name)
        layout = Layout(n, inertial)
        variables = hy.make_vars(*layout.names())
        par = {name: hy.par[i] for i, name in enumerate(PARAMETERS)}
        rhs = rhs_expressions(law, layout, variables, par, hy.exp, hy.log, periodic=periodic, damped=damped)
        buffer: list = []
        nt = [hy.nt_event_batch(variables[layout.x(j)] - par["ln_v_th"], _LaneCallback(buffer, j, False))
              for j in range(n)]
        if maxima:
            nt += [hy.nt_event_batch(MAXIMUM_EVENT_SCALE * rhs[layout.x(j)], _LaneCallback(buffer, j, True),
                                     direction=hy.event_direction.negative) for j in range(n)]
        ta = hy.taylor_adaptive_batch(list(zip(variables, rhs)), np.zeros((layout.size, lanes)),
                                      pars=np.zeros((len(PARAMETERS), lanes)), nt_events=nt,
                                      compact_mode=n > COMPACT_ABOVE, tol=tol)
        hit = _CACHE[key] = (ta, layout, buffer)
    return hit


def run_batch(specs, states0, events: int, *, t_max: float = math.inf, max_steps: int = 10_000_000,
              maxima: bool = True, tol: float = EXACT_TOL, lanes: int = LANES, every: int | None = None,
              save=None, resume=None, steady: bool = True) -> list[RSChainResult]:
    """``simulate.run`` for chains of one structure, ``lanes`` at a time; one result per spec, in order.

    ``specs`` share state law, N, inertia, ends and damping (η > 0 or not), and have M > 0 or η > 0;
    ``states0`` are their starts (``initial_state``). A lane that has its events takes the next chain
    waiting (the batch stops, that lane's time is set back to 0, and it goes on: no lane waits for the
    slowest while chains remain); with fewer chains than lanes the spare lanes idle.

    Checkpoints per lane, as ``simulate.run``'s: ``save(c, snapshot)`` is called for chain ``c`` at the end
    of the first step after which its events done reach a new multiple of ``every`` (while events remain);
    ``resume[c]`` (a ``checkpoint.Snapshot`` or None) restarts chain ``c`` from one. A lane's steps depend
    on its own column only, so a chain resumed from a lane's snapshot takes the steps of the straight lane,
    bit for bit; from a scalar run's snapshot it agrees with the scalar run to rounding.

    ``steady``: each lane ends ``steady`` by ``simulate.run``'s test (its own samples on its own time)."""
    specs = list(specs)
    if not specs:
        raise InputError("specs", specs, "is empty", "give at least one RSChainSpec")
    first = specs[0]
    structure = (first.state_law, first.n, first.inertial, first.periodic, first.eta > 0)
    for spec in specs:
        if not isinstance(spec, RSChainSpec):
            raise InputError("specs", spec, "is not an RSChainSpec", "give RSChainSpec(...) values")
        if (spec.state_law, spec.n, spec.inertial, spec.periodic, spec.eta > 0) != structure:
            raise InputError("specs", spec, "differs in structure from the first", "batch chains of one "
                             "state law, N, inertia, ends and damping")
        if not (spec.inertial or spec.eta > 0):
            raise InputError("specs", spec, "is massless and undamped (M = 0, η = 0)",
                             "run it with simulate.run: it may blow up in finite time, which stops a batch")
    if int(events) < 1:
        raise InputError("events", events, "must be >= 1", "give the number of events to catalogue")
    if isinstance(lanes, bool) or not isinstance(lanes, (int, np.integer)) or not 1 <= lanes <= 64:
        raise InputError("lanes", lanes, "is not a lane count from 1 to 64", f"give e.g. {LANES}")
    lanes = int(lanes)
    tol = _number("tol", tol, positive=True, fix=f"give a tolerance from {EXACT_TOL:.3g} to {LOOSEST_TOL:g}")
    if not EXACT_TOL <= tol <= LOOSEST_TOL:
        raise InputError("tol", tol, f"is outside [{EXACT_TOL:.3g}, {LOOSEST_TOL:g}]",
                         f"give a tolerance from {EXACT_TOL:.3g} (the exact default) to {LOOSEST_TOL:g}")
    ta, layout, buffer = _compiled((*structure, bool(maxima), tol, lanes))
    starts = [np.asarray(s, dtype=float) for s in states0]
    if len(starts) != len(specs) or any(s.shape != (layout.size,) for s in starts):
        raise InputError("states0", [s.shape for s in starts], f"are not {len(specs)} states of {layout.size} "
                         "values", "give initial_state(spec, ...) for each spec")
    if save is not None and (every is None or int(every) < 1):
        raise InputError("every", every, "must be >= 1 with save", "give the events between checkpoints")
    resume = list(resume) if resume is not None else [None] * len(specs)
    if len(resume) != len(specs):
        raise InputError("resume", len(resume), f"is not one snapshot (or None) per spec ({len(specs)})",
                         "give a list as long as specs")
    for snap in resume:
        if snap is not None and (np.shape(snap.state) != (layout.size,) or np.shape(snap.above) != (first.n,)):
            raise ValueError(f"checkpoint state of {np.size(snap.state)} values does not fit this chain "
                             f"({layout.size})")
    buffer.clear()
    state, pars, p_index = ta.state, ta.pars, layout.potency
    queue = list(range(len(specs)))
    run_of: list = [None] * lanes           # the chain each lane integrates (None: idle)
    assemblers: list = [None] * lanes
    status: list = [None] * lanes
    results: list = [None] * len(specs)
    bounded_t = math.isfinite(t_max)
    # steps counted once for all lanes (every lane takes one step per batch step): a lane's steps are
    # the count now less the count when its chain was loaded, or when its last event ended
    clock = {"now": 0, "deadline": 0, "idle": np.zeros(0, dtype=np.intp)}
    loaded, last_end, ended_at = [0] * lanes, [0] * lanes, [0] * lanes
    start_time = [(0.0, 0.0)] * lanes       # the double-length time a lane (re)starts at
    chunks = [0] * lanes                    # checkpoints of the lane's chain so far (multiples of every)
    watches: list = [None] * lanes          # the lane's steady-sliding test (simulate._Steady), or None
    next_sample = np.full(lanes, math.inf)  # its next sample time (inf: none)
    p_row = state[p_index]                  # a view: P of every lane

    def load(lane: int, chain: int) -> None:
        values = specs[chain].parameters()
        pars[:, lane] = [values[name] for name in PARAMETERS]
        run_of[lane] = chain
        asm = assemblers[lane] = _Events(specs[chain], layout, int(events))
        status[lane] = [RSChainStatus.COMPLETE, ""]
        snap = resume[chain]
        if snap is None:
            state[:, lane] = starts[chain]
            loaded[lane] = last_end[lane] = clock["now"]
            start_time[lane] = (0.0, 0.0)
        else:                               # as simulate.run restores a snapshot
            state[:, lane] = snap.state
            start_time[lane] = tuple(snap.dtime)
            asm.above[:] = snap.above
            asm.n_above = int(np.count_nonzero(asm.above))
            asm.current = None if snap.current is None else {**snap.current, "blocks": set(snap.current["blocks"])}
            asm.t_last = snap.t_last
            asm.rows = list(snap.rows)
            asm.restored_balance_max = snap.balance_max
            loaded[lane] = clock["now"] - int(snap.steps[0])
            last_end[lane] = clock["now"] - int(snap.steps[1])
        chunks[lane] = asm.done // every if save is not None else 0
        watches[lane] = _Steady(specs[chain], start_time[lane][0] + start_time[lane][1]) if steady else None
        next_sample[lane] = watches[lane].next if steady else math.inf

    def finish(lane: int) -> None:
        chain, asm = run_of[lane], assemblers[lane]
        cols = list(zip(*asm.rows)) if asm.rows else [()] * 8
        results[chain] = RSChainResult(
            spec=specs[chain], t_start=np.array(cols[0], dtype=float), hypocentre=np.array(cols[1], dtype=np.int64),
            n_blocks=np.array(cols[2], dtype=np.int64), potency=np.array(cols[3], dtype=float),
            duration=np.array(cols[4], dtype=float),
            max_velocity=np.array(cols[5], dtype=float) if maxima else np.full(len(asm.rows), np.nan),
            stress_drop=np.array(cols[6], dtype=float), balance=np.array(cols[7], dtype=float),
            t_end=asm.t_last if asm.rows else math.nan, steps=ended_at[lane] - loaded[lane],
            status=status[lane][0], message=status[lane][1], meta={"lanes": lanes},
            restored_balance_max=asm.restored_balance_max)
        run_of[lane] = None
        next_sample[lane] = math.inf

    def state_at(lane: int):
        def at(time: float) -> np.ndarray:
            times = ta.time.copy()          # the other lanes anywhere: only this lane's column is read
            times[lane] = time
            return ta.update_d_output(times)[:, lane]
        return at

    readers = [state_at(lane) for lane in range(lanes)]
    ended: list = []                        # lanes whose chain ended in this propagation

    def running() -> list:
        return [lane for lane in range(lanes) if run_of[lane] is not None and lane not in ended]

    def retune() -> None:
        """After roots or a refill: the lanes between events (P reset each step) and the step deadline."""
        live = running()
        clock["idle"] = np.array([lane for lane in live if not assemblers[lane].n_above], dtype=np.intp)
        clock["deadline"] = min((last_end[lane] for lane in live), default=clock["now"]) + max_steps

    def end(lane: int) -> None:
        ended.append(lane)
        ended_at[lane] = clock["now"]

    def snapshot(lane: int) -> Snapshot:
        asm, now, (hi, lo) = assemblers[lane], clock["now"], ta.dtime
        c = asm.current
        return Snapshot(state=np.array(state[:, lane], copy=True), dtime=(float(hi[lane]), float(lo[lane])),
                        steps=(now - loaded[lane], now - last_end[lane]), above=asm.above.copy(),
                        current=None if c is None else {**c, "blocks": set(c["blocks"])}, t_last=asm.t_last,
                        rows=list(asm.rows), balance_max=asm.restored_balance_max)

    def step(ta) -> bool:
        now = clock["now"] = clock["now"] + 1
        grew = []
        if buffer:
            roots: dict = {}
            for lane, time, kind, j in buffer:
                roots.setdefault(lane, []).append((time, kind, j))
            buffer.clear()
            for lane, found in roots.items():
                if run_of[lane] is None or lane in ended:
                    continue
                asm = assemblers[lane]
                before = asm.done
                asm.feed(found, readers[lane])
                if asm.done >= asm.wanted:
                    end(lane)
                elif asm.done > before:
                    last_end[lane] = now
                    grew.append(lane)
            retune()
        if clock["idle"].size:
            p_row[clock["idle"]] = 0.0       # between events P restarts from 0, as in simulate.run
        if steady:                          # in simulate.run's order: after P's reset, before the bounds
            times = ta.time
            if np.any(next_sample <= times):
                for lane in running():
                    if next_sample[lane] <= times[lane]:
                        w = watches[lane]
                        if w.sample(float(times[lane]), state[:, lane], assemblers[lane].n_above):
                            status[lane] = [RSChainStatus.STEADY,
                                            w.message(float(times[lane]), assemblers[lane].done,
                                                      now - loaded[lane])]
                            end(lane)
                            next_sample[lane] = math.inf
                        else:
                            next_sample[lane] = w.next
                retune()
            for lane in grew:
                if watches[lane] is not None:
                    watches[lane].reset()
        if now > clock["deadline"] or bounded_t:
            for lane in running():
                asm = assemblers[lane]
                if now - last_end[lane] > max_steps or (bounded_t and ta.time[lane] - asm.t_last > t_max):
                    status[lane] = [RSChainStatus.NO_STOP,
                                    f"no-stop: event {asm.done + 1} did not end within t_max = {t_max:g} or "
                                    f"max_steps = {max_steps} ({now - loaded[lane]} steps)"]
                    end(lane)
            retune()
        if save is not None:                # after P's reset and the no-stop check, as simulate.run
            for lane in grew:
                if lane not in ended and assemblers[lane].done // every > chunks[lane]:
                    chunks[lane] = assemblers[lane].done // every
                    save(run_of[lane], snapshot(lane))
        # stop to give an ended lane the next chain, or when no lane has a chain left
        return not ((ended and queue) or not running())

    for lane in range(lanes):
        load(lane, queue.pop(0) if queue else 0)
        if lane >= len(specs):
            run_of[lane] = None             # a spare lane: the first chain's start, never read
            next_sample[lane] = math.inf
    ta.set_dtime(np.array([t[0] for t in start_time]), np.array([t[1] for t in start_time]))
    retune()
    while any(chain is not None for chain in run_of):
        ended.clear()
        ta.propagate_until(np.full(lanes, 1e300), callback=step)
        for lane, res in enumerate(ta.propagate_res):
            if run_of[lane] is not None and lane not in ended and res[0] != hy.taylor_outcome.cb_stop:
                status[lane] = [RSChainStatus.NONFINITE, f"{res[0]} after {clock['now'] - loaded[lane]} steps"]
                end(lane)
        if not ended:
            raise RuntimeError("rs-chain batch: a propagation ended with no chain done (a bug)")
        hi, lo = (np.array(v, copy=True) for v in ta.dtime)
        for lane in ended:
            finish(lane)
            if queue:
                load(lane, queue.pop(0))
                hi[lane], lo[lane] = start_time[lane]   # t = 0 as a scalar run, or the snapshot's time
        ta.set_dtime(hi, lo)
        ended.clear()
        retune()
    return results
