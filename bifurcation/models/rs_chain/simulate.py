"""``rs_chain``: one run of the rate-and-state chain, its event catalog and the stress balance per event.

An event is a connected run of time during which at least one block slips faster than v_th (a block
"slips" while V_j > v_th). Per event: ``t_start`` (the first up-crossing), ``hypocentre`` (its block),
``n_blocks`` (distinct blocks above v_th during the event), ``potency`` (ΔΣδ_j, from the integrated
P), ``duration`` (until the last block falls below v_th), ``max_velocity`` (the largest V_j at an exact
maximum, ẋ_j = 0, of a block above v_th) and the stress balance: summing the force balance over the
blocks (the neighbour springs cancel for free and periodic ends),

    Σ_j (μ_j + z_j + η V_j)  changes by  k (N V_lp Δt − ΔP)   over the event,

whose two sides come from different variables (x, y, z against the integrated P): ``balance`` is
their difference over the event's stress change (a check of the integration, not used to compute
anything).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import heyoka as hy
import numpy as np

from ...errors import InputError
from ..rate_state.laws import resolve_state_law
from ._system import EXACT_TOL, PARAMETERS, Layout, compiled, rhs_expressions, steady_state
from .checkpoint import Snapshot
from .result import RSChainStatus

__all__ = ["CATALOG_FIELDS", "STEADY_BAND", "STEADY_FLOOR", "STEADY_RATIO", "STEADY_WINDOW", "STEADY_WINDOWS", "RSChainResult", "linear_growth", "RSChainSpec", "RSChainStatus", "initial_state", "rs_chain", "run"]

CATALOG_FIELDS = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")

#: The loosest heyoka tolerance ``run`` accepts: order 11; the catalog's error there is measured in
#: docs/rs-chain.md ("Speed"), beyond it nothing was measured.
LOOSEST_TOL = 1e-8


#: Steady sliding (status ``steady``; docs/rs-chain.md, "Steady sliding"). With τ = Dc/V_lp, the largest
#: deviation d = max_j max(|ln V_j − ln V_lp|, |ln θ_j − ln θ_ss|) is sampled once per τ (at the end of the
#: first Taylor step past each multiple of τ); its maximum over a window of STEADY_WINDOW τ (longer where
#: the slowest linear mode needs it: two of its halving times and one of its period) is D. A run
#: ends ``steady`` when STEADY_WINDOWS consecutive windows have no block above v_th, every sample within
#: STEADY_BAND, D > 0 and each D below STEADY_RATIO times the one before (the deviations observed to decay,
#: by 1/8 or more over the last three windows), and the linearisation at steady sliding is stable
#: (``linear_growth`` < 0 by a margin): an observed decay, not the stiffness alone, since a large
#: perturbation can lead to stick-slip where the linearisation is stable (sub-critical). Measured: the
#: deviations of aging, N = 3, a = 0.008, b = 0.0135, Dc = 0.02, k = 0.12, η = 5e-3, A = 0.5 decay by
#: ~10 per 25 τ.
STEADY_BAND = 1e-3
STEADY_WINDOW = 10
STEADY_WINDOWS = 4
STEADY_RATIO = 0.5
#: the linearisation counts as stable when max Re λ < −STEADY_MARGIN · max |λ| (finite differences of the
#: right-hand side are ~1e-8 relative: a nearly marginal mode is not called stable)
STEADY_MARGIN = 1e-6
#: a window maximum at or below this counts as decayed (the deviations' rounding floor is ~1e-15: there
#: they no longer shrink), once a window above it was seen to decay
STEADY_FLOOR = 1e-12


def linear_growth(spec: "RSChainSpec") -> tuple[float, float, float]:
    """(max Re λ, max |λ|, |Im λ| of the λ with max Re λ) of the chain linearised at steady sliding at V_lp.

    All blocks alike, so the modes decouple: mode m of the neighbour Laplacian (eigenvalue −4 sin²(πm/2N)
    with free, mirror ends; −4 sin²(πm/N) periodic) is the single slider with stiffness
    k_m = k (1 + 4ℓ² sin²(…)). Each slider's Jacobian (x, y[, z]) by central differences of
    ``rhs_expressions`` (numpy, all modes at once)."""
    n = spec.n
    m = np.arange(n, dtype=float)
    lap = 4 * np.sin(np.pi * m / (n if spec.periodic else 2 * n)) ** 2 if n > 1 else np.zeros(1)
    lap = np.unique(lap)
    layout = Layout(1, spec.inertial)
    values = spec.parameters()
    par = {name: values[name] for name in PARAMETERS}
    par["k"] = spec.k * (1 + spec.ell ** 2 * lap)
    x0, y0 = steady_state(spec.law, spec.v_lp, spec.dc)
    base = [x0, y0] + ([0.0] if spec.inertial else [])
    dim = len(base)
    jac = np.empty((lap.size, dim, dim))
    for i in range(dim):
        h = 1e-6 * max(1.0, abs(base[i]))
        cols = []
        for sign in (1.0, -1.0):
            v = [np.full(lap.size, b, dtype=float) for b in base] + [np.zeros(lap.size)]
            v[i] = v[i] + sign * h
            cols.append(rhs_expressions(spec.law, layout, v, par, np.exp, np.log, periodic=False,
                                        damped=spec.eta > 0)[:dim])
        for r in range(dim):
            jac[:, r, i] = (np.asarray(cols[0][r]) - np.asarray(cols[1][r])) / (2 * h)
    lam = np.linalg.eigvals(jac).ravel()
    slowest = lam[np.argmax(lam.real)]
    return float(slowest.real), float(np.max(np.abs(lam))), float(abs(slowest.imag))


class _Steady:
    """The steady-sliding test of one run (see STEADY_BAND): ``sample`` is called when time >= ``next``."""

    def __init__(self, spec: "RSChainSpec", t0: float) -> None:
        growth, radius, omega = linear_growth(spec)
        self.stable = growth < -STEADY_MARGIN * radius
        self.growth = growth
        self.tau = spec.dc / spec.v_lp
        # the window: STEADY_WINDOW τ, or longer where the slowest mode is slower: two of its halving
        # times (so it must shrink to 1/4 a window, against the 1/2 asked) and one of its periods (a
        # decreasing stretch of a slow oscillation is no decay)
        span = max(2 * math.log(2) / -growth, 2 * math.pi / omega if omega > 0 else 0.0) if self.stable else 0.0
        self.length = max(STEADY_WINDOW * self.tau, span)
        self.n = spec.n
        self.x_ss, self.y_ss = steady_state(spec.law, spec.v_lp, spec.dc)
        # samples on the grid of multiples of τ, and the windows restarted at every event's end: a run
        # resumed from a checkpoint (taken at an event's end) samples as the straight run did
        self.next = self.after(t0) if self.stable else math.inf
        self.reset()

    def after(self, time: float) -> float:
        """The first multiple of τ above ``time`` (time/τ may round below a whole number)."""
        m = math.floor(time / self.tau) + 1
        return self.tau * (m + 1) if self.tau * m <= time else self.tau * m

    def reset(self) -> None:
        self.start, self.peak, self.maxima = None, 0.0, []

    def sample(self, time: float, state, n_above: int) -> bool:
        """True: steady sliding established at ``time``."""
        self.next = self.after(time)
        if n_above:
            self.reset()
            return False
        n = self.n
        d = max(float(np.max(np.abs(state[:n] - self.x_ss))), float(np.max(np.abs(state[n:2 * n] - self.y_ss))))
        if not d <= STEADY_BAND:
            self.reset()
            return False
        done = False
        if self.start is None:
            self.start = time
        elif time >= self.start + self.length:          # the window [start, time) is complete
            self.maxima = (self.maxima + [(self.start, self.peak)])[-STEADY_WINDOWS:]
            self.start, self.peak = time, 0.0
            w = [m for _, m in self.maxima]
            done = (len(w) == STEADY_WINDOWS and w[0] > STEADY_FLOOR
                    and all(w[i + 1] < STEADY_RATIO * w[i] or w[i + 1] <= STEADY_FLOOR
                            for i in range(STEADY_WINDOWS - 1)))
        self.peak = max(self.peak, d)
        return done

    def message(self, time: float, done: int, total: int) -> str:
        w = ", ".join(f"{m:.2e}" for _, m in self.maxima)
        return (f"steady: steady sliding after {done} events, no event to come: from t = "
                f"{self.maxima[0][0]:.6g} the largest |ln V_j − ln V_lp|, |ln θ_j − ln θ_ss| per "
                f"{self.length / self.tau:.4g} Dc/V_lp decayed {w} (each < {STEADY_RATIO:g} × the one before or "
                f"<= {STEADY_FLOOR:g}, all <= {STEADY_BAND:g}) and the linearisation is stable (max Re λ = "
                f"{self.growth:.3g}) (t = {time:.17g}, {total} steps)")


def _number(argument, value, *, low=None, positive=False, fix="give a finite number") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(argument, value, "is not a number", fix) from None
    if not math.isfinite(v):
        raise InputError(argument, value, "is not finite", fix)
    if positive and not v > 0:
        raise InputError(argument, value, "must be > 0", fix)
    if low is not None and v < low:
        raise InputError(argument, value, f"must be >= {low:g}", fix)
    return v


@dataclass(frozen=True)
class RSChainSpec:
    """A validated chain: N blocks, state law, a, b, Dc, k, ℓ, V_lp, M, η, v_th and its ends."""

    n: int
    state_law: str
    a: float
    b: float
    dc: float
    k: float
    ell: float
    v_lp: float
    mass: float = 0.0
    eta: float = 0.0
    v_th: float = 10.0
    periodic: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.n, bool) or not isinstance(self.n, (int, np.integer)) or self.n < 1:
            raise InputError("n", self.n, "must be a whole number of blocks >= 1", "give n = 1, 2, ...")
        object.__setattr__(self, "state_law", resolve_state_law(self.state_law).name)
        for name in ("a", "dc", "k", "v_lp", "v_th"):
            object.__setattr__(self, name, _number(name, getattr(self, name), positive=True,
                                                   fix=f"give {name} > 0"))
        for name in ("b", "ell", "mass", "eta"):
            object.__setattr__(self, name, _number(name, getattr(self, name), low=0.0,
                                                   fix=f"give {name} >= 0"))
        if not self.v_th > self.v_lp:
            raise InputError("v_th", self.v_th, f"is not above the plate velocity v_lp = {self.v_lp:g}",
                             "give a slip-velocity threshold v_th > v_lp (a block slips while V > v_th)")

    @property
    def inertial(self) -> bool:
        return self.mass > 0

    @property
    def law(self):
        return resolve_state_law(self.state_law)

    def parameters(self) -> dict:
        return {"a": self.a, "b": self.b, "dc": self.dc, "k": self.k, "ell2": self.ell * self.ell,
                "v_lp": self.v_lp, "mass": self.mass if self.inertial else 1.0, "eta": self.eta,
                "ln_v_th": math.log(self.v_th)}

    def stress(self, state, layout: Layout) -> float:
        """Σ_j (μ_j − μ0 + z_j + η V_j) at ``state`` (μ0 left out: it cancels in every change)."""
        n = self.n
        x = np.asarray(state[:n], dtype=float)
        y = np.asarray(state[n:2 * n], dtype=float)
        s = self.a * x + self.b * (y - math.log(self.law.steady_factor * self.dc)) + self.eta * np.exp(x)
        if self.inertial:
            s = s + np.asarray(state[2 * n:3 * n], dtype=float)
        return float(math.fsum(s))


def initial_state(spec: RSChainSpec, amplitude: float = 0.0, seed: int = 0) -> np.ndarray:
    """Steady sliding at V_lp with ln V_j perturbed by A r_j, r_j uniform in [−1, 1) from
    ``numpy.random.default_rng(seed)`` (θ_j stays at its steady value for V_lp; z_j = 0)."""
    amplitude = _number("amplitude", amplitude, low=0.0, fix="give amplitude >= 0")
    x_ss, y_ss = steady_state(spec.law, spec.v_lp, spec.dc)
    r = np.random.default_rng(int(seed)).uniform(-1.0, 1.0, spec.n) if amplitude > 0 else np.zeros(spec.n)
    x = x_ss + amplitude * r
    if np.max(x) >= math.log(spec.v_th):
        raise InputError("amplitude", amplitude, f"starts a block at V >= v_th = {spec.v_th:g}",
                         "give a smaller amplitude or a larger v_th (blocks start below the threshold)")
    layout = Layout(spec.n, spec.inertial)
    state = np.zeros(layout.size)
    state[:spec.n] = x
    state[spec.n:2 * spec.n] = y_ss
    return state


@dataclass(frozen=True)
class RSChainResult:
    """The first events of a run: catalog arrays, per-event stress balance, final state and status."""

    spec: RSChainSpec
    t_start: np.ndarray
    hypocentre: np.ndarray
    n_blocks: np.ndarray
    potency: np.ndarray
    duration: np.ndarray
    max_velocity: np.ndarray
    stress_drop: np.ndarray      # −ΔΣ(μ_j + z_j + ηV_j) over the event
    balance: np.ndarray          # |ΔΣ − k(N V_lp Δt − ΔP)| / |ΔΣ| per event
    t_end: float                 # the end of the last event
    steps: int
    status: RSChainStatus
    message: str = ""
    crossings: np.ndarray | None = None   # rows (t, block, +1 up / −1 down) with ``crossings=True``
    meta: dict = field(default_factory=dict)
    #: a run resumed from a store's checkpoint: the largest balance of the restored events (their
    #: stress_drop and balance are NaN: a checkpoint keeps only this of them); NaN otherwise
    restored_balance_max: float = math.nan

    @property
    def events(self) -> int:
        return int(self.t_start.size)

    @property
    def balance_max(self) -> float:
        """The largest balance over all events, restored ones included (NaN without events)."""
        values = self.balance[~np.isnan(self.balance)].tolist()
        if not math.isnan(self.restored_balance_max):
            values.append(self.restored_balance_max)
        return max(values) if values else math.nan

    def catalog(self) -> dict:
        return {name: getattr(self, name) for name in CATALOG_FIELDS}


class _Events:
    """Assembles slip events from the time-ordered crossings of each step."""

    def __init__(self, spec: RSChainSpec, layout: Layout, wanted: int) -> None:
        self.spec, self.layout, self.wanted = spec, layout, wanted
        self.above = np.zeros(spec.n, dtype=bool)
        self.n_above = 0      # = above.sum(), kept as an int: the step callback asks it every Taylor step
        self.rows: list = []
        self.current = None
        self.t_last = 0.0
        self.ln_v_th = math.log(spec.v_th)
        self.crossings: list | None = None
        self.restored_balance_max = math.nan     # see RSChainResult.restored_balance_max
        # RSChainSpec.stress's constants, bound once: it ran at 24 µs a call (law lookup, small-array numpy,
        # fsum over numpy scalars), 2 calls an event, ~20 % of an N = 4 run
        self._y_ss = math.log(spec.law.steady_factor * spec.dc)

    def stress(self, state) -> float:
        """``RSChainSpec.stress`` in Python floats (~2 µs at N = 4 against 24; equal to rounding: libm's
        exp for numpy's)."""
        spec, n = self.spec, self.spec.n
        values = state.tolist()
        a, b, eta, y_ss, exp = spec.a, spec.b, spec.eta, self._y_ss, math.exp
        terms = [a * x + b * (y - y_ss) + eta * exp(x) for x, y in zip(values[:n], values[n:2 * n])]
        if spec.inertial:
            terms += values[2 * n:3 * n]
        return math.fsum(terms)

    @property
    def done(self) -> int:
        return len(self.rows)

    def feed(self, buffer: list, state_at) -> None:
        """Assemble one step's roots; ``state_at(t)`` is the state at t inside that step (dense output)."""
        for time, kind, j in sorted(buffer, key=lambda r: (r[0], -r[1])):
            if self.done >= self.wanted:
                return
            if self.crossings is not None and kind != 0:
                self.crossings.append((time, j, kind))
            if kind == 1:
                if self.above[j]:
                    continue          # a repeated root at a tangency: already above
                if not self.n_above:
                    data = state_at(time)
                    self.current = {"t_start": time, "hypocentre": j, "blocks": {j}, "vmax": self.spec.v_th,
                                    "p0": float(data[self.layout.potency]), "s0": self.stress(data)}
                self.above[j] = True
                self.n_above += 1
                self.current["blocks"].add(j)
            elif kind == -1:
                if not self.above[j]:
                    continue
                self.above[j] = False
                self.n_above -= 1
                if not self.n_above:
                    self._close(time, state_at(time))
            elif self.above[j]:
                x = float(state_at(time)[j])
                if x > self.ln_v_th:
                    self.current["vmax"] = max(self.current["vmax"], math.exp(x))

    def _close(self, time, data) -> None:
        c, spec = self.current, self.spec
        dt = time - c["t_start"]
        potency = float(data[self.layout.potency]) - c["p0"]
        ds = self.stress(data) - c["s0"]
        load = spec.k * (spec.n * spec.v_lp * dt - potency)
        balance = abs(ds - load) / abs(ds) if ds != 0 else math.inf
        self.rows.append((c["t_start"], c["hypocentre"], len(c["blocks"]), potency, dt, c["vmax"], -ds, balance))
        self.current = None
        self.t_last = time


def run(spec: RSChainSpec, state0, events: int, *, t_max: float = math.inf, max_steps: int = 10_000_000,
        maxima: bool = True, crossings: bool = False, every: int | None = None, save=None,
        resume=None, tol: float = EXACT_TOL, steady: bool = True) -> RSChainResult:
    """Integrate from ``state0`` (``initial_state``) until ``events`` events are catalogued.

    ``t_max`` and ``max_steps`` bound the time and the Taylor steps from the start or the end of the
    last event to the end of the next one; beyond them the run stops with ``no-stop`` and keeps the
    events before. ``maxima=False`` leaves out the velocity-maximum events (``max_velocity`` is NaN);
    ``crossings=True`` keeps every threshold crossing (t, block, ±1) of the catalogued events.
    ``tol`` is heyoka's tolerance: the default, double epsilon, is the exact engine (≤ 1.8e-14 from the
    mpmath references); a looser one, up to ``LOOSEST_TOL``, lowers the Taylor order and the cost per
    step, not the step count (docs/rs-chain.md, "Speed": the catalog's measured error at each tolerance).

    Checkpoints (``checkpoint.Snapshot``): ``save(snapshot)`` is called at the end of the first step
    after which the events done reach a new multiple of ``every`` (while events remain to do); a run
    given ``resume=snapshot`` goes on from it (``state0`` gives only the shape) and computes the same
    events, bit for bit, as the run that saved it.

    ``steady=True`` ends a run whose deviations from steady sliding are observed to decay (within
    STEADY_BAND, by STEADY_RATIO per STEADY_WINDOW Dc/V_lp, over STEADY_WINDOWS windows, with the
    linearisation stable) with status ``steady`` and the events before; it only reads the state, so the
    events are those of ``steady=False``, bit for bit.
    """
    if int(events) < 1:
        raise InputError("events", events, "must be >= 1", "give the number of events to catalogue")
    tol = _number("tol", tol, positive=True, fix=f"give a tolerance from {EXACT_TOL:.3g} to {LOOSEST_TOL:g}")
    if not EXACT_TOL <= tol <= LOOSEST_TOL:
        raise InputError("tol", tol, f"is outside [{EXACT_TOL:.3g}, {LOOSEST_TOL:g}]",
                         f"give a tolerance from {EXACT_TOL:.3g} (the exact default) to {LOOSEST_TOL:g}")
    if save is not None and (every is None or int(every) < 1):
        raise InputError("every", every, "must be >= 1 with save", "give the events between checkpoints")
    if resume is not None and crossings:
        raise InputError("crossings", crossings, "cannot be kept by a resumed run (a checkpoint holds none)",
                         "run from the start with crossings=True")
    c = compiled(spec.state_law, spec.n, inertial=spec.inertial, periodic=spec.periodic,
                 damped=spec.eta > 0, maxima=maxima, tol=tol)
    ta, layout = c.integrator, c.layout
    state0 = np.asarray(state0, dtype=float)
    if state0.shape != (layout.size,):
        raise InputError("state0", state0.shape, f"is not a state of {layout.size} values",
                         "give initial_state(spec, ...)")
    values = spec.parameters()
    ta.pars[:] = [values[name] for name in PARAMETERS]
    c.recorder.buffer.clear()
    c.recorder.bind(ta)
    state_at = c.recorder.state_at
    assembler = _Events(spec, layout, int(events))
    if crossings:
        assembler.crossings = []
    steps = (0, 0)        # total, since the last event ended
    if resume is None:
        ta.time = 0.0
        ta.state[:] = state0
    else:
        if np.shape(resume.state) != (layout.size,) or np.shape(resume.above) != (spec.n,):
            raise ValueError(f"checkpoint state of {np.size(resume.state)} values does not fit this chain "
                             f"({layout.size})")
        ta.state[:] = resume.state
        ta.dtime = resume.dtime          # the double-length time: the rounded one would shift every step
        assembler.above[:] = resume.above
        assembler.n_above = int(np.count_nonzero(assembler.above))
        assembler.current = None if resume.current is None else {**resume.current,
                                                                 "blocks": set(resume.current["blocks"])}
        assembler.t_last = resume.t_last
        assembler.rows = list(resume.rows)
        assembler.restored_balance_max = resume.balance_max
        steps = tuple(resume.steps)
    status = [RSChainStatus.COMPLETE, ""]
    p_index = layout.potency
    saved = [assembler.done // every if save is not None else 0]     # chunks checkpointed so far
    # The step callback runs once per Taylor step (1-5 µs of heyoka work at N <= 16), so it touches only
    # Python ints and a view of the state bound once (``ta.state`` builds a new array per access) and reads
    # the catalog only when the step recorded a crossing or maximum.
    buffer, rows, wanted = c.recorder.buffer, assembler.rows, assembler.wanted
    state = ta.state
    bounded_t = math.isfinite(t_max)
    watch = _Steady(spec, float(ta.time)) if steady else None
    next_sample = [watch.next if watch is not None else math.inf]
    x_view = state     # the watch reads x and y only

    total, since = steps      # Taylor steps: in all, since the last event ended

    def step(ta) -> bool:
        nonlocal total, since
        total += 1
        since += 1
        grew = False
        if buffer:            # rows change only here: the done, reset and save checks with them
            before = len(rows)
            assembler.feed(buffer, state_at)
            buffer.clear()
            if len(rows) >= wanted:
                return False
            if len(rows) > before:
                since, grew = 0, True
        if not assembler.n_above:
            state[p_index] = 0.0     # between events P restarts from 0: it never grows large
        if next_sample[0] <= ta.time:
            if watch.sample(ta.time, x_view, assembler.n_above):
                status[0] = RSChainStatus.STEADY
                status[1] = watch.message(ta.time, assembler.done, total)
                return False
            next_sample[0] = watch.next
        if grew and watch is not None:
            watch.reset()
        if since > max_steps or (bounded_t and ta.time - assembler.t_last > t_max):
            status[0] = RSChainStatus.NO_STOP
            status[1] = (f"no-stop: event {assembler.done + 1} did not end within t_max = {t_max:g} or "
                         f"max_steps = {max_steps} (t = {ta.time:.17g}, {total} steps)")
            return False
        if grew and save is not None and len(rows) // every > saved[0]:
            saved[0] = len(rows) // every
            save(_snapshot(ta, assembler, (total, since)))
        return True

    outcome = ta.propagate_until(1e300, callback=step)[0]
    if outcome == hy.taylor_outcome.err_nf_state:
        status = [RSChainStatus.NONFINITE, f"nonfinite state at t = {ta.time:.17g} after {total} steps "
                  f"(M = 0 and η = 0 blow up in finite time below the critical stiffness: give η > 0 or M > 0)"]
    rows = assembler.rows
    cols = list(zip(*rows)) if rows else [()] * 8
    return RSChainResult(
        spec=spec, t_start=np.array(cols[0], dtype=float), hypocentre=np.array(cols[1], dtype=np.int64),
        n_blocks=np.array(cols[2], dtype=np.int64), potency=np.array(cols[3], dtype=float),
        duration=np.array(cols[4], dtype=float),
        max_velocity=np.array(cols[5], dtype=float) if maxima else np.full(len(rows), np.nan),
        stress_drop=np.array(cols[6], dtype=float), balance=np.array(cols[7], dtype=float),
        t_end=assembler.t_last if rows else math.nan, steps=total, status=status[0], message=status[1],
        crossings=np.array(assembler.crossings, dtype=float).reshape(-1, 3) if crossings else None,
        restored_balance_max=assembler.restored_balance_max)


def _snapshot(ta, assembler: _Events, steps) -> Snapshot:
    c = assembler.current
    return Snapshot(state=np.array(ta.state, copy=True), dtime=tuple(float(v) for v in ta.dtime),
                    steps=(steps[0], steps[1]), above=assembler.above.copy(),
                    current=None if c is None else {**c, "blocks": set(c["blocks"])}, t_last=assembler.t_last,
                    rows=list(assembler.rows), balance_max=assembler.restored_balance_max)


def rs_chain(*, n, state_law="aging", a=0.01, b=0.015, dc=0.01, k, ell=1.0, v_lp=1.0, mass=0.0, eta=0.0,
             v_th=10.0, periodic=False, amplitude=0.1, seed=1, events=100, t_max=math.inf,
             max_steps=10_000_000, maxima=True, crossings=False, tol=EXACT_TOL, steady=True) -> RSChainResult:
    """Run a rate-and-state chain from perturbed steady sliding and catalogue its first ``events`` events
    (``steady``: see ``run``)."""
    spec = RSChainSpec(n=n, state_law=state_law, a=a, b=b, dc=dc, k=k, ell=ell, v_lp=v_lp, mass=mass, eta=eta,
                       v_th=v_th, periodic=bool(periodic))
    return run(spec, initial_state(spec, amplitude, seed), events, t_max=t_max, max_steps=max_steps,
               maxima=maxima, crossings=crossings, tol=tol, steady=steady)
