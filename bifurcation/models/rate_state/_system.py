"""The rate-and-state slider as heyoka Taylor integrators, compiled once per structure.

Variables (docs/rate-state.md): x = ln V, y_i = ln θ_i and, with inertia, z = k(δ_lp − δ) − ηV − μ = M V̇
(the net force; η ≥ 0 the radiation damping, friction per unit slip rate). In these variables

    quasi-static:  (a + η e^x) ẋ = k(V_lp − e^x) − Σ b_i ẏ_i
    inertial:      ẋ = z e^{−x}/M,   ż = k(V_lp − e^x) − (a + η e^x) ẋ − Σ b_i ẏ_i
    state:         ẏ_i = law_i.rate(x, y_i; Dc_i)                     (laws.py)

An undamped slider (η = 0) is compiled without the η terms (``damped=False``): the same equations
and step sequence as before damping existed, and no division by a series where a constant does.

x and y keep their relative precision over any number of decades of V (a double x carries V to 2e-16
relative at V = 1e-20 as at V = 1e3), and the net force z is integrated directly, never formed as the
small difference of two O(μ0) forces. The slip δ needs no equation: k(δ_lp − δ) = μ + ηV (+ z with
inertia).

Runtime parameters (one compiled integrator serves every parameter set of a structure), in the slots
of ``Slots``: a, k, V_lp (set per load segment), M (unused quasi-static), η (unused undamped), then
b_i, Dc_i and the ln of each slip-velocity threshold; ``parameters`` fills them.

Events, all non-terminal and located exactly by heyoka's polynomial root finding on each step:
ẋ = 0 (velocity extrema: maximum when ẋ goes from + to −) and x = ln V_j (slip thresholds).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import heyoka as hy
import numpy as np

from .laws import resolve_state_law

__all__ = ["TAYLOR_BLOWUP", "Compiled", "Recorder", "Slots", "blowup_guard", "compiled", "fp_info", "parameters",
           "rhs_expressions"]

#: Largest |top-order Taylor coefficient of ln V| a double step may have. Where V blows up in finite
#: time (quasi-static below k_c, a cycle running away) the coefficients grow like ρ^−n, ρ the distance
#: to the singularity: ×16 per step measured (aging, κ = 0.9). Past ~1e307 the next step's overflow, its
#: size is NaN and heyoka warns ("invalid timestep value of nan") before returning a non-finite state.
#: 1e300 stops ~6 steps before that; bounded cycles do reach 1e290–1e300 (quasi-static aging at k_c,
#: ln V up to 29.8: with 1e290 that branch lost its largest cycles; 1e300, 1e305 and no bound agree).
TAYLOR_BLOWUP = 1e300


#: The same for real128 (largest finite ~1.19e4932): its order-38 coefficients grow ~1e3 per step there.
TAYLOR_BLOWUP_QUAD = "1e4900"


class blowup_guard:
    """A step callback for ``propagate_*``: False (stop) once the last step's top Taylor coefficient of
    ln V passes ``TAYLOR_BLOWUP`` (``TAYLOR_BLOWUP_QUAD`` in real128): ``reason`` = "blow-up"; or once
    ``STALL_STEPS`` steps in a row leave the integrator's double-length time where it was (heyoka's step
    size 0): ``reason`` = "stall". Without the second test a stalled run would call this Python callback
    once per empty step up to ``max_steps`` (2e6: seconds), where heyoka alone spins through them in C++.

    The time compared is ``ta.dtime`` (hi, lo), not the rounded ``ta.time``: at a slip-law spike late in a
    long run (t ~ 4.5e3, steps ~1e-14 below the ulp of t) the rounded time stands still for 100 steps while
    the run advances; reading it called the deep slip-law cycle of the bench "stalled" after 4 of 20 cycles.
    This runs once per Taylor step, so it reads the top coefficient through a view of the integrator's
    Taylor-coefficient buffer bound once: reading ``ta.tc`` (a new array per call) beside ``ta.dtime`` on every
    step took 12.3 ms for 20 deep aging cycles (6 984 steps) against 7.4 ms this way, 7.5 ms for the
    earlier guard (``ta.tc`` and ``ta.time``) and 4.9 ms with no callback (best of 11, alternated)."""

    #: Steps in a row that do not move t before the run is called stalled (one or a few such steps
    #: happen where t still advances on the next: measured on the quasi-static fates, none needs 100).
    STALL_STEPS = 100

    def __init__(self, dtype) -> None:
        self.bound = TAYLOR_BLOWUP if dtype is np.float64 else dtype(TAYLOR_BLOWUP_QUAD)
        self.reason = ""
        self._last = None
        self._still = 0
        self._ta = None
        self._top = self._at = None

    def _bind(self, ta) -> None:
        # heyoka's coefficient buffer is allocated once per integrator: a view of it stays valid
        tc = ta.tc
        self._ta = ta
        if tc.dtype == np.float64 and tc.flags.c_contiguous:
            self._top, self._at = memoryview(tc).cast("B").cast("d"), tc.shape[1] - 1   # x's last coefficient
        else:
            self._top, self._at = tc[0], -1

    def __call__(self, ta) -> bool:
        if ta is not self._ta:
            self._bind(ta)
        if not abs(self._top[self._at]) < self.bound:
            self.reason = "blow-up"
            return False
        now = ta.dtime
        self._still = self._still + 1 if now == self._last else 0
        if self._still >= self.STALL_STEPS:
            self.reason = "stall"
            return False
        self._last = now
        return True

_CACHE: dict = {}


class Slots:
    """Where each runtime parameter lives in the integrator's ``pars`` (n state variables)."""

    A, K, V_LP, MASS, DAMPING = range(5)
    FIXED = 5

    @staticmethod
    def b(n: int, i: int) -> int:
        return Slots.FIXED + i

    @staticmethod
    def dc(n: int, i: int) -> int:
        return Slots.FIXED + n + i

    @staticmethod
    def threshold(n: int, j: int) -> int:
        return Slots.FIXED + 2 * n + j

    @staticmethod
    def size(n: int, n_thresholds: int) -> int:
        return Slots.FIXED + 2 * n + n_thresholds


