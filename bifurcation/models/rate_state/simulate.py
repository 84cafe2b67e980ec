"""``rate_state``: one run of the rate-and-state spring-slider under a load-point history.

The run goes segment by segment of the load history: the load-point velocity is a runtime parameter
set at the start of each segment, and ``propagate_until`` lands exactly on the step time, so a step
is never smoothed. Output times are evaluated on heyoka's dense output (the Taylor polynomial of the
step: same accuracy as the steps themselves). Events are recorded at their exact times.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import heyoka as hy
import numpy as np

from ...errors import InputError
from ...engine._exact import at_precision
from ._system import Slots, blowup_guard, compiled, parameters
from .spec import LoadHistory, SliderSpec, load_history

__all__ = ["DEFAULT_MAX_STEPS", "RateStateResult", "rate_state", "run_spec"]

#: Bound on the Taylor steps of one run (nothing hangs; status ``max-steps`` beyond).
DEFAULT_MAX_STEPS = 2_000_000
_PRECISIONS = ("double", "quad")


@dataclass(frozen=True)
class RateStateResult:
    """Time series at the requested output times, events, and a status.

    ``ln_v``, ``ln_theta`` (one row per state variable), ``mu`` and ``slip`` (δ − δ(t0)) are arrays in
    the run's precision (float64, or heyoka real128 for ``precision="quad"``). ``extrema`` rows are
    (t, ln V, +1 for a maximum / −1 for a minimum); ``crossings`` rows are (t, threshold index,
    +1 upward / −1 downward). ``status`` is ``ok``, ``max-steps``, ``unbounded`` (V blows up in
    finite time, e.g. quasi-static below k_c: the Taylor coefficients of ln V are about to overflow,
    ``_system.TAYLOR_BLOWUP``), ``stalled`` (the time step fell below the resolution of t first) or
    ``nonfinite``; on anything but
    ``ok`` the series hold NaN from the first time the run could not reach; ``meta["ln_v_stop"]`` is ln V
    where such a run stopped.
    """

    spec: SliderSpec
    history: LoadHistory
    t: np.ndarray
    ln_v: np.ndarray
    ln_theta: np.ndarray
    net_force: np.ndarray      # z = M V̇ (zeros when quasi-static)
    mu: np.ndarray
    slip: np.ndarray
    extrema: np.ndarray
    crossings: np.ndarray
    crossing_states: tuple     # (t, state (ln V, ln θ_i[, z])) per crossing, in the run's precision
    thresholds: tuple
    status: str
    message: str
    steps: int
    precision: str
    meta: dict = field(default_factory=dict)

    @property
    def v(self) -> np.ndarray:
        return np.exp(self.ln_v.astype(float))

    @property
    def theta(self) -> np.ndarray:
        return np.exp(self.ln_theta.astype(float))


def _times(t) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(t, dtype=float))
    if arr.ndim != 1 or arr.size == 0:
        raise InputError("t", t, "is empty", "give the output times, e.g. t=numpy.arange(41)")
    if not np.all(np.isfinite(arr)):
        raise InputError("t", t, "has a non-finite time", "give finite output times")
    if np.any(np.diff(arr) < 0):
        raise InputError("t", t, "is not sorted", "give output times in increasing order")
    return arr


def rate_state(*, a, b, dc, state_law, k, v_lp, t, mass=None, damping=0.0, mu0=0.6, v_ref=1.0, v0=None,
               theta0=None, thresholds=(), precision="double", max_steps=DEFAULT_MAX_STEPS,
               progress=None) -> RateStateResult:
    """Integrate the spring-slider with rate-and-state friction (docs/rate-state.md).

    μ = μ0 + a ln(V/V*) + Σ_i b_i ln(V* θ_i/(c_i Dc_i))  (c_i = 2 for PRZ, else 1);
    quasi-static k(δ_lp − δ) − ηV = μ (``mass=None``), or inertial M δ̈ = k(δ_lp − δ) − ηV − μ.

    Parameters
    ----------
    a, b, dc, state_law : the direct effect a > 0, and per state variable b_i ≥ 0, Dc_i > 0 and its law
        (``aging``/``dieterich``, ``slip``/``ruina``, ``prz``; one name for all). One or two variables.
    k : spring stiffness > 0.
    v_lp : a number, or a ``LoadHistory`` (``load_history([1, 10], at=[10])``).
    t : output times (sorted, from the history's start on).
    mass : M > 0 for the inertial slider.
    damping : radiation damping η ≥ 0 (friction per unit slip rate; QDYN's η/σ), 0 for none.
    v0, theta0 : initial V and θ_i (default: V0 = the first load-point velocity, θ_i at steady state).
    thresholds : slip velocities V_j whose crossings are recorded (slip events).
    precision : ``"double"``, or ``"quad"`` (heyoka real128, tolerance 1.9e-34) for verification.
    progress : optional ``progress(t, steps)``, called every 100 Taylor steps (the CLI's progress line).
    """
    spec = SliderSpec(a=a, b=b, dc=dc, state_law=state_law, k=k, mass=mass, mu0=mu0, v_ref=v_ref,
                      damping=damping)
    history = load_history(v_lp)
    return run_spec(spec, history, t, v0=v0, theta0=theta0, thresholds=thresholds,
                    precision=precision, max_steps=max_steps, progress=progress)


class _Progress:
    """A step callback: ``guard``'s verdict, and ``progress(t, steps)`` every ``EVERY`` steps (the caller
    decides how often to say it; a modulo per step costs nothing beside the guard's own Python call)."""

    EVERY = 100

    def __init__(self, guard, progress, t_start: float, steps: int) -> None:
        self.guard, self.progress, self.t_start, self.steps = guard, progress, t_start, steps

    def __call__(self, ta) -> bool:
        self.steps += 1
        if self.steps % self.EVERY == 0:
            self.progress(float(ta.time) + self.t_start, self.steps)
        return self.guard(ta)


def run_spec(spec: SliderSpec, history: LoadHistory, t, *, v0=None, theta0=None, z0=0.0, thresholds=(),
             precision="double", max_steps=DEFAULT_MAX_STEPS, ln_v0=None, ln_theta0=None,
             progress=None) -> RateStateResult:
    """``rate_state`` on validated specs; ``ln_v0``/``ln_theta0`` give the start in log variables exactly;
    ``progress(t, steps)``, if given, is called every ``_Progress.EVERY`` steps (a long run's progress)."""
    if precision not in _PRECISIONS:
        raise InputError("precision", precision, "is not a precision", "use 'double' or 'quad'")
    times = _times(t)
    if times[0] < history.times[0]:
        raise InputError("t", float(times[0]), f"is before the load history's start {history.times[0]:g}",
                         "give output times from the start of the history on")
    thresholds = tuple(float(v) for v in np.atleast_1d(np.asarray(thresholds, dtype=float)))
    if any(not (math.isfinite(v) and v > 0) for v in thresholds):
        raise InputError("thresholds", thresholds, "must be finite velocities > 0", "give slip velocities > 0")
    c = compiled(spec.state_law, spec.inertial, len(thresholds), precision, damped=spec.damped)
    dtype = c.dtype
    ta = c.integrator
    n = spec.n_states

    if ln_v0 is None:
        v_start = history.velocities[0] if v0 is None else v0
        if not (isinstance(v_start, (int, float)) and math.isfinite(v_start) and v_start > 0):
            raise InputError("v0", v_start, "must be a finite velocity > 0",
                             "give v0 > 0 (needed when the history starts with a hold)")
        # Logs taken in the run's precision: a double ln θ0 would cost real128 runs 1e-16 at the start,
        # and a decimal input (v_lp = "0.1") is read at that precision too (engine._exact).
        ln_v0 = np.log(at_precision(v_start, dtype))
        if theta0 is None and ln_theta0 is None:
            ln_theta0 = [np.log(dtype(law.steady_factor) * at_precision(d, dtype) / at_precision(v_start, dtype))
                         for law, d in zip(spec.laws, spec.dc)]
    if ln_theta0 is None:
        theta0 = list(np.atleast_1d(theta0))
        if len(theta0) != n or not all(math.isfinite(float(v)) and float(v) > 0 for v in theta0):
            raise InputError("theta0", theta0, f"must be {n} finite state value(s) > 0", "give θ0 > 0 per variable")
        ln_theta0 = [np.log(at_precision(v, dtype)) for v in theta0]

    # State and parameters, converted to the integrator's type from their decimal/double value once.
    state = [ln_v0, *ln_theta0] + ([z0] if spec.inertial else [])
    ta.state[:] = np.array([v if isinstance(v, dtype) else dtype(v) for v in state], dtype=dtype)
    ta.time = dtype(0)
    pars = parameters(spec, spec.k, history.velocities[0], [math.log(v) for v in thresholds])
    ta.pars[:] = np.array([at_precision(v, dtype) for v in pars], dtype=dtype)
    c.recorder.reset(dtype(0))
    c.recorder.x0 = float(ln_v0)

    out = np.full((times.size, ta.state.size), np.nan, dtype=dtype)
    status, message, steps = "ok", "", 0
    meta = {}
    bounds = list(history.times[1:]) + [math.inf]
    t_last = times[-1]
    for j, (v_seg, t_end) in enumerate(zip(history.velocities, bounds)):
        t_start = history.times[j]
        if t_start > t_last:
            break
        ta.pars[Slots.V_LP] = at_precision(v_seg, dtype)
        # Each segment runs in its own local time from 0: the step size and event times are then resolved
        # relative to the segment, not to an absolute t (a reload after a 1e12 hold would otherwise be
        # integrated with the 1e-4 granularity of t = 1e12).
        ta.time = dtype(0)
        c.recorder.offset = t_start
        c.recorder.first = j == 0
        stop = min(t_end, t_last)
        sel = (times >= t_start) & (times <= stop)
        if stop > t_start:
            # propagate_grid: the outputs from the dense output of each step (the same steps as without
            # outputs), landing exactly on the segment's end. (c_output=True costs ~12 ms per call.)
            inner = times[sel & (times > t_start)]
            grid = np.unique(np.concatenate([[t_start], inner, [stop]]))
            guard = blowup_guard(dtype)
            res = ta.propagate_grid((grid - t_start).astype(dtype), max_steps=max(max_steps - steps, 1),
                                    callback=guard if progress is None else _Progress(guard, progress, t_start,
                                                                                      steps))
            outcome, steps_j, values = res[0], res[3], np.asarray(res[-1])
            steps += steps_j
            rows = {float(g): values[i] for i, g in enumerate(grid) if i < values.shape[0]}
            if outcome != hy.taylor_outcome.time_limit:
                if outcome == hy.taylor_outcome.cb_stop:
                    status = "unbounded" if guard.reason == "blow-up" else "stalled"
                elif outcome == hy.taylor_outcome.err_nf_state:
                    status = "nonfinite"
                elif steps < max_steps:
                    # The step fell below the resolution of t: V blowing up in finite time (the
                    # quasi-static slider below k_c) or collapsing.
                    status = "stalled"
                else:
                    status = "max-steps"
                reached = float(ta.time) + t_start
                meta["ln_v_stop"] = float(ta.state[0])     # ln V where the run ended early
                message = (f"{status} at t = {reached:.17g} after {steps} steps "
                           f"(segment {j}, V_lp = {v_seg:g})")
                if status == "unbounded":
                    message += f": V blows up in finite time (ln V = {float(ta.state[0]):.4g} and rising)"
                elif status == "stalled":   # where: a stall at large V is a blow-up the guard missed, at small V not
                    message += f" at ln V = {meta['ln_v_stop']:.4g}"
                for i in np.flatnonzero(sel):
                    if times[i] < reached and float(times[i]) in rows:
                        out[i] = rows[float(times[i])]
                break
            for i in np.flatnonzero(sel):
                out[i] = rows[float(times[i])]
        else:
            out[sel] = ta.state
    # An output time at a step lands on the next segment's start: equal by continuity of the state.
    return _result(spec, history, times, out, c, thresholds, status, message, steps, precision, meta)


def _result(spec, history, times, out, c, thresholds, status, message, steps, precision, meta=None) -> RateStateResult:
    n = spec.n_states
    ln_v = out[:, 0]
    ln_theta = out[:, 1:1 + n].T.copy()
    z = out[:, 1 + n] if spec.inertial else np.zeros_like(ln_v)
    mu = spec.mu(ln_v, ln_theta, log=_log_for(c.dtype), num=c.dtype)
    spring = mu + z   # k(δ_lp − δ) = μ + z + ηV
    if spec.damped:
        spring = spring + at_precision(spec.damping, c.dtype) * np.exp(ln_v)
    spring = spring / at_precision(spec.k, c.dtype)
    if c.dtype is np.float64:
        dlp = np.array([history.displacement(float(s)) for s in times]).astype(c.dtype)
    else:   # real128: the load point's displacement and k from the decimals too, or slip is double-accurate
        dlp = np.array([history.displacement(float(s), c.dtype) for s in times], dtype=c.dtype)
    slip = (dlp - dlp[0]) - (spring - spring[0])
    ext = np.array(c.recorder.extrema, dtype=float).reshape(-1, 3)
    cro = np.array(c.recorder.crossings, dtype=float).reshape(-1, 3)
    return RateStateResult(spec, history, times, ln_v, ln_theta, z, mu, slip,
                           ext, cro, tuple(c.recorder.crossing_states), thresholds, status, message, steps, precision,
                           dict(meta or {}))


def _log_for(dtype):
    if dtype is np.float64:
        return math.log

    def log(v):
        return np.log(np.asarray(v, dtype=dtype))
    return log
