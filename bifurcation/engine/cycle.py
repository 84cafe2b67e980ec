"""The event loop: one run of a model at one point, from its initial state to its ``end`` event.

For the single block (docs/physics.md, ``bifurcation.models.single_block``) a run is one slip cycle:
the block starts at U = U̇ = 0 when the spring force has just reached the threshold (Ü(0) = 0), slides
while U̇ > 0 and stops the first time U̇ returns to 0. Over one period rod and block advance by the
same amount, so the recurrence time is exactly T = Δ/ν; in the scaled variable W = U/ν this is
T = W(stop), with no division. The stuck phase is never integrated.
"""

from __future__ import annotations

import math

import heyoka as hy
import numpy as np

from ..laws import FrictionLaw, resolve_law
from ..models.single_block import SINGLE_BLOCK
from ._actions import Run, act, limit
from ._integrator import Compiled, compiled
from ._validate import check_batch, check_nu, check_nu_f, check_precision, check_work
from .result import DEFAULT_MAX_STEPS, DEFAULT_T_MAX, SlipResult

__all__ = ["AUTO_BATCH_MIN_POINTS", "DEFAULT_MAX_STEPS", "DEFAULT_T_MAX", "auto_batch", "batch_lanes", "batch_order",
           "run_cycle",
           "run_model", "slip"]

#: ``slip``'s default batches from this many points on (``auto_batch``). Measured (CPU time per point,
#: this machine, after the first call): at 16 points a batch of 8 is 1.1-1.8x faster than the scalar
#: loop for Carlson-Langer, piecewise-linear and exp(-x); at 4 points it is slower for piecewise-linear.
AUTO_BATCH_MIN_POINTS = 16


def run_cycle(c: Compiled, values, *, state0=None, t_max: float = DEFAULT_T_MAX,
              max_steps: int = DEFAULT_MAX_STEPS) -> dict:
    """Integrate one run with the compiled integrator ``c``; returns a dict of raw outcomes.

    ``values`` maps each runtime slot of the model (``c.slots.names``) to its value here (for the
    single block: ``nu``, ``nu_f``, ``forcing``; ``forcing = 0`` with ``nu = 1`` is the ν = 0 flow of
    the direct limit), or is the sequence of those values in slot order. ``state0`` defaults to the model's initial state. Times, the final state (by
    name) and the records are returned in the integrator's precision (numpy scalars). This loop runs
    once per event of every point: it keeps Python work per event to a few integer comparisons.
    """
    if isinstance(values, dict):
        values = [values[name] for name in c.slots.names]
    time, state, found, maxima, crossings, steps, status, message = _run(c, values, state0, t_max, max_steps)
    out = dict(zip(c.state_names, state))
    out.update(found)
    out.update(maxima)
    out.update(time=time, crossings=crossings, steps=steps, status=status, message=message, info=c.info)
    return out


def _run(c: Compiled, values, state0, t_max: float, max_steps: int, run: Run | None = None) -> tuple:
    """``run_cycle`` without the dict: (time, state, first records, maxima, crossings, steps, status,
    message), all in its precision, ``state`` the integrator's own buffer (read it before the next run).
    ``values`` in slot order. ``run``: the ``Run`` of ``_runner(c)`` to reuse (a loop over points
    makes one: ~1 µs per point of a ~30 µs run)."""
    ta = c.integrator
    dtype = c.dtype
    ta.time = dtype(0)
    state = ta.state  # views on the integrator's buffers
    pars = ta.pars
    start = c.initial if state0 is None else state0
    for i, value in enumerate(start):
        state[i] = value
    # A terminal event's cooldown outlives a reset of time and state: clear it, or a point would
    # depend on the one before it.
    ta.reset_cooldowns()
    for i, value in enumerate(values):   # the slots in order: parameters[0], parameters[1], ...
        pars[i] = value
    if run is None:
        run = _runner(c)
    run.found = dict.fromkeys(c.first_records, math.nan)
    # a running maximum starts at the start's value (the initial state of the model, or state0)
    run.maxima = dict(c.max_start) if state0 is None else {name: start[index] for name, index in c.max_records}
    run.start(c)   # crossings: later crossings of the breakpoint that carries a "first" record (τ1 of Eq. 16)
    n_events = len(c.kinds)
    propagate = ta.propagate_until
    t_end = dtype(t_max)
    steps = 0
    while True:
        outcome, _, _, n, *_ = propagate(t_end, max_steps=max(max_steps - steps, 1))
        steps += n
        index = -int(outcome) - 1  # terminal event i comes back as the outcome −(i + 1)
        if not 0 <= index < n_events:  # time or step limit, or a non-finite state
            status, message = limit(outcome, ta.time, steps, t_max, max_steps)
            break
        status = act(c, index, run)
        if status is not None:
            message = run.message
            break
    return ta.time, state, run.found, run.maxima, run.crossings, steps, status, message   # state: the live view


