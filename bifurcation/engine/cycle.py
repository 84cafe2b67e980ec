"""One slip cycle: from rest at the static threshold to the stop.

The block starts at U = U̇ = 0 when the spring force has just reached the threshold (Ü(0) = 0), slides
while U̇ > 0 and stops the first time U̇ returns to 0 (PHYSICS.md). Over one period rod and block
advance by the same amount, so the recurrence time is exactly T = Δ/ν; in the scaled variable
W = U/ν this is T = W(stop), with no division. The stuck phase is never integrated.
"""

from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from ..laws import FrictionLaw, resolve_law
from ._integrator import Compiled, EventKind, compiled, fp_info
from ._validate import check_nu, check_nu_f, check_precision
from .result import SlipResult, Status

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_T_MAX", "run_cycle", "slip"]

#: Bound on the time of one cycle. The longest legitimate cycles are the creep oscillations just above
#: ν_f = 1/2 (t0 ~ 2π/ω of Eq. 9) and the creep time t1 ~ (α − ω) ln(1/ν) ≤ 40; both are far below this.
DEFAULT_T_MAX = 1.0e5
#: Bound on the Taylor steps of one cycle (a few hundred are typical).
DEFAULT_MAX_STEPS = 200_000

_TIME_LIMIT = hy.taylor_outcome.time_limit
_STEP_LIMIT = hy.taylor_outcome.step_limit
_NONFINITE = hy.taylor_outcome.err_nf_state


def _set_piece(pars, piece: int, n_pieces: int) -> None:
    if n_pieces > 1:
        pars[3:3 + n_pieces] = 0
        pars[3 + piece] = 1


def run_cycle(c: Compiled, nu, nu_f, *, forcing: float = 1.0, state0=(0.0, 0.0), piece: int = 0,
              t_max: float = DEFAULT_T_MAX, max_steps: int = DEFAULT_MAX_STEPS) -> dict:
    """Integrate one cycle with the compiled integrator ``c``; returns a dict of raw outcomes.

    ``forcing = 1`` is a finite-ν cycle in the scaled variables; ``forcing = 0`` with ``nu = 1`` is
    the ν = 0 flow (the direct limit). Times and positions are returned in the integrator's
    precision (numpy scalars).
    """
    ta = c.integrator
    _, dtype, _ = fp_info(c.precision)
    ta.time = dtype(0)
    ta.state[:] = state0
    pars = ta.pars
    pars[0], pars[1], pars[2] = nu, nu_f, forcing
    _set_piece(pars, piece, c.n_pieces)
    breakpoints = c.law.breakpoints
    creep_time = math.nan
    crossings = []  # times U̇ crosses ν_f (x = 1) after t1, for τ1 of Eq. (16)
    vmax = ta.state[1]
    steps = 0
    status = Status.NO_STOP
    message = ""
    while True:
        outcome, _, _, n, *_ = ta.propagate_until(dtype(t_max), max_steps=max(max_steps - steps, 1))
        steps += n
        code = int(outcome)
        if code >= 0 or outcome in (_TIME_LIMIT, _STEP_LIMIT, _NONFINITE):
            if outcome == _NONFINITE:
                status, message = Status.NONFINITE, f"non-finite state at t = {float(ta.time):.17g}"
            else:
                status = Status.NO_STOP
                message = (f"no stop before t_max = {t_max:g} / max_steps = {max_steps} "
                           f"(t = {float(ta.time):.6g}, steps = {steps})")
            break
        index = -code - 1
        kind = c.kinds[index]
        if kind is EventKind.STOP:
            status = Status.STICK_SLIP
            break
        if kind is EventKind.MAX_VELOCITY:
            vmax = max(vmax, ta.state[1])
        elif kind is EventKind.REACH_NU_F:
            if math.isnan(creep_time):
                creep_time = ta.time
        else:  # a switch at breakpoint j: the upper end of this piece means up, the lower means down
            j = c.breakpoint_of[index]
            up = j == piece
            if not up and j != piece - 1:  # cannot happen with ordered breakpoints; be explicit
                status, message = Status.NONFINITE, f"switch event {j} seen in piece {piece}"
                break
            piece = piece + 1 if up else piece - 1
            _set_piece(pars, piece, c.n_pieces)
            if breakpoints[j] == 1.0:
                if up and math.isnan(creep_time):
                    creep_time = ta.time
                else:
                    crossings.append(ta.time)
    return dict(time=ta.time, W=ta.state[0], V=ta.state[1], vmax=vmax, creep_time=creep_time,
                crossings=crossings, steps=steps, status=status, message=message)


