"""Many slip cycles through heyoka's batch (SIMD) integrator, one point per lane, lanes refilled.

A terminal event in any lane returns control for the whole batch (heyoka's batch semantics); the
lanes without an event have just finished a step and continue at the next call. So only the stop and
the piece switches are terminal here; velocity maxima and t1 are recorded by non-terminal events
(``LaneRecorder``), which keeps the SIMD lanes stepping between returns. A lane whose point
has stopped is loaded at once with the next point (its own time, state and parameters), so the SIMD
width stays busy until the queue is empty. Every lane keeps its double-length time exactly
(``dtime``/``set_dtime``), so a point gives the same bits whichever lane and neighbours it had.
"""

from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from ._integrator import Compiled, EventKind
from .result import Status

__all__ = ["run_batch"]

_NONFINITE = hy.taylor_outcome.err_nf_state
_SUCCESS = hy.taylor_outcome.success
_STOP, _RUNG = EventKind.STOP, EventKind.RUNG


def run_batch(c: Compiled, nu: np.ndarray, nu_f: np.ndarray, *, t_max: float, max_steps: int) -> dict:
    """Raw outcomes (arrays over the points) of finite-ν cycles for flat arrays ``nu``, ``nu_f``."""
    ta = c.integrator
    lanes = c.batch_size
    n_points = nu.size
    n_pieces = c.n_pieces
    out_time = np.full(n_points, math.nan)
    out_W = np.full(n_points, math.nan)
    out_vmax = np.full(n_points, math.nan)
    out_creep = np.full(n_points, math.nan)
    out_steps = np.zeros(n_points, dtype=np.int64)
    out_status = np.zeros(n_points, dtype=np.int8)
    messages = {}

    point = np.full(lanes, -1)
    piece = np.zeros(lanes, dtype=int)
    creep, vmax = c.recorder.creep, c.recorder.vmax  # written by the non-terminal events too
    steps = np.zeros(lanes, dtype=np.int64)
    hi, lo = (np.array(a) for a in ta.dtime)
    state = ta.state
    pars = ta.pars
    queue = iter(range(n_points))

    def load(lane: int) -> None:
        i = next(queue, -1)
        point[lane] = i
        if i < 0:
            return
        hi[lane] = lo[lane] = 0.0
        state[:, lane] = 0.0
        ta.reset_cooldowns(lane)  # the previous point's cooldowns must not reach this one
        pars[0, lane], pars[1, lane], pars[2, lane] = nu[i], nu_f[i], 1.0
        if n_pieces > 1:
            pars[3:3 + n_pieces, lane] = 0.0
            pars[3, lane] = 1.0
        piece[lane], creep[lane], vmax[lane], steps[lane] = 0, math.nan, 0.0, 0

    def finish(lane: int, status: Status, message: str = "") -> None:
        i = point[lane]
        out_time[i], out_W[i], out_vmax[i] = hi[lane], state[0, lane], vmax[lane]
        out_creep[i], out_steps[i], out_status[i] = creep[lane], steps[lane], int(status)
        if message:
            messages[i] = message
        load(lane)

    kinds, breakpoint_of, at_one = c.kinds, c.breakpoint_of, c.switch_at_one
    n_events = len(kinds)
    # A lane that never gets a point (fewer points than lanes) must still have a finite right side:
    # ν = ν_f = 0 gave 0/0, a NaN time step and a ValueError from heyoka for the whole batch.
    pars[0, :] = pars[1, :] = 1.0
    for lane in range(lanes):
        load(lane)
    ta.set_dtime(hi, lo)
    while (point >= 0).any():
        active = point >= 0
        target = np.where(active, t_max, hi)
        ta.propagate_until(target, max_steps=max_steps)
        results = ta.propagate_res
        hi, lo = (np.array(a) for a in ta.dtime)
        reloaded = False
        for lane in np.flatnonzero(active):
            outcome, _, _, n = results[lane]
            steps[lane] += n
            index = -int(outcome) - 1  # terminal event i comes back as −(i + 1)
            if 0 <= index < n_events:
                if kinds[index] is _STOP:
                    finish(lane, Status.STICK_SLIP)
                    reloaded = True
                    continue
                if kinds[index] is _RUNG:  # this lane's step ended on a rung: nothing to do
                    continue
                # only the stop, the switches and the rungs are terminal in batch mode
                j = breakpoint_of[index]
                up = j == piece[lane]
                pars[3 + piece[lane], lane] = 0.0
                piece[lane] += 1 if up else -1
                pars[3 + piece[lane], lane] = 1.0
                if up and j == at_one and creep[lane] != creep[lane]:
                    creep[lane] = hi[lane]
            elif outcome == _SUCCESS:  # stopped because another lane had an event
                if steps[lane] >= max_steps:
                    finish(lane, Status.NO_STOP, f"no stop within max_steps = {max_steps}")
                    reloaded = True
            else:
                if outcome == _NONFINITE:
                    finish(lane, Status.NONFINITE, f"non-finite state at t = {hi[lane]:.17g}")
                else:
                    finish(lane, Status.NO_STOP, f"no stop before t_max = {t_max:g} / max_steps = "
                                                 f"{max_steps} (t = {hi[lane]:.6g}, steps = {steps[lane]})")
                reloaded = True
        if reloaded:
            ta.set_dtime(hi, lo)
    return dict(time=out_time, W=out_W, vmax=out_vmax, creep_time=out_creep,
                duration=out_time - out_creep, steps=out_steps,
                status=out_status, messages=messages)
