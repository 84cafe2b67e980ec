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
from ._integrator import Compiled, EventKind, compiled
from ._validate import check_batch, check_nu, check_nu_f, check_precision, check_work
from .result import DEFAULT_MAX_STEPS, DEFAULT_T_MAX, SlipResult, Status

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_T_MAX", "run_cycle", "slip"]

_NONFINITE = hy.taylor_outcome.err_nf_state
_STOP, _MAX_VELOCITY, _REACH_NU_F, _RUNG = (EventKind.STOP, EventKind.MAX_VELOCITY, EventKind.REACH_NU_F,
                                            EventKind.RUNG)


def run_cycle(c: Compiled, nu, nu_f, *, forcing: float = 1.0, state0=(0.0, 0.0),
              t_max: float = DEFAULT_T_MAX, max_steps: int = DEFAULT_MAX_STEPS) -> dict:
    """Integrate one cycle with the compiled integrator ``c``; returns a dict of raw outcomes.

    ``forcing = 1`` is a finite-ν cycle in the scaled variables; ``forcing = 0`` with ``nu = 1`` is
    the ν = 0 flow (the direct limit). Times and positions are returned in the integrator's
    precision (numpy scalars). This loop runs once per event of every point: it keeps Python work
    per event to a few integer comparisons.
    """
    ta = c.integrator
    dtype = c.dtype
    ta.time = dtype(0)
    state = ta.state  # views on the integrator's buffers
    pars = ta.pars
    state[0], state[1] = state0
    # A terminal event's cooldown outlives a reset of time and state: clear it, or a point would
    # depend on the one before it.
    ta.reset_cooldowns()
    pars[0], pars[1], pars[2] = nu, nu_f, forcing
    piece = 0  # both starts (rest at x = 0, the manifold at x < first breakpoint) are on piece 0
    if c.n_pieces > 1:
        pars[3:] = 0
        pars[3] = 1
    kinds, breakpoint_of, at_one = c.kinds, c.breakpoint_of, c.switch_at_one
    n_events = len(kinds)
    propagate = ta.propagate_until
    t_end = dtype(t_max)
    creep_time = math.nan
    crossings = []  # times U̇ crosses ν_f (x = 1) after t1, for τ1 of Eq. (16)
    vmax = state[1]
    steps = 0
    status = Status.NO_STOP
    message = ""
    while True:
        outcome, _, _, n, *_ = propagate(t_end, max_steps=max(max_steps - steps, 1))
        steps += n
        index = -int(outcome) - 1  # terminal event i comes back as the outcome −(i + 1)
        if not 0 <= index < n_events:  # time or step limit, or a non-finite state
            if outcome == _NONFINITE:
                status, message = Status.NONFINITE, f"non-finite state at t = {float(ta.time):.17g}"
            else:
                message = (f"no stop before t_max = {t_max:g} / max_steps = {max_steps} "
                           f"(t = {float(ta.time):.6g}, steps = {steps})")
            break
        kind = kinds[index]
        if kind is _STOP:
            status = Status.STICK_SLIP
            break
        if kind is _MAX_VELOCITY:
            if state[1] > vmax:
                vmax = state[1]
        elif kind is _REACH_NU_F:
            if creep_time != creep_time:  # NaN: the first time only
                creep_time = ta.time
        elif kind is _RUNG:  # the step ended on a rung of the ladder; nothing to record
            pass
        else:  # a switch at breakpoint j: the upper end of this piece means up, the lower means down
            j = breakpoint_of[index]
            up = j == piece
            if not up and j != piece - 1:  # cannot happen with ordered breakpoints; be explicit
                status, message = Status.NONFINITE, f"switch event {j} seen in piece {piece}"
                break
            pars[3 + piece] = 0
            piece = piece + 1 if up else piece - 1
            pars[3 + piece] = 1
            if j == at_one:
                if up and creep_time != creep_time:
                    creep_time = ta.time
                else:
                    crossings.append(ta.time)
    return dict(time=ta.time, W=state[0], vmax=vmax, creep_time=creep_time,
                crossings=crossings, steps=steps, status=status, message=message)


def _scalar_points(c: Compiled, nu: np.ndarray, nu_f: np.ndarray, t_max: float, max_steps: int) -> dict:
    """Raw outcomes for flat arrays of points, one scalar integration each."""
    dtype = c.dtype
    keys = ("time", "W", "vmax", "creep_time")
    out = {k: np.full(nu.size, math.nan) for k in (*keys, "duration")}
    out["steps"] = np.zeros(nu.size, dtype=np.int64)
    out["status"] = np.zeros(nu.size, dtype=np.int8)
    messages = {}
    for i in range(nu.size):
        raw = run_cycle(c, dtype(nu[i]), dtype(nu_f[i]), t_max=t_max, max_steps=max_steps)
        for k in keys:
            out[k][i] = float(raw[k])
        # Subtract before rounding to float64 (quad keeps the difference exact to ~1e-33).
        out["duration"][i] = float(raw["time"] - raw["creep_time"])
        out["steps"][i], out["status"][i] = raw["steps"], int(raw["status"])
        if raw["message"]:
            messages[i] = raw["message"]
    out["messages"] = messages
    return out