def _runner(c: Compiled) -> Run:
    """The event actions' view of a run on the scalar integrator of ``c``."""
    ta = c.integrator
    return Run(ta.pars, ta.state, None, None, lambda: ta.time)


def _scalar_points(c: Compiled, values: dict, size: int, t_max: float, max_steps: int, exact=None) -> dict:
    """Raw outcomes for flat arrays of runtime values, one scalar integration each.

    Besides the final state, the records, ``steps`` and ``status``, each "first" record ``r`` gives
    ``time_after_<r>`` = end time − r, subtracted in the integrator's precision before rounding to
    float64 (quad keeps the difference exact to ~1e-33).
    """
    dtype = c.dtype
    names, firsts, maxima = c.state_names, c.first_records, [n for n, _ in c.max_records]
    out = {k: np.full(size, math.nan) for k in ("time", *names, *firsts, *maxima)}
    for r in firsts:
        out[f"time_after_{r}"] = np.full(size, math.nan)
    out["steps"] = np.zeros(size, dtype=np.int64)
    out["status"] = np.zeros(size, dtype=np.int8)
    messages = {}
    time_out, steps_out, status_out = out["time"], out["steps"], out["status"]
    state_out = [out[n] for n in names]
    first_out = [(r, out[r], out[f"time_after_{r}"]) for r in firsts]
    max_out = [(n, out[n]) for n in maxima]
    # one row of slot values per point, in the integrator's precision (float64 → real128 is exact)
    rows = [[dtype(v) for v in row] for row in zip(*(values[name] for name in c.slots.names))]
    for k, name in enumerate(c.slots.names):   # a decimal given as text, read at the run's precision
        given = (exact or {}).get(name)
        if given is not None and dtype is not np.float64:
            from ._exact import at_precision

            for i in range(size):
                if float(given[i]) == float(values[name][i]):   # the slot takes the axis value as it is
                    rows[i][k] = at_precision(given[i], dtype)
    run = _runner(c)
    for i in range(size):
        time, state, found, peaks, _, steps, status, message = _run(c, rows[i], None, t_max, max_steps, run)
        time_out[i] = float(time)
        for column, value in zip(state_out, state):
            column[i] = float(value)
        for r, column, after in first_out:
            column[i] = float(found[r])
            after[i] = float(time - found[r])
        for n, column in max_out:
            column[i] = float(peaks[n])
        steps_out[i], status_out[i] = steps, int(status)
        if message:
            messages[i] = message
    out["messages"] = messages
    out["info"] = c.info
    return out


def batch_order(model, points: dict):
    """The order in which a batch run takes the points (a permutation of their indices), or None.

    A return of the batch integrator costs ~10 µs for all lanes and comes whenever a lane's point
    ends, so it pays when the lanes' points end in the same step: neighbours in the queue should take
    alike step counts. Points are taken by decade of each log-scale axis (ν), then by the linear
    axes (ν_f) ascending. Measured (2 000 random single-block points, 16 lanes, CPU time per point):
    Carlson-Langer 23.0 -> 16.2 µs, piecewise-linear 21.7 -> 17.3 µs; the bench grid is in this order
    already. Results do not depend on the order (each lane keeps its point's own time and state).
    """
    axes = [a for a in model.axes if a.name in points]
    if not axes:
        return None
    minor = [np.asarray(points[a.name], dtype=float).ravel() for a in axes if a.scale != "log"]
    with np.errstate(divide="ignore", invalid="ignore"):
        major = [np.floor(np.log10(np.asarray(points[a.name], dtype=float).ravel())) for a in axes
                 if a.scale == "log"]
    return np.lexsort((*reversed(minor), *reversed(major)))