def parameters(spec, k, v_lp, ln_thresholds=()) -> list:
    """The runtime parameter vector of ``spec`` at spring stiffness k and load-point velocity V_lp."""
    return [spec.a, k, v_lp, spec.mass or 1.0, spec.damping, *spec.b, *spec.dc, *ln_thresholds]


def fp_info(precision: str):
    """(heyoka fp_type or None, numpy dtype) for ``"double"`` or ``"quad"`` (real128)."""
    if precision == "double":
        return None, np.float64
    if precision == "quad":
        return hy.real128, hy.real128
    raise ValueError(precision)


class Recorder:
    """Velocity extrema and threshold crossings of one run, recorded at their exact times."""

    def __init__(self) -> None:
        self.reset()

    def reset(self, start=0.0) -> None:
        self.start = start
        self.offset = 0.0   # the current segment's start: the integrator runs in segment-local time
        self.first = True   # in the first segment (its local time 0 is the start of the run)
        self.x0 = float("nan")  # ln V at the start (set by the run): the reference of the first extremum
        self.extrema: list = []     # (t, ln V, +1 maximum / -1 minimum)
        self.crossings: list = []   # (t, threshold index, +1 up / -1 down)
        self.crossing_states: list = []  # (t, state) in the run's precision, for return maps

    def __deepcopy__(self, memo) -> "Recorder":
        return self  # heyoka deep-copies callbacks; all of them must record here

    def extremum(self, ta, time, d_sgn) -> None:
        if time == self.start and self.first:
            return  # at a steady start ẋ = 0 exactly: not an extremum of the run
        ta.update_d_output(time)
        x = _peak(ta, time, float(ta.d_output[0]))
        # At a steady state ẋ is rounding noise that changes sign at almost every step: an "extremum"
        # within 64 ulps of the last recorded one is that noise, not an oscillation, and is dropped.
        # Real extrema of a smooth ln V alternate between maxima and minima, so a repeat of the last
        # kind is noise too.
        kind = 1 if d_sgn < 0 else -1   # ẋ decreasing through 0 at a maximum of V
        last_x, last_kind = (self.extrema[-1][1], self.extrema[-1][2]) if self.extrema else (self.x0, 0)
        if abs(x - last_x) <= 64 * 2.2e-16 * max(1.0, abs(x)) or kind == last_kind:
            return
        self.extrema.append((float(time) + self.offset, x, kind))

    def crossing(self, j: int):
        def record(ta, time, d_sgn):
            if time != self.start or not self.first:
                ta.update_d_output(time)
                self.crossings.append((float(time) + self.offset, j, 1 if d_sgn > 0 else -1))
                self.crossing_states.append((time + type(time)(self.offset), ta.d_output.copy()))
        return record