def _unresolved(status: np.ndarray, messages: dict, x_max: np.ndarray, x_checked: float) -> np.ndarray:
    """Mark stopped points whose U̇/ν_f went past the ladder's checked range (docs/engine.md)."""
    beyond = (status == int(Status.STICK_SLIP)) & (x_max > x_checked)
    for i in np.flatnonzero(beyond):
        status[i] = int(Status.UNRESOLVED)
        messages[int(i)] = (f"U̇/ν_f reached {x_max[i]:.3g}, beyond x = {x_checked:.3g} up to which the engine "
                            "checked that no Taylor step can step over this law's friction; use a larger ν_f")
    return beyond


def _classify(raw: dict, nu: np.ndarray, nu_f: np.ndarray,
              x_checked: float = math.inf) -> tuple[dict, dict]:
    """Result fields from raw outcomes: creep vs stick-slip, the stick check, NaN where undefined."""
    status = raw["status"].copy()
    messages = dict(raw["messages"])
    _unresolved(status, messages, nu * raw["vmax"] / nu_f, x_checked)
    stopped = status == int(Status.STICK_SLIP)
    creep = stopped & (nu_f > 0.5) & np.isnan(raw["creep_time"])
    status[creep] = int(Status.CREEP)
    # Static friction holds |spring force| = |1 + ν(t − W)| ≤ 1 after the stop; else it back-slips.
    back = stopped & (nu * (raw["W"] - raw["time"]) > 2)
    for i in np.flatnonzero(back):
        status[i] = int(Status.NO_STICK)
        messages[int(i)] = (f"spring force {1 + nu[i] * (raw['time'][i] - raw['W'][i]):.6g} exceeds "
                            "static friction after the stop: the block would slide back")
    # stick-slip, creep and no-stick all stopped: the cycle itself is well defined
    W = np.where(stopped, raw["W"], math.nan)
    fields = {
        "delta": nu * W,
        "period": W,
        "creep_time": np.where(stopped, raw["creep_time"], math.nan),
        "slip_duration": np.where(stopped, raw["duration"], math.nan),
        "stop_time": np.where(stopped, raw["time"], math.nan),
        "max_velocity": np.where(stopped, nu * raw["vmax"], math.nan),
        "steps": raw["steps"],
        "status": status,
    }
    return fields, messages


def slip(law: str | FrictionLaw, *, nu, nu_f, precision: str = "double",
         t_max: float = DEFAULT_T_MAX, max_steps: int = DEFAULT_MAX_STEPS, batch: int = 1) -> SlipResult:
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
    batch : int
        Lanes of heyoka's batch (SIMD) integrator (double only); 1 integrates point by point. Results
        of a batch run do not depend on the batch size or the order of points, and agree with the
        scalar run to rounding (≤ 3e-15 seen), not bit for bit (SIMD code differs). A terminal event
        in any lane returns control for all lanes, so batching pays for laws with one piece (~1.5×
        for Carlson–Langer) and not for piecewise laws, whose switches are terminal (see
        ``bifurcation bench``). The scalar run is the default.

    Returns
    -------
    SlipResult
        ``delta`` Δ, ``period`` T = Δ/ν, ``creep_time`` t1 (first time U̇ = ν_f; NaN where U̇ never
        reaches ν_f), ``slip_duration`` (stop − t1; NaN where t1 is), ``stop_time`` (start to stop;
        Eq. 9's t0 in creep), ``max_velocity``, ``steps``, ``status``.
    """
    law = resolve_law(law)
    check_precision(precision)
    check_work(t_max, max_steps)
    nu_b, nu_f_b = np.broadcast_arrays(check_nu(nu), check_nu_f(nu_f))
    batch = check_batch(batch, precision)
    shape = nu_b.shape
    nu_flat = np.ascontiguousarray(nu_b, dtype=float).ravel()
    nu_f_flat = np.ascontiguousarray(nu_f_b, dtype=float).ravel()
    c = compiled(law, precision, batch)
    if batch > 1:
        from ._batch import run_batch

        raw = run_batch(c, nu_flat, nu_f_flat, t_max=t_max, max_steps=max_steps)
    else:
        raw = _scalar_points(c, nu_flat, nu_f_flat, t_max, max_steps)
    fields, messages = _classify(raw, nu_flat, nu_f_flat, c.x_checked)
    return SlipResult(nu=nu_flat.reshape(shape), nu_f=nu_f_flat.reshape(shape),
                      **{k: v.reshape(shape) for k, v in fields.items()},
                      messages=messages, law=law.name, precision=precision)
