"""The rate-and-state Burridge–Knopoff chain as one heyoka Taylor integrator per structure.

Block j (j = 0..N−1), normal stress 1, friction μ_j = μ0 + a ln V_j + b ln(θ_j/(c Dc)) (the slider's
convention, rate_state/laws.py), loading spring k to a plate at V_lp, neighbour springs ℓ²k, radiation
damping η:

    M V̇_j = k(δ_lp − δ_j) + ℓ²k(δ_{j+1} − 2δ_j + δ_{j−1}) − μ_j − η V_j      (free ends: δ_{−1} ≡ δ_0,
                                                                               δ_N ≡ δ_{N−1}; periodic)

Variables as the slider's (docs/rate-state.md): x_j = ln V_j, y_j = ln θ_j and, with inertia, the net
force z_j = M V̇_j; plus P = Σ_j δ_j (reset between events: the potency of an event is its change).
Differentiating the force balance (μ̇ = a ẋ + b ẏ):

    quasi-dynamic (M = 0):  (a + η e^{x_j}) ẋ_j = k(V_lp − e^{x_j}) + ℓ²k Δe^{x}_j − b ẏ_j
    inertial (M > 0):       ẋ_j = z_j e^{−x_j}/M,  ż_j = k(V_lp − e^{x_j}) + ℓ²k Δe^{x}_j − (a + η e^{x_j}) ẋ_j − b ẏ_j
    state:                  ẏ_j = law.rate(x_j, y_j; Dc)      (the slider's rate_state.laws, imported)
    potency:                Ṗ = Σ_j e^{x_j}

With M = 0 and η = 0 this is the slider's quasi-static system per block, which blows up in finite time
below the critical stiffness: such a run ends with status ``nonfinite``/``no-stop``, as the slider's
"stalled". The terms that are zero by structure (coupling for N = 1, damping for η = 0) are left out of
the expressions, so N = 1 compiles the slider's own right-hand side (plus P).

Events (non-terminal, located by heyoka's polynomial root finding on each step): x_j = ln v_th in
both directions (block j starts or stops slipping) and ẋ_j = 0 downwards (a velocity maximum).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import heyoka as hy
import numpy as np

from ..rate_state.laws import StateLaw, resolve_state_law

__all__ = ["PARAMETERS", "Compiled", "Layout", "compiled", "rhs_expressions"]

#: Runtime parameters, by name (the heyoka ``par[i]`` in this order; ``Layout.par``).
PARAMETERS = ("a", "b", "dc", "k", "ell2", "v_lp", "mass", "eta", "ln_v_th")

#: The velocity-maximum event is ẋ_j times this constant. heyoka sets each step from the Taylor
#: coefficients of the state *and of every event equation*; ẋ_j's are x_j's times (order + 1)/h, so at
#: scale 1 the maxima shortened the steps (+20 % of steps at N = 16, ℓ = 3). A constant factor moves no
#: root, and a maximum's value V_j = e^{x_j} is first-order insensitive to its time (ẋ_j = 0 there); the
#: crossings of v_th, the times the catalog is made of, stay set by x_j's own coefficients. Measured at
#: N = 16: 10 461 steps for 60 events against 12 559 at scale 1 and 10 028 without maxima; every
#: max_velocity still agrees with the mpmath references (tests/test_rs_chain.py).
MAXIMUM_EVENT_SCALE = 1e-12

#: Above this many blocks heyoka's compact mode (one compiled function per kind of operation, looped over
#: the blocks) instead of the fully unrolled Taylor step. Measured (aging, ℓ = 3, η = 1e-3, scaled maxima,
#: order 20, µs a step of a run): N = 16 13.5 unrolled against 19.0 compact (compile 3.5 s CPU, once per
#: machine: heyoka caches compiled code on disk); N = 32 26.6 against 36.8 (12 s); N = 64 103 against 75
#: (67 s): past a few dozen blocks the unrolled step no longer fits the caches.
COMPACT_ABOVE = 16

#: heyoka's default tolerance (the engine's exact default): double epsilon.
EXACT_TOL = float(np.finfo(float).eps)

_CACHE: dict = {}


@dataclass(frozen=True)
class Layout:
    """Where block j's variables and each named parameter live in the integrator (no bare indices)."""

    n: int
    inertial: bool

    def x(self, j: int) -> int:
        return j

    def y(self, j: int) -> int:
        return self.n + j

    def z(self, j: int) -> int:
        return 2 * self.n + j

    @property
    def potency(self) -> int:
        return (3 if self.inertial else 2) * self.n

    @property
    def size(self) -> int:
        return self.potency + 1

    @staticmethod
    def index(name: str) -> int:
        return PARAMETERS.index(name)

    def names(self) -> list[str]:
        out = [f"x{j}" for j in range(self.n)] + [f"y{j}" for j in range(self.n)]
        if self.inertial:
            out += [f"z{j}" for j in range(self.n)]
        return out + ["P"]


def _laplacian(v: list, periodic: bool) -> list:
    """(Δv)_j = v_{j+1} − 2v_j + v_{j−1} with free (mirror) or periodic ends."""
    n = len(v)
    if n == 1:
        return [None]
    out = []
    for j in range(n):
        left = v[j - 1] if j > 0 else (v[n - 1] if periodic else None)
        right = v[j + 1] if j < n - 1 else (v[0] if periodic else None)
        if n == 2 and periodic:   # both neighbours are the same block: two springs to it
            out.append(2 * (v[1 - j] - v[j]))
            continue
        terms = [w - v[j] for w in (left, right) if w is not None]
        out.append(terms[0] if len(terms) == 1 else terms[0] + terms[1])
    return out