def run_model(model, law, points: dict, *, precision: str = "double", t_max: float = DEFAULT_T_MAX,
              max_steps: int = DEFAULT_MAX_STEPS, batch: int = 1, exact: dict | None = None) -> tuple[dict, dict]:
    """The model's outputs and messages for flat arrays ``points`` (axis name → values); a batch run
    takes them in ``batch_order`` and returns them in the given order."""
    size = next(iter(points.values())).size if points else 1
    order = batch_order(model, points) if batch > 1 and size > batch and not model.structural else None
    if order is None:
        return _run_model(model, law, points, precision=precision, t_max=t_max, max_steps=max_steps,
                          batch=batch, exact=exact)
    fields, messages = _run_model(
        model, law, {k: np.asarray(v).ravel()[order] for k, v in points.items()}, precision=precision,
        t_max=t_max, max_steps=max_steps, batch=batch,
        exact={k: np.asarray(v).ravel()[order] for k, v in exact.items()} if exact else None)
    out = {}
    for name, column in fields.items():
        out[name] = np.empty_like(column)
        out[name][order] = column
    return out, {int(order[i]): text for i, text in messages.items()}


def _run_model(model, law, points: dict, *, precision: str = "double", t_max: float = DEFAULT_T_MAX,
               max_steps: int = DEFAULT_MAX_STEPS, batch: int = 1, exact: dict | None = None) -> tuple[dict, dict]:
    """The model's outputs and messages for flat arrays ``points`` (axis name → values).

    ``exact``: for ``precision="quad"``, the points as given (object arrays: decimal text, Decimal, …)
    of runtime slots that take an axis value unchanged, read in real128 (``engine._exact``).

    The one path of every model: compile (cached), run each point (scalar loop or SIMD batch), then
    the model's ``classify`` turns raw outcomes into its outputs.
    """
    law = resolve_law(law)
    size = next(iter(points.values())).size if points else 1
    values = model.runtime(points)
    structural = [a.name for a in model.structural]
    if not structural:
        return _run_group(model, law, values, size, {}, precision, t_max, max_steps, batch, exact)
    # one compiled system per distinct structure (an N-block chain per N): run each group, scatter back
    keys = np.stack([np.asarray(points[name]).ravel() for name in structural], axis=1)
    groups, inverse = np.unique(keys, axis=0, return_inverse=True)
    fields, messages = {}, {}
    for g, key in enumerate(groups):
        where = np.flatnonzero(inverse.ravel() == g)
        structure = {name: model.axis(name).cast(value) for name, value in zip(structural, key)}
        part, notes = _run_group(model, law, {k: v[where] for k, v in values.items()}, where.size, structure,
                                 precision, t_max, max_steps, batch,
                                 {k: np.asarray(v)[where] for k, v in exact.items()} if exact else None)
        for name, column in part.items():
            if name not in fields:
                fields[name] = np.empty(size, dtype=np.asarray(column).dtype)
            fields[name][where] = column
        messages.update({int(where[i]): text for i, text in notes.items()})
    return fields, messages


def _run_group(model, law, values, size, structure, precision, t_max, max_steps, batch, exact=None):
    c = compiled(law, precision, batch if batch > 1 else 1, model=model, structure=structure)
    if batch > 1:
        from ._batch import run_batch

        raw = run_batch(c, values, size, t_max=t_max, max_steps=max_steps)
    else:
        raw = _scalar_points(c, values, size, t_max, max_steps, exact)
    return model.classify(raw, values)


