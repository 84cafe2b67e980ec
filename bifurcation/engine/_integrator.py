"""One compiled Taylor integrator per (law, precision), reused for every (ν, ν_f).

Scaled equations (PHYSICS.md): with U = νW,

    Ẅ = c·t − W + Σ_k s_k g_k(x)/ν,   x = νẆ/ν_f,

where g_k = 1 − Φ on piece k of the law and s_k is a one-hot runtime parameter that selects the piece
(flipped at a terminal event, so a kink is crossed exactly and never smoothed; the sum is taken with
``select`` on the parameter, so an unselected piece never enters). c = 1 for a finite-ν
cycle; c = 0 with ν = 1 turns the same integrator into the ν = 0 flow Ü = −U + g(U̇/ν_f) used by the
direct limit. Runtime parameters: par[0] = ν, par[1] = ν_f, par[2] = c, par[3 + k] = s_k.

ν_f enters by division, never through a precomputed 1/ν_f or ν/ν_f: just above ν_f = 1/2 the creep
cycle is ill-conditioned in ν_f (Δ ~ e^{αt0}, t0 ≈ 2π/ω, so d ln Δ/d ln α ≈ 2πα³/ω³ ≈ 700 at
ν_f = 0.51) and the one systematic rounding of such a constant cost 4e-14 in Δ; roundings made per
evaluation do not add up that way.

Every event function is O(1) in the scaled variables while the block slips (PHYSICS.md: a switching
function of size 1e12 spoils the location of other events).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import heyoka as hy
import numpy as np

from ..laws import FrictionLaw
from ._fading import ladder

__all__ = ["Compiled", "EventKind", "LaneRecorder", "build", "compiled", "fp_info"]

_CACHE: dict = {}

#: Cooldown of the terminal events. heyoka's automatic one scales with the error estimate of the event
#: equation, which follows the state: at ν ≤ 3e-17 (W ~ 1e17) it outlasted the two time units between
#: the up- and down-crossings of the kink of Eq. (12), the second switch was missed and Δ came out 0.6 %
#: wrong. 1e-12 is far above the restart offset (a few ulps of t ≲ 1e3) and far below the shortest
#: time between events (~ln 2/(2α) ≈ 7e-5 at ν_f = 1e-4).
COOLDOWN = 1e-12


class EventKind(Enum):
    STOP = "stop"            # U̇ returns to 0: terminal for the cycle
    MAX_VELOCITY = "max"     # dU̇/dt = 0 from above: a velocity maximum
    REACH_NU_F = "creep"     # U̇ = ν_f from below (t1), where 1 is not a breakpoint
    SWITCH = "switch"        # U̇/ν_f crosses a breakpoint of the law
    RUNG = "rung"            # U̇/ν_f falls through a rung of the law's ladder (_fading): ends a step only


@dataclass(frozen=True)
class Compiled:
    """A compiled integrator and the meaning of its terminal events."""

    law: FrictionLaw
    precision: str
    integrator: object
    kinds: tuple            # EventKind per terminal event index
    breakpoint_of: tuple    # breakpoint index per event (-1 where not a switch)
    n_pieces: int
    batch_size: int
    recorder: "LaneRecorder | None" = None  # batch mode: where non-terminal events record
    dtype: type = np.float64                # numpy type of the integrator's numbers
    switch_at_one: int = -1                 # index of the breakpoint x = 1 (U̇ = ν_f), -1 if none
    x_checked: float = float("inf")         # the ladder vouches for x = U̇/ν_f up to here (_fading)


def fp_info(precision: str):
    """(heyoka fp_type or None for double, numpy dtype, constant maker) for a precision name."""
    if precision == "double":
        return None, np.float64, lambda v: hy.expression(float(v))
    if precision == "quad":
        return hy.real128, hy.real128, lambda v: hy.expression(hy.real128(str(v)))
    raise ValueError(precision)


def _system(law: FrictionLaw, num):
    W, V = hy.make_vars("W", "V")
    nu, nu_f, c = hy.par[0], hy.par[1], hy.par[2]
    x = (nu * V) / nu_f
    pieces = law.pieces
    if len(pieces) == 1:
        drop = pieces[0].drop(x, num)
    else:
        # select on the one-hot parameter, not a product with it: a piece may be NaN outside its own
        # interval (log(x) at x = 0, say) and 0·NaN is NaN. The condition is constant over every step,
        # so this is no state-dependent switch and weakens no event guarantee.
        drop = hy.select(hy.par[3 + len(pieces) - 1], pieces[-1].drop(x, num), num(0))
        for k in range(len(pieces) - 2, -1, -1):
            drop = hy.select(hy.par[3 + k], pieces[k].drop(x, num), drop)
    rhs = c * hy.time - W + drop / nu
    # dx/dt = νẄ/ν_f, written without the 1/ν so that it stays O(1) during the slip.
    dxdt = (nu * (c * hy.time - W) + drop) / nu_f
    return (W, V), rhs, x, dxdt


class LaneRecorder:
    """Velocity maxima and t1 of each batch lane, recorded by non-terminal event callbacks.

    In batch mode a terminal event in any lane returns control for all lanes, so only the events
    that change the integration (the stop, the piece switches) are terminal; the others are recorded
    here at the exact event time from heyoka's dense output, without leaving the integrator.
    """

    def __init__(self, lanes: int) -> None:
        self.vmax = np.zeros(lanes)
        self.creep = np.full(lanes, np.nan)

    def __deepcopy__(self, memo) -> "LaneRecorder":
        # heyoka deep-copies each event callback on construction; all of them must record here.
        return self

    def on_max_velocity(self, ta, time, d_sgn, lane) -> None:
        times = np.array(ta.time)
        times[lane] = time
        ta.update_d_output(times)
        self.vmax[lane] = max(self.vmax[lane], ta.d_output[1, lane])

    def on_reach_nu_f(self, ta, time, d_sgn, lane) -> None:
        if np.isnan(self.creep[lane]):
            self.creep[lane] = time


def _events(law: FrictionLaw, x, dxdt, fp_type, recorder: LaneRecorder | None, rungs=()):
    """Terminal events (with their kinds and breakpoint indices) and non-terminal events."""
    batch = recorder is not None
    make = hy.t_event_batch if batch else hy.t_event
    fp = {"fp_type": fp_type} if fp_type is not None else {}

    cooldown = fp_type(COOLDOWN) if fp_type is not None else COOLDOWN

    def ev(eq, direction):
        return make(eq, direction=direction, cooldown=cooldown, **fp)

    neg, pos, anyd = (hy.event_direction.negative, hy.event_direction.positive, hy.event_direction.any)
    events, kinds, bp_of, nt_events = [ev(x, direction=neg)], [EventKind.STOP], [-1], []
    if batch:
        nt_events.append(hy.nt_event_batch(dxdt, recorder.on_max_velocity, direction=neg))
    else:
        events.append(ev(dxdt, direction=neg))
        kinds.append(EventKind.MAX_VELOCITY)
        bp_of.append(-1)
    if 1.0 not in law.breakpoints:
        if batch:
            nt_events.append(hy.nt_event_batch(x - 1.0, recorder.on_reach_nu_f, direction=pos))
        else:
            events.append(ev(x - 1.0, direction=pos))
            kinds.append(EventKind.REACH_NU_F)
            bp_of.append(-1)
    for j, b in enumerate(law.breakpoints):
        events.append(ev(x / b - 1.0, direction=anyd))
        kinds.append(EventKind.SWITCH)
        bp_of.append(j)
    # Terminal in batch mode too: a non-terminal event cannot end a step, and ending the step of the
    # lane that crosses a rung is the whole point (docs/engine.md, "Friction that fades").
    for r in rungs:
        events.append(ev(x / r - 1.0, direction=neg))
        kinds.append(EventKind.RUNG)
        bp_of.append(-1)
    return events, tuple(kinds), tuple(bp_of), nt_events


def compiled(law: FrictionLaw, precision: str = "double", batch_size: int = 1) -> Compiled:
    """The cached compiled integrator for ``law`` (built on first use in this process)."""
    key = (law.name, law.formula, precision, batch_size)
    hit = _CACHE.get(key)
    if hit is None:
        hit = _CACHE[key] = build(law, precision, batch_size)
    return hit


def build(law: FrictionLaw, precision: str = "double", batch_size: int = 1) -> Compiled:
    """Compile a new integrator for ``law`` (uncached; the benchmark's naive baseline uses this)."""
    fp_type, dtype, num = fp_info(precision)
    (W, V), rhs, x, dxdt = _system(law, num)
    batch = batch_size > 1
    recorder = LaneRecorder(batch_size) if batch else None
    steps = ladder(law, precision)
    events, kinds, bp_of, nt_events = _events(law, x, dxdt, fp_type, recorder, steps.rungs)
    npars = 3 + (len(law.pieces) if len(law.pieces) > 1 else 0)
    kwargs = dict(t_events=events, nt_events=nt_events, compact_mode=precision == "quad")
    if fp_type is not None:
        kwargs["fp_type"] = fp_type
    if batch:
        ta = hy.taylor_adaptive_batch([(W, V), (V, rhs)], np.zeros((2, batch_size)),
                                      pars=np.zeros((npars, batch_size)), **kwargs)
    else:
        ta = hy.taylor_adaptive([(W, V), (V, rhs)], np.zeros(2, dtype=dtype),
                                pars=np.zeros(npars, dtype=dtype), **kwargs)
    at_one = law.breakpoints.index(1.0) if 1.0 in law.breakpoints else -1
    return Compiled(law, precision, ta, kinds, bp_of, len(law.pieces), batch_size, recorder, dtype, at_one,
                    steps.x_checked)