def rhs_expressions(law: StateLaw, layout: Layout, variables, par: dict, exp, log, *, periodic: bool,
                    damped: bool) -> list:
    """Right-hand sides of ``variables`` (in ``layout`` order) with named parameters ``par``.

    Works on heyoka expressions and on floats (the numba/LSODA baseline checks its own against it).
    """
    n = layout.n
    xs = [variables[layout.x(j)] for j in range(n)]
    ys = [variables[layout.y(j)] for j in range(n)]
    v = [exp(x) for x in xs]
    ydot = [law.rate(x, y, par["dc"], exp, log) for x, y in zip(xs, ys)]
    lap = _laplacian(v, periodic)
    drive = []
    for j in range(n):
        load = par["k"] * (par["v_lp"] - v[j])
        if lap[j] is not None:
            load = load + par["ell2"] * par["k"] * lap[j]
        drive.append(load)
    if layout.inertial:
        zs = [variables[layout.z(j)] for j in range(n)]
        xdot = [z * exp(-x) / par["mass"] for z, x in zip(zs, xs)]
        resist = [(par["a"] + par["eta"] * v[j]) if damped else par["a"] for j in range(n)]
        zdot = [drive[j] - resist[j] * xdot[j] - par["b"] * ydot[j] for j in range(n)]
        rest = zdot
    else:
        xdot = [((drive[j] - par["b"] * ydot[j]) / (par["a"] + par["eta"] * v[j])) if damped
                else (drive[j] - par["b"] * ydot[j]) / par["a"] for j in range(n)]
        rest = []
    total = v[0]
    for w in v[1:]:
        total = total + w
    return [*xdot, *ydot, *rest, total]


class Recorder:
    """Threshold crossings and velocity maxima of one step, buffered as (time, kind, block).

    The callbacks record only when and what: the state at a root is read later (``state_at``, from the
    step callback, while the step's Taylor polynomials are still the integrator's dense output) and only
    where the catalog needs it, an event's first up-crossing and last down-crossing and the maxima of
    blocks above v_th (a dense output and its copy per root were ~4 µs, most of them for roots the catalog
    does not use). The dense output is read through a view bound once per integrator (``ta.d_output``
    builds a new array on each access, ~0.6 µs)."""

    def __init__(self) -> None:
        self.buffer: list = []
        self._ta = self._out = None

    def __deepcopy__(self, memo) -> "Recorder":
        return self   # heyoka deep-copies callbacks; every copy must record here

    def bind(self, ta) -> None:
        if ta is not self._ta:
            self._ta, self._out = ta, ta.d_output

    def state_at(self, time: float) -> np.ndarray:
        """The state at ``time`` inside the last step (a view, overwritten by the next call)."""
        self._ta.update_d_output(time)
        return self._out

    def crossing(self, j: int):
        buffer = self.buffer

        def record(ta, time, d_sgn):
            buffer.append((float(time), 1 if d_sgn > 0 else -1, j))
        return _Callback(record)

    def maximum(self, j: int):
        buffer = self.buffer

        def record(ta, time, d_sgn):
            buffer.append((float(time), 0, j))
        return _Callback(record)


class _Callback:
    def __init__(self, fn) -> None:
        self.fn = fn

    def __call__(self, ta, time, d_sgn) -> None:
        self.fn(ta, time, d_sgn)

    def __deepcopy__(self, memo) -> "_Callback":
        return self


@dataclass(frozen=True)
class Compiled:
    """A compiled integrator for one structure and what its callbacks record into."""

    law: StateLaw
    layout: Layout
    periodic: bool
    damped: bool
    integrator: object
    recorder: Recorder


def compiled(law: str, n: int, *, inertial: bool, periodic: bool, damped: bool, maxima: bool = True,
             tol: float = EXACT_TOL) -> Compiled:
    """The cached integrator for (state law, N, inertia, ends, damping, velocity-maximum events, tolerance).

    ``tol`` is heyoka's: it sets the Taylor order (20 at double epsilon, 15 at 1e-12), not the step count
    (set by the solution's radius of convergence)."""
    key = (resolve_state_law(law).name, int(n), bool(inertial), bool(periodic), bool(damped), bool(maxima),
           float(tol))
    hit = _CACHE.get(key)
    if hit is None:
        hit = _CACHE[key] = _build(*key)
    return hit


def _build(law_name, n, inertial, periodic, damped, maxima, tol) -> Compiled:
    law = resolve_state_law(law_name)
    layout = Layout(n, inertial)
    names = layout.names()
    variables = hy.make_vars(*names)
    par = {name: hy.par[i] for i, name in enumerate(PARAMETERS)}
    rhs = rhs_expressions(law, layout, variables, par, hy.exp, hy.log, periodic=periodic, damped=damped)
    recorder = Recorder()
    nt = [hy.nt_event(variables[layout.x(j)] - par["ln_v_th"], recorder.crossing(j)) for j in range(n)]
    if maxima:
        nt += [hy.nt_event(MAXIMUM_EVENT_SCALE * rhs[layout.x(j)], recorder.maximum(j),
                           direction=hy.event_direction.negative) for j in range(n)]
    ta = hy.taylor_adaptive(list(zip(variables, rhs)), np.zeros(len(names)), pars=np.zeros(len(PARAMETERS)),
                            nt_events=nt, compact_mode=n > COMPACT_ABOVE, tol=tol)
    return Compiled(law, layout, periodic, damped, ta, recorder)


def steady_state(law: StateLaw, v: float, dc: float) -> tuple[float, float]:
    """(x, y) of steady sliding at velocity ``v``: θ = c Dc / V."""
    return math.log(v), math.log(law.steady_factor * dc / v)