def _horner(coefficients: list, x: float) -> float:
    """The polynomial with ``coefficients`` (highest power first) at x, as np.polyval evaluates it."""
    y = 0.0
    for p in coefficients:
        y = y * x + p
    return y


def _peak(ta, time, x_dense: float) -> float:
    """ln V at an extremum, from the step's Taylor polynomial in the step's own time.

    The callback's event time is an absolute double: at t ~ 1e3 it carries ~1e-13 of rounding, and at a
    slip spike (|ẍ| ~ 1e20 and more) the dense output read there is off by ½|ẍ|δt² (3.5e-8 in ln V_max
    of a deep slip-law cycle, against real128 and mpmath). Newton on p'(τ) = 0 with τ measured from the
    step's start (to the precision of the step, not of t) removes that; the value is p(τ*). Falls back
    to the dense-output value if the iteration leaves the step.
    """
    tc = ta.tc
    if tc.dtype != np.float64:
        return x_dense   # real128: its t carries 1e-34 relative, the dense output is already exact enough
    try:
        c = tc[0].tolist()
        h = float(ta.last_h)
        hi, lo = ta.dtime
        tau = (float(time) - float(hi)) - float(lo) + h
        # On Python floats, not numpy: the same IEEE products as c[1:] * np.arange(1, c.size), without numpy's
        # per-call overhead on 20-element arrays (rsfmodel's five cases, best of 15 alternated: 1.80 against
        # 2.03 ms in total)
        d1 = [c[i] * i for i in range(1, len(c))]
        d2 = [d1[i] * i for i in range(1, len(d1))]
        if not (all(map(math.isfinite, d2)) and math.isfinite(tau)):
            return x_dense
        # Horner on Python floats: the same operations as np.polyval (y = y·τ + p, each rounded), bit for
        # bit, without numpy's ~1 µs per scalar operation (np.polyval made this 40 µs a call, 6 Newton
        # steps: most of a short run's time, e.g. 2.4 of 3.0 ms for the rate-state bench's prz_1)
        c1, c2, c0 = d1[::-1], d2[::-1], c[::-1]
        for _ in range(6):
            curvature = _horner(c2, tau)
            if not curvature:   # a flat extremum: Newton cannot move (and 0/0 would warn on stderr)
                return x_dense
            step = _horner(c1, tau) / curvature
            tau -= step
            if abs(step) <= 1e-16 * abs(h):
                break
        if not (-1e-12 * abs(h) <= tau <= h * (1 + 1e-12)) or not math.isfinite(tau):
            return x_dense
        x = _horner(c0, tau)
        return x if abs(x - x_dense) < 1e-6 * max(1.0, abs(x_dense)) else x_dense
    except Exception:   # a precision whose coefficients numpy cannot hold: the dense output's value
        return x_dense