def batch_lanes() -> int:
    """Lanes of ``slip``'s default batch on this host: four times heyoka's recommended SIMD width (4 on
    the AVX2 and the AVX-512 hosts measured: heyoka keeps to 256-bit vectors, and ``force_avx512`` was no
    faster here). A return of the batch integrator is shared by more lanes, and the per-lane cost of a
    step is lowest at 16 (0.22 µs against 0.26 at 8 and 0.31 at 4, Carlson-Langer). Measured on the
    AVX-512 host (CPU time per point, one process): 16 lanes as fast as or faster than 4, 8 and 32 from
    16 to 10 000 points for Carlson-Langer and piecewise-linear (1 989-point bench grid: 11.7 µs against
    12.9 at 8 and 13.0 at 32; 128 random points: 15.0 against 15.6 at 8). Again after the block reloads of
    ``_batch`` (random points, 16 to 10 000): 16 lanes fastest or within 4 % of the fastest of 8, 16 and 32."""
    return 4 * int(hy.recommended_simd_size())


def auto_batch(law, size: int, precision: str = "double") -> int:
    """The batch ``slip`` uses by default for ``size`` points: ``batch_lanes()`` from
    ``AUTO_BATCH_MIN_POINTS`` points in double precision, else 1 (scalar).

    A function of the inputs and the host only (never of timing), so a call gives the same bits every
    time on a host. Batch results do not depend on the lane count or the order of points, and equal the
    scalar ones to rounding (≤ 7e-15 on the bench grid of 1 989 points; more at the ill-conditioned
    ν_f ≈ 0.51, see test_engine), not bit for bit. On the bench grid (2 000 points, CPU time per
    point, ``bifurcation bench``) the default batch is 2.9x (Carlson-Langer) and 2.5x (piecewise-linear)
    faster than the scalar loop.
    """
    if precision != "double" or size < AUTO_BATCH_MIN_POINTS:
        return 1
    return batch_lanes()


def slip(law: str | FrictionLaw, *, nu, nu_f, precision: str = "double",
         t_max: float = DEFAULT_T_MAX, max_steps: int = DEFAULT_MAX_STEPS, batch: int | None = None) -> SlipResult:
    """One slip cycle for every (ν, ν_f) of the broadcast of ``nu`` and ``nu_f``.

    Parameters
    ----------
    law : str or FrictionLaw
        A name of ``bifurcation.law_names()`` or a formula in x (see ``bifurcation.laws``).
    nu, nu_f : array_like
        Pulling speed ν > 0 and friction velocity ν_f > 0 (Eq. 5), broadcast against each other. With
        ``precision="quad"`` a decimal given as text (``"1e-9"``, a ``Decimal``) is read in real128.
    precision : {"double", "quad"}
        ``"quad"`` integrates in heyoka real128 (verification; results are rounded to float64).
    t_max, max_steps : float, int
        Bounds after which a point that has not stopped gets status ``no-stop``.
    batch : int, optional
        Lanes of heyoka's batch (SIMD) integrator (double only); 1 integrates point by point. Default:
        ``auto_batch`` (a batch of ``batch_lanes()`` from 16 points in double precision, else scalar),
        chosen from the number of points, the precision and the host, never from timing. Results of a
        batch run do not depend on the batch size or the order of points, and agree with the scalar
        run to rounding (≤ 7e-15 on the bench grid), not bit for bit (SIMD code differs): pass
        ``batch=1`` for the scalar bits (workflows and the store use their own ``batch``, default 1).

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
    batch = auto_batch(law, nu_b.size, precision) if batch is None else check_batch(batch, precision)
    shape = nu_b.shape
    nu_flat = np.ascontiguousarray(nu_b, dtype=float).ravel()
    nu_f_flat = np.ascontiguousarray(nu_f_b, dtype=float).ravel()
    exact = None
    if precision == "quad":   # the inputs as given: decimals are read in real128, not via the double
        given = np.broadcast_arrays(np.asarray(nu, dtype=object), np.asarray(nu_f, dtype=object))
        exact = {"nu": given[0].ravel(), "nu_f": given[1].ravel()}
    fields, messages = run_model(SINGLE_BLOCK, law, {"nu": nu_flat, "nu_f": nu_f_flat}, precision=precision,
                                 t_max=t_max, max_steps=max_steps, batch=batch, exact=exact)
    return SlipResult(nu=nu_flat.reshape(shape), nu_f=nu_f_flat.reshape(shape),
                      **{k: v.reshape(shape) for k, v in fields.items()},
                      messages=messages, law=law.name, precision=precision)