def _finite_nu_point(c: Compiled, nu: float, nu_f: float, t_max: float, max_steps: int):
    _, dtype, _ = fp_info(c.precision)
    nu_q = dtype(nu)
    raw = run_cycle(c, nu_q, dtype(nu_f), t_max=t_max, max_steps=max_steps)
    status, message = raw["status"], raw["message"]
    t_stop, W = raw["time"], raw["W"]
    delta = nu_q * W
    if status is Status.STICK_SLIP and nu_f > 0.5 and math.isnan(raw["creep_time"]):
        status = Status.CREEP
    if status in (Status.STICK_SLIP, Status.CREEP):
        # Static friction holds |spring force| = |1 + ν(t − W)| ≤ 1 after the stop; else it back-slips.
        if nu_q * (W - t_stop) > 2:
            status = Status.NO_STICK
            message = (f"spring force {float(1 + nu_q * (t_stop - W)):.6g} exceeds static friction "
                       "after the stop: the block would slide back")
    else:
        delta = W = dtype(math.nan)
    creep_time = raw["creep_time"]
    slip_duration = t_stop - creep_time if not math.isnan(creep_time) else math.nan
    return (float(delta), float(W), float(creep_time), float(slip_duration),
            float(t_stop) if status != Status.NO_STOP else math.nan,
            float(nu_q * raw["vmax"]) if status != Status.NO_STOP else math.nan,
            raw["steps"], status, message)


def slip(law: str | FrictionLaw, *, nu, nu_f, precision: str = "double",
         t_max: float = DEFAULT_T_MAX, max_steps: int = DEFAULT_MAX_STEPS) -> SlipResult:
    """One slip cycle for every (ν, ν_f) of the broadcast of ``nu`` and ``nu_f``.

    Parameters
    ----------
    law : str or FrictionLaw
        A name of ``bifurcation.law_names()`` or a formula in x (see ``bifurcation.laws``).
    nu, nu_f : array_like
        Pulling speed ν > 0 and friction velocity ν_f > 0 (Eq. 5), broadcast against each other.
    precision : {"double", "quad"}
        ``"quad"`` integrates in heyoka real128 (verification; results are rounded to float64).
    t_max, max_steps : float, int
        Bounds after which a point that has not stopped gets status ``no-stop``.

    Returns
    -------
    SlipResult
        ``delta`` Δ, ``period`` T = Δ/ν, ``creep_time`` t1 (first time U̇ = ν_f; NaN where U̇ never
        reaches ν_f, i.e. in creep), ``slip_duration`` (stop − t1; NaN in creep), ``stop_time``
        (start to stop; Eq. 9's t0 in creep), ``max_velocity``, ``steps``, ``status``.
    """
    law = resolve_law(law)
    check_precision(precision)
    nu_b, nu_f_b = np.broadcast_arrays(check_nu(nu), check_nu_f(nu_f))
    c = compiled(law, precision)
    shape = nu_b.shape
    floats = np.full((6,) + shape, np.nan)
    steps = np.zeros(shape, dtype=np.int64)
    status = np.zeros(shape, dtype=np.int8)
    messages = {}
    for i, idx in enumerate(np.ndindex(shape)):
        *vals, n, st, msg = _finite_nu_point(c, float(nu_b[idx]), float(nu_f_b[idx]), t_max, max_steps)
        floats[(slice(None),) + idx] = vals
        steps[idx], status[idx] = n, int(st)
        if msg:
            messages[i] = msg
    delta, period, creep_time, slip_duration, stop_time, max_velocity = floats
    return SlipResult(nu=np.array(nu_b, dtype=float), nu_f=np.array(nu_f_b, dtype=float), delta=delta,
                      period=period, creep_time=creep_time, slip_duration=slip_duration,
                      stop_time=stop_time, max_velocity=max_velocity, steps=steps, status=status,
                      messages=messages, law=law.name, precision=precision)