@dataclass(frozen=True)
class Compiled:
    """A compiled integrator for one structure, and where its parameters and events live."""

    laws: tuple[str, ...]
    inertial: bool
    damped: bool
    n_thresholds: int
    precision: str
    integrator: object
    recorder: Recorder
    dtype: type


def rhs_expressions(laws, inertial: bool, variables, par, exp, log, damped: bool = True):
    """Right-hand sides for ``variables`` = (x, y_1..y_n[, z]) with parameters ``par`` (``Slots``).

    Works on heyoka expressions (the integrator) and on mpmath numbers (the Hopf analysis and the
    reference), so every consumer integrates the same equations. ``damped=False`` leaves out the
    radiation-damping terms (η = 0 exactly).
    """
    n = len(laws)
    x, ys = variables[0], variables[1:1 + n]
    a, k, v_lp, mass = par[Slots.A], par[Slots.K], par[Slots.V_LP], par[Slots.MASS]
    b = [par[Slots.b(n, i)] for i in range(n)]
    dc = [par[Slots.dc(n, i)] for i in range(n)]
    # the velocity-strengthening coefficient of ẋ: a, plus ηV with radiation damping
    resist = a + par[Slots.DAMPING] * exp(x) if damped else a
    ydot = [resolve_state_law(law).rate(x, y, d, exp, log) for law, y, d in zip(laws, ys, dc)]
    state_force = b[0] * ydot[0]
    for bi, yi in zip(b[1:], ydot[1:]):
        state_force = state_force + bi * yi
    load = k * (v_lp - exp(x))
    if not inertial:
        return [(load - state_force) / resist, *ydot]
    z = variables[1 + n]
    xdot = z * exp(-x) / mass
    return [xdot, *ydot, load - resist * xdot - state_force]


def compiled(laws: tuple[str, ...], inertial: bool, n_thresholds: int = 0, precision: str = "double",
             section: bool = False, damped: bool = False) -> Compiled:
    """The cached integrator for (laws, inertia, number of thresholds, precision[, section, damping]).

    ``section=True`` adds a terminal event on the upward crossing of the first threshold (x = ln V_0
    with ẋ > 0): the Poincaré section of the cycle continuation. ``damped=True`` includes the
    radiation-damping terms (η in its parameter slot).
    """
    key = (tuple(laws), bool(inertial), int(n_thresholds), precision, bool(section), bool(damped))
    hit = _CACHE.get(key)
    if hit is None:
        hit = _CACHE[key] = _build(*key)
    return hit


def _build(laws, inertial, n_thresholds, precision, section=False, damped=False) -> Compiled:
    fp_type, dtype = fp_info(precision)
    n = len(laws)
    names = ["x"] + [f"y{i}" for i in range(n)] + (["z"] if inertial else [])
    variables = hy.make_vars(*names)
    if len(names) == 1:
        variables = [variables]
    par = [hy.par[i] for i in range(Slots.size(n, n_thresholds))]
    rhs = rhs_expressions(laws, inertial, variables, par, hy.exp, hy.log, damped=damped)
    recorder = Recorder()
    fp = {"fp_type": fp_type} if fp_type is not None else {}
    nt = [hy.nt_event(rhs[0], recorder.extremum, **fp)]
    for j in range(n_thresholds):
        nt.append(hy.nt_event(variables[0] - par[Slots.threshold(n, j)], recorder.crossing(j), **fp))
    t_ev = []
    if section:
        t_ev.append(hy.t_event(variables[0] - par[Slots.threshold(n, 0)], direction=hy.event_direction.positive, **fp))
    ta = hy.taylor_adaptive(list(zip(variables, rhs)), np.zeros(len(names), dtype=dtype),
                            pars=np.zeros(len(par), dtype=dtype), nt_events=nt, t_events=t_ev,
                            compact_mode=precision == "quad", **fp)
    return Compiled(tuple(laws), bool(inertial), bool(damped), n_thresholds, precision, ta, recorder, dtype)
