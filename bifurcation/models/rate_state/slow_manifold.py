"""Deep stick-slip cycles with inertia: event-split phases, inertial where V is large, slow manifold where it is tiny.

With mass M the slider (variables x = ln V, y_i = ln θ_i, net force z = M V̇; ``_system``) has a fast
mode: z relaxes at the rate a'/(M V) (a' = a + ηV), which at V = e^−25 V_lp is ~1e10 times the
cycle's own rate, so the explicit Taylor integrator stalls in the stick phase. There the inertial term
is a tiny perturbation of the quasi-static force balance, and the solution is attracted to a slow
manifold z = M V ẋ with ẋ = f(x, y) given by the invariance condition

    a' ẋ = k(V_lp − V) − Σ b_i ẏ_i − M V̈,       V̈ = V (ẋ² + ẍ),  ẍ = ∂_x f·ẋ + Σ ∂_{y_i} f·ẏ_i,

an asymptotic series in ε = M V ẋ / a'. Starting from the massless rate f_0 (M = 0), each iteration

    f_{j+1} = f_0 − (M e^x / a') (f_j² + ∂_x f_j · f_j + Σ ∂_{y_i} f_j · ẏ_i)

gains one order of ε (symbolic derivatives, ``heyoka.diff``); ``ORDER`` iterations leave an error
O(ε^{ORDER+1}) in ẋ.

The run alternates compiled Taylor integrators, switched by terminal events:

- **inertial** (x, y, z) while |z|/a' (= ε) is above ``SWITCH``; when ε rises through −``SWITCH`` on the
  way down (V below V_lp/e) it hands over to the same equations with more events (**approach**),
  which switch down once the manifold's own ε (from x, y) is within ±``SWITCH`` and the fast
  transient w = z/a' − ε is below ``TRANSIENT``, or below ``PROJECT`` where projecting it away is
  accurate to ``TRANSIENT`` (whichever becomes true last), to
- **reduced** (x, y) with ẋ = f_ORDER: the massless stick phase plus the inertial correction; when
  M V f/a' rises through +``SWITCH`` on the way up (or falls through −4·``SWITCH``: a descent steepening
  again) it switches back, with z = M e^x f_ORDER(x, y) (on the manifold).

**Fast time.** The inertial and approach phases run in s with dt = M e^x ds (the clock t a state variable):

    dx/ds = z,   dy_i/ds = M e^x ẏ_i,   dz/ds = M e^x (k(V_lp − e^x) − Σ b_i ẏ_i) − a' z,   dt/ds = M e^x.

In physical time (ẋ = z e^{−x}/M) the fast mode's Taylor coefficients grow like (a'/(M V))^n: past
a'/(M V) ~ 1e15 (order ~20) they overflow, and the step is NaN. The slip law's inertial plunge after a
slip is that case: θ does not heal without slip, so the force deficit left by the overshoot, z ≈ −0.05
at b = 0.05, is only recovered by ln V falling by |z|/a ≈ 5 more after V is already e^−30 (measured
overflow at ln V = −29.9, M = 1e-4). In s every coefficient is O(a'^n) at any V, and the deep end of
the plunge (ln V = −55.6 there) costs a few dozen steps.

**Projection.** Below |x| ~ 1 the integrator resolves z only to ~1e-16·max|x, y| (its error control is
relative to the state's largest component): at ln V = −55.6 the transient w stalls at ~7e-14 and never
reaches ``TRANSIENT``. So the switch down moves x along the fast fibre by w (x + z/a' is constant under
the fast dynamics), wrong only by |w| times the coupling of the fibres to the slow flow,
M e^x(|∂_x drive| + Σ b_i |∂_x ẏ_i|)/a'² (drive = k(V_lp − V) − Σ b_i ẏ_i), plus η e^x w²/(2a'): at most
``TRANSIENT`` (measured 3e-56 at the slip law's deep switch, where that coupling is ~1e-43).

Error of the split, per switch: (1) going down, the error of projecting the fast transient away (above;
with |w| ≤ ``TRANSIENT`` it is below that too); the run records it (``switches[i][3]``). (2)
In the reduced phase the neglected order, f_{ORDER+1} − f_ORDER ∝ V^{ORDER+1}, is largest at the switch
and integrates to at most |Δẋ|/((ORDER + 1)|ẋ|) in x (V falls exponentially below it); the run
records its estimate relative to ẋ at both switches (``switches[i][4]``: the last term times the ratio
of the last two). The series is asymptotic (the error of f_N is ~(Cε)^{N+1}, C ≈ 5–10 measured
against the mpmath slow solution). ``SWITCH`` and ``ORDER`` are chosen so that both are below ~1e-16 (docs/rate-state.md, "Deep cycles with mass"): the cost of the inertial phase grows like
1/``SWITCH`` (its steps are limited by the fast rate), the reduced phase costs what the massless one does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import heyoka as hy
import numpy as np

from ._system import Slots, _peak, parameters, rhs_expressions
from .laws import resolve_state_law

__all__ = ["ORDER", "SWITCH", "TRANSIENT", "HybridRun", "deep_cycle", "deep_cycle_point", "hybrid_integrators",
           "manifold_rates", "run_hybrid"]

#: Switch level of ε = M V ẋ / a' between the inertial and the reduced integrator.
SWITCH = 1e-4
#: Iterations of the slow-manifold series (error ~(Cε)^{ORDER+1} in ẋ, C ≈ 5–10: ≤ 1e-15 at ε = SWITCH,
#: measured 8e-17 at the switches of the docs' cases).
ORDER = 4
#: The reduced phase also hands back to the inertial one if ε falls below −ESCAPE·SWITCH (a second,
#: steeper descent): the series is not trusted beyond a few times the level it was entered at.
ESCAPE = 4.0
#: The fast transient left at a switch down, |z/a' − ε| (a shift of x it would have caused): at most this,
#: or ``PROJECT`` with the shift added to x (the switch projects along the fast fibre, x + z/a' − ε) where
#: the projection's own error, |w|·coupling (``_Guard``), is at most ``TRANSIENT``.
TRANSIENT = 1e-16
#: Largest transient w the switch down projects away (w is resolved to ~1e-13 only once |x| ~ 50: the
#: integrator's error control is relative to the state's largest component, so there z, and w, stall at a
#: floor ~ 1e-16·|x|/a' far above ``TRANSIENT``; measured 7e-14 at ln V = −55.6, a = 0.01).
PROJECT = 1e-8

#: Steps per ``propagate_until`` call of ``run_hybrid``. A piece that leaves the integrator's time where it
#: was is a stall: measured on the slip law (a 0.01, b 0.015, Dc 0.01, k 0.1, M 1) in the approach phase
#: with the switch at 1e-5, the manifold's ε sitting at −1.00001e-5 while the transient w = 0.8: steps of
#: 3.7e-14 at s = 8e5 (below its ulp), 560 µs each, for ever (5e6 steps, > 5 min, before this bound).
PIECE = 1000
#: After the transient, each turn of Newton and of the error estimates may take this many times the steps
#: of the turn that found the candidate (the deeper switch's turn costs up to ~10× more inertial steps).
TURN_FACTOR = 50
#: ... and at least this many.
TURN_FLOOR = 20_000
#: Stalls of the approach phase a run recovers from by going on in the plain inertial phase (each costs
#: ``PIECE`` steps; beyond this the run ends "stalled").
RESCUES = 10
#: Turns of the transient search (all within one ``max_steps``). Far below k_c with mass the perturbation
#: grows by only 2π Re λ/|λ| per turn (aging, a 0.01, b 0.015, Dc 0.01, k 0.5, M 1: ~200 turns to the
#: cycle, measured; M = 10: ~300): turns are cheap (~100 steps) until the cycle is deep.
MAX_TURNS = 2000

_CACHE: dict = {}


def manifold_rates(laws, x, ys, par, exp, order: int, damped: bool, diff):
    """[f_0, f_1, …, f_order] (ẋ on the slow manifold, successive orders) and the state rates ẏ_i."""
    rhs0 = rhs_expressions(laws, False, [x, *ys], par, exp, hy.log, damped=damped)
    f0, g = rhs0[0], rhs0[1:]
    resist = par[Slots.A] + par[Slots.DAMPING] * exp(x) if damped else par[Slots.A]
    c = par[Slots.MASS] * exp(x) / resist
    fs = [f0]
    for _ in range(order):
        f = fs[-1]
        along = diff(f, x) * f
        for y, gy in zip(ys, g):
            along = along + diff(f, y) * gy
        fs.append(f0 - c * (f * f + along))
    return fs, g


@dataclass
class _Pair:
    inertial: object
    approach: object
    reduced: object
    tail: object          # cfunc: (f_N − f_{N−1}, f_{N−1} − f_{N−2}, f_N, ε, coupling…) at (x, y)
    order: int
    extrema: "_Extrema"


def hybrid_integrators(laws: tuple[str, ...], damped: bool, order: int = ORDER, compact: bool = True) -> _Pair:
    """The compiled inertial and reduced integrators (cached per laws, damping, order)."""
    if order < 2:
        raise ValueError("the slow-manifold series needs order >= 2 (its tail is estimated from two terms)")
    key = (tuple(laws), bool(damped), int(order), bool(compact))
    hit = _CACHE.get(key)
    if hit is not None:
        return hit
    n = len(laws)
    names = ["x"] + [f"y{i}" for i in range(n)]
    v = hy.make_vars(*names, "z", "t")
    x, ys, z, clock = v[0], list(v[1:1 + n]), v[1 + n], v[2 + n]
    # pars: the engine's slots (the section ln V_lp the one threshold), then the switch level s and the
    # physical time at which an inertial segment is to stop (its clock is a state variable, below)
    size = Slots.size(n, 1)
    par = [hy.par[i] for i in range(size + 2)]
    s_par, ln_lp, t_stop = par[size], par[Slots.threshold(n, 0)], par[size + 1]
    resist = par[Slots.A] + par[Slots.DAMPING] * hy.exp(x) if damped else par[Slots.A]

    fs, g = manifold_rates(laws, x, ys, par, hy.exp, order, damped, hy.diff)
    f = fs[order]
    eps = par[Slots.MASS] * hy.exp(x) * f / resist        # ε on the manifold, from (x, y) alone
    rec = _Extrema(n)

    # The inertial phases run in the fast time s, dt = M e^x ds (module docstring, "Fast time"): the
    # physical-time right-hand sides times M e^x, so no e^{−x}, and the fast mode decays at the rate a'
    # in s whatever V is (in t it is a'/(M V), whose Taylor coefficients overflow once it passes ~1e15).
    mv = par[Slots.MASS] * hy.exp(x)
    g_t = [resolve_state_law(law).rate(x, y, par[Slots.dc(n, i)], hy.exp, hy.log) for i, (law, y) in enumerate(zip(laws, ys))]
    drive = par[Slots.K] * (par[Slots.V_LP] - hy.exp(x))                 # k(V_lp − V) − Σ b_i ẏ_i
    for i, gy in enumerate(g_t):
        drive = drive - par[Slots.b(n, i)] * gy
    rhs_i = [z, *[mv * gy for gy in g_t], mv * drive - resist * z, mv]
    w = z / resist - eps                                   # the fast transient, in units of x
    guard = _Guard(n)
    pos, neg = hy.event_direction.positive, hy.event_direction.negative
    # plain inertial: only z-based events (the series ε is meaningless, and huge, where V is large)
    ev_i = [hy.t_event(z / resist + s_par, direction=pos, callback=_Below(n)),    # → approach
            hy.t_event(x - ln_lp, direction=pos),                                # section
            hy.t_event(clock - t_stop, direction=pos)]                           # the run's end
    inertial = hy.taylor_adaptive(list(zip([x, *ys, z, clock], rhs_i)), np.zeros(n + 3), pars=np.zeros(len(par)),
                                  t_events=ev_i, nt_events=[hy.nt_event(z, rec)])
    # the approach to the manifold: the same equations, switched down when the manifold's ε is small
    # and the fast transient is gone (the last of the two conditions to become true fires)
    ev_a = [hy.t_event(eps + s_par, direction=pos, callback=guard),
            hy.t_event(w - TRANSIENT, direction=neg, callback=guard),
            hy.t_event(w + TRANSIENT, direction=pos, callback=guard),
            hy.t_event(w - PROJECT, direction=neg, callback=guard),
            hy.t_event(w + PROJECT, direction=pos, callback=guard),
            hy.t_event(z / resist + ESCAPE * s_par, direction=neg),              # steeper again → inertial
            hy.t_event(x - (ln_lp - 1), direction=pos),                          # back above V_lp/e → inertial
            hy.t_event(x - ln_lp, direction=pos),                                # section (not reached)
            hy.t_event(clock - t_stop, direction=pos)]                           # the run's end
    approach = hy.taylor_adaptive(list(zip([x, *ys, z, clock], rhs_i)), np.zeros(n + 3), pars=np.zeros(len(par)),
                                  t_events=ev_a, nt_events=[hy.nt_event(z, rec)], compact_mode=compact)

    ev_r = [hy.t_event(eps - s_par, direction=pos),                  # switch up
            hy.t_event(eps + ESCAPE * s_par, direction=neg),         # steeper again
            hy.t_event(x - ln_lp, direction=pos)]                    # section
    reduced = hy.taylor_adaptive(list(zip([x, *ys], [f, *g])), np.zeros(n + 1), pars=np.zeros(len(par) - 1),
                                 t_events=ev_r, nt_events=[hy.nt_event(f, rec)], compact_mode=compact)
    # the last two terms of the series (their ratio estimates the next, neglected one), ẋ and ε
    # and the coupling of the fast fibres to the slow flow (x + z/a' drifts at M e^x ∂_x(drive)/a'² per
    # unit of transient, and y at M e^x ∂_x ẏ_i/a', which moves x by b_i/a' times that): the projection's
    # error per unit of w (``_Guard``)
    drive = par[Slots.K] * (par[Slots.V_LP] - hy.exp(x))
    for i, gy in enumerate(g):
        drive = drive - par[Slots.b(n, i)] * gy
    mv2 = par[Slots.MASS] * hy.exp(x) / (resist * resist)
    coupling = [mv2 * hy.diff(drive, x)] + [mv2 * par[Slots.b(n, i)] * hy.diff(gy, x) for i, gy in enumerate(g)]
    tail = hy.cfunc([fs[order] - fs[order - 1], fs[order - 1] - fs[order - 2], f, eps, *coupling], [x, *ys],
                    compact_mode=compact)
    guard.tail = tail
    hit = _CACHE[key] = _Pair(inertial, approach, reduced, tail, order, rec)
    return hit


class _Extrema:
    """Velocity extrema (ẋ = 0) of both integrators at their exact times, in the run's time."""

    def __init__(self, n: int) -> None:
        self.base, self.out, self.n = 0.0, [], n

    def __call__(self, ta, time, d_sgn) -> None:
        ta.update_d_output(time)
        x = _peak(ta, time, float(ta.d_output[0]))
        kind = 1 if d_sgn < 0 else -1     # ẋ (or z) decreasing through 0 at a maximum of V
        if self.out and self.out[-1][2] == kind:
            return                        # rounding noise of a flat extremum, not a new one
        # (the inertial phases run in fast time: their physical time is the clock, the last variable)
        t = float(ta.d_output[self.n + 2]) if ta.state.size == self.n + 3 else float(time)
        self.out.append((self.base + t, x, kind))

    def __deepcopy__(self, memo):
        return self


class _Below:
    """Leave the plain inertial integrator for the approach only below V_lp/e (ε = z/a' also passes
    −s near the top of a spike)."""

    def __init__(self, n: int) -> None:
        self.n = n

    def __call__(self, ta, d_sgn) -> bool:
        return not ta.state[0] < ta.pars[Slots.threshold(self.n, 0)] - 1.0

    def __deepcopy__(self, memo):
        return self


class _At:
    """A stand-in for an integrator (state, pars) to ask ``_Guard`` about a point outside an event."""

    def __init__(self, state, pars) -> None:
        self.state, self.pars = state, pars


class _Guard:
    """Switch down (return False: stop) only where all three hold: V below V_lp/e, |ε| on the manifold at
    most the switch level, and the fast transient |z/a' − ε| at most ``TRANSIENT`` (each event checks
    the other two, so the switch happens when the last of them becomes true)."""

    def __init__(self, n: int) -> None:
        self.n, self.tail = n, None

    def __call__(self, ta, d_sgn) -> bool:
        n, u, p = self.n, ta.state, ta.pars
        if not u[0] < p[Slots.threshold(n, 0)] - 1.0:
            return True
        eps, w, error = _transient(self.tail, u, p, n)
        # (2× and 1e-6: an event's root is located to the time's rounding, its value to ~1e-9 of the level)
        small = abs(w) <= 2 * TRANSIENT or (abs(w) <= PROJECT * (1 + 1e-6) and error <= TRANSIENT)
        return not (abs(eps) <= p[Slots.size(n, 1)] * (1 + 1e-6) and small)

    def __deepcopy__(self, memo):
        return self


def _transient(tail, u, p, n):
    """(ε on the manifold, transient w = z/a' − ε, error of projecting w away) at the inertial state u.

    Along a fast fibre x + z/a' is constant but for the slow flow: projecting onto the manifold moves x
    by w, wrong by |w| times the coupling (summed with its signs dropped) plus the damping's curvature
    η e^x w²/(2a') (a' depends on x)."""
    out = tail(u[:1 + n], pars=p[:tail.nparams])
    eps = out[3]
    resist = p[Slots.A] + p[Slots.DAMPING] * math.exp(u[0])
    w = u[1 + n] / resist - eps
    error = abs(w) * float(np.sum(np.abs(out[4:]))) + p[Slots.DAMPING] * math.exp(u[0]) * w * w / (2 * resist)
    return float(eps), float(w), error


@dataclass
class HybridRun:
    """One hybrid run: section crossings, velocity extrema, switches, and why it stopped."""

    status: str                                  # "ok", "section", "step-budget", "stalled", "failed"
    t: float = 0.0
    phase: str = "inertial"
    state: np.ndarray = field(default_factory=lambda: np.zeros(0))   # (x, y…[, z]) at the end
    sections: list = field(default_factory=list)     # (t, phase, state) at upward V = V_lp
    extrema: list = field(default_factory=list)      # (t, ln V, +1 max / −1 min)
    switches: list = field(default_factory=list)     # (t, "down"/"up", ln V, transient shift, series tail)
    steps: int = 0
    inertial_steps: int = 0
    message: str = ""


def run_hybrid(spec, v_lp: float, phase: str, state, t_end: float, *, stop_at_sections: int = 0,
               switch: float = SWITCH, order: int = ORDER, max_steps: int = 5_000_000) -> HybridRun:
    """Integrate ``spec`` (inertial) from ``state`` in ``phase`` ("inertial": x, y…, z; "reduced": x, y…)
    for time ``t_end``, switching phases at ε = ±``switch`` (module docstring). Stops at the
    ``stop_at_sections``-th upward crossing of V = V_lp if > 0 (status "section")."""
    pair = hybrid_integrators(spec.state_law, spec.damped, order)
    n = spec.n_states
    ln_lp = math.log(v_lp)
    pars = np.array(parameters(spec, spec.k, v_lp, [ln_lp]) + [switch, t_end], dtype=float)
    out = HybridRun("ok", phase=phase)
    done: list = []        # durations of the finished segments (their sum, math.fsum, is the run's time)
    u = np.array(state, dtype=float)
    rec = pair.extrema
    rec.out = out.extrema
    fresh, rescues = True, 0
    while True:
        ta = {"inertial": pair.inertial, "approach": pair.approach, "reduced": pair.reduced}[phase]
        fast = phase != "reduced"   # fast time s, the physical time a state variable (the clock)
        if fresh:   # a new segment (the start or a switch); after a section event the segment goes on
            ta.time = 0.0
            ta.state[:] = np.concatenate([u, [0.0]]) if fast else u
            pars[-1] = t_end - math.fsum(done)
            ta.pars[:] = pars[:len(ta.pars)]
            ta.reset_cooldowns()
            rec.base = math.fsum(done)
        # bounded by the clock's terminal event (fast phases) or t_end, and the step budget, taken in pieces
        # of PIECE steps: a piece that does not move the integrator's time is a stall (below)
        limit = 1e300 if fast else t_end - rec.base
        while True:
            before = float(ta.time)
            res = ta.propagate_until(limit, max_steps=max(min(PIECE, max_steps - out.steps), 1))
            outcome, steps = res[0], res[3]
            out.steps += steps
            if fast:
                out.inertial_steps += steps
            if outcome != hy.taylor_outcome.step_limit or out.steps >= max_steps:
                break
            if not abs(float(ta.time) - before) > 1e-12 * abs(before):
                outcome = "stalled"
                break
        local = float(ta.state[-1]) if fast else float(ta.time)
        t = math.fsum([*done, local])
        u = np.array(ta.state[:-1] if fast else ta.state, dtype=float)
        fresh = False
        if outcome == "stalled" and phase == "approach" and rescues < RESCUES:
            # the approach only watches for the switch down: go on with the plain inertial equations (the
            # same ones, without its events) and give up on switching during this descent
            rescues += 1
            done.append(local)
            fresh, phase = True, "inertial"
            continue
        ev = -int(outcome) - 1 if outcome != "stalled" else -1   # a terminal event i stops with outcome −(i + 1)
        if outcome != "stalled" and (outcome == hy.taylor_outcome.time_limit
                                     or (fast and ev == {"inertial": 2, "approach": 8}[phase])):
            out.status, out.t, out.phase, out.state = "ok", t, phase, u
            return out
        if 0 <= ev < 16:
            section = ev == {"inertial": 1, "approach": 7, "reduced": 2}[phase]
            if section:
                out.sections.append((t, phase, u.copy()))
                if stop_at_sections and len(out.sections) >= stop_at_sections:
                    out.status, out.t, out.phase, out.state = "section", t, phase, u
                    return out
                continue
            done.append(local)
            fresh = True
            if phase == "inertial":   # near the manifold: watch for the switch
                # (already on it — a descent slow enough that the transient is gone — switch now: the
                # approach's crossing events would not fire from where they already are)
                phase = "approach" if pair.approach.t_events[0].callback(_At(u, pars), 0) else "switch"
            elif phase == "approach" and ev in (5, 6):   # not there after all
                phase = "inertial"
            else:
                phase = "switch" if phase == "approach" else phase
            if phase == "switch":   # down: drop z, projecting the transient it leaves onto x
                x, ys, z = u[0], u[1:1 + n], u[1 + n]
                _, w, error = _transient(pair.tail, u, pars, n)
                x = x + w
                tail, f = _tail(pair, np.concatenate([[x], ys]), pars)
                out.switches.append((t, "down", x, error, tail))
                kind = 1 if z > 0 else -1
                if (z < 0) != (f < 0) and z != 0 and (not rec.out or rec.out[-1][2] != kind):
                    # ẋ changes sign within the dropped transient: the extremum is where it ends, at x + w
                    rec.out.append((t, float(x), kind))
                phase, u = "reduced", np.concatenate([[x], ys])
            elif phase == "reduced":  # up: z on the manifold
                x = u[0]
                tail, f = _tail(pair, u, pars)
                out.switches.append((t, "up", x, 0.0, tail))
                phase, u = "inertial", np.concatenate([u, [spec.mass * math.exp(x) * f]])
            continue
        status = "stalled" if outcome == "stalled" else "step-budget" if out.steps >= max_steps else "failed"
        out.status, out.t, out.phase, out.state = status, t, phase, u
        why = {hy.taylor_outcome.err_nf_state: "non-finite state (a step overflowed: e^±ln V out of range)",
               hy.taylor_outcome.step_limit: "step budget spent",
               "stalled": f"the integrator stalled ({PIECE} steps did not move its time: an event re-firing at one point)"
               }.get(outcome, str(outcome))
        last_x = float(out.extrema[-1][1]) if out.extrema else float("nan")
        out.message = f"{why} at t = {t:.6g} in the {phase} phase (last ln V extremum {last_x:.4g})"
        return out


def _tail(pair, xy, pars):
    """(estimated neglected term relative to ẋ, ẋ) on the manifold at (x, y): the next term of the series
    as the last one times the ratio of the last two (they shrink by ~ε per order)."""
    last, before, f = pair.tail(xy, pars=pars[:pair.tail.nparams])[:3]
    ratio = abs(last / before) if before != 0 else 0.0
    return abs(last) * ratio / max(abs(f), 1e-300), float(f)


#: Largest series tail (relative, at a switch) and transient shift (in ln V) a cycle may carry and still be
#: vouched for: far above what SWITCH and ORDER give (≤ 1e-16), far below the period's goal (1e-10).
TRUST_TAIL = 1e-13


def _turn(spec, v_lp, phase, w, period_guess, ledger=None, **kw):
    """One turn of the return map from the section point (phase, w): (w', period, run) or None.
    ``ledger`` ([steps, why]), if given, gets the steps added and the reason of a failure."""
    x_lp = math.log(v_lp)
    start = np.concatenate([[x_lp], w])
    t_max = 50 * period_guess
    r = run_hybrid(spec, v_lp, phase, start, t_max, stop_at_sections=1, **kw)
    if ledger is not None:
        ledger[0] += r.steps
    if r.status == "section" and r.t < 1e-9 * period_guess:   # the start itself, seen as a crossing
        r = run_hybrid(spec, v_lp, phase, start, t_max, stop_at_sections=2, **kw)
        if ledger is not None:
            ledger[0] += r.steps
    if r.status != "section" or r.phase != phase:
        if ledger is not None:
            ledger[1:] = [r.message or f"status {r.status}"]
        return None
    return r.state[1:], r.t, r


def deep_cycle(spec, v_lp: float, period0: float, *, max_turns: int = MAX_TURNS, max_steps: int = 5_000_000,
               progress=None):
    """The attracting cycle of an inertial ``spec`` by the event-split integrator (module docstring):
    a ``cycle.CycleResult``, with status "limit-cycle" only where the split vouches for it. Started
    from steady sliding with ln V raised by ``attractor.PERTURBATION``; ``period0`` (the linear period
    2π/ω_c) bounds each turn (10⁴ of them) and scales the start-on-section test.

    Bounded: ``max_steps`` Taylor steps in all (transient, Newton and error turns), each turn after the
    transient at most ``TURN_FACTOR`` times the candidate turn's steps (≥ ``TURN_FLOOR``), and a stalled
    integrator stops its turn (``PIECE``). ``progress(text)``, if given, is called once per turn."""
    return deep_cycle_point(spec, v_lp, period0, max_turns=max_turns, max_steps=max_steps, progress=progress)[0]


def deep_cycle_point(spec, v_lp: float, period0: float, *, max_turns: int = MAX_TURNS, max_steps: int = 5_000_000,
                     progress=None):
    """(``CycleResult``, section phase, section point w = (ln θ_i…[, z])) of ``deep_cycle``; w is None
    where there is no cycle."""
    from .attractor import BLOWUP, CANDIDATE_TOL, MIN_AMPLITUDE, PERTURBATION
    from .cycle import CycleResult

    n = spec.n_states
    x_lp = math.log(v_lp)
    y_star = [math.log(law.steady_factor * d / v_lp) for law, d in zip(spec.laws, spec.dc)]
    u = np.array([x_lp + PERTURBATION, *y_star, 0.0])
    phase, steps, last = "inertial", 0, None
    for turn in range(max_turns):
        budget = max(max_steps - steps, 1)   # one budget for the whole transient search
        r = run_hybrid(spec, v_lp, phase, u, 1e4 * period0, stop_at_sections=1, max_steps=budget)
        if r.status == "section" and r.t < 1e-9 * period0:   # the start itself, on the section
            r = run_hybrid(spec, v_lp, phase, u, 1e4 * period0, stop_at_sections=2, max_steps=budget)
        steps += r.steps
        if progress is not None:
            progress(f"event-split transient: turn {turn + 1}, {r.status} at t = {r.t:.6g} in the {r.phase} "
                     f"phase, {steps} of {max_steps} steps")
        top = max([e[1] for e in r.extrema] + [float(r.state[0])])
        if top - x_lp > BLOWUP:
            return _none("not-resolved", f"ln V/V_lp passed {BLOWUP:g} (the event-split integrator vouches "
                               "for bounded cycles only)", steps=steps)
        if r.status != "section":
            return _none("not-resolved", r.message or f"status {r.status}", steps=steps)
        phase, u = r.phase, r.state.copy()
        w = u[1:]
        if last is not None and last[0] == phase:
            scale = np.maximum(np.abs(w), 1.0 if phase == "reduced" else np.r_[np.ones(n), [abs(w[-1]) or 1.0]])
            if np.max(np.abs(w - last[1]) / scale) < CANDIDATE_TOL:
                break
        last = (phase, w.copy())
    else:
        return _none("not-resolved", f"no cycle within {max_turns} turns of the event-split integrator",
                           steps=steps)
    # Newton on the return map P(w) − w in the section's phase
    scale = np.maximum(np.abs(w), 1.0)
    if phase == "inertial":
        scale[-1] = max(abs(w[-1]), 1e-300)
    period = r.t
    # each later turn: a multiple of what the candidate's turn took, and what is left of the whole budget
    # (``steps`` stays the transient's, as the result reports it; the ledger counts them all)
    per_turn = max(TURN_FACTOR * r.steps, TURN_FLOOR)
    ledger = [steps, ""]

    def budget():
        left = max_steps - ledger[0]
        if left <= 0:
            ledger[1:] = [f"step budget of {max_steps} spent"]
            raise _Lost
        return min(per_turn, left)

    def G(v):
        got = _turn(spec, v_lp, phase, v, period, ledger, max_steps=budget())
        if progress is not None:
            progress(f"event-split Newton: {ledger[0]} of {max_steps} steps")
        if got is None:
            raise _Lost
        return got[0] - v, got

    try:
        for _ in range(10):
            g, got = G(w)
            hs = 1e-7 * scale
            J = np.array([(G(w + hs[j] * e)[0] - G(w - hs[j] * e)[0]) / (2 * hs[j])
                          for j, e in enumerate(np.eye(w.size))]).T
            dw = np.linalg.solve(J, -g)
            w = w + dw
            if np.max(np.abs(dw) / scale) < 1e-12:
                break
        else:
            return _none("not-resolved", "Newton on the event-split return map did not converge", steps=steps)
        g, (w1, period, run) = G(w)
        mult = float(np.max(np.abs(np.linalg.eigvals(J + np.eye(w.size)))))
        # error estimates: a second turn (independent rounding), and the method's own bias: one turn with
        # the switch 10× deeper and one more order of the series
        second = _turn(spec, v_lp, phase, w1, period, ledger, max_steps=budget())
        deeper = _turn(spec, v_lp, phase, w, period, ledger, switch=SWITCH / 10, order=ORDER + 1,
                       max_steps=budget()) if second is not None else None
    except (_Lost, np.linalg.LinAlgError):
        why = f" ({ledger[1]})" if ledger[1] else ""
        return _none("not-resolved", f"the event-split return map lost the cycle during Newton{why}", steps=steps)
    if second is None or deeper is None:
        return _none("not-resolved", f"the cycle could not be re-run for its error estimate ({ledger[1]})",
                     steps=steps)

    def extremes(rr):
        xs = [x_lp] + [e[1] for e in rr.extrema]
        return max(xs) - x_lp, min(xs) - x_lp

    top, bottom = extremes(run)
    tails = [s[4] for s in run.switches] + [0.0]
    shifts = [s[3] for s in run.switches] + [0.0]
    if top - bottom < MIN_AMPLITUDE or mult >= 1:
        return _none("not-resolved", "the event-split fixed point is not an attracting cycle", steps=steps)
    if max(tails) > TRUST_TAIL or max(shifts) > TRUST_TAIL:
        return _none("not-resolved", f"the slow-manifold switch is not accurate here (series tail "
                           f"{max(tails):.2g}, transient {max(shifts):.2g} at the switches)", steps=steps)
    ulp = 4 * 2.220446049250313e-16

    def err(v, *others):
        return max([abs(v - o) for o in others] + [ulp * abs(v)])

    t2, t3 = second[1], deeper[1]
    e2, e3 = extremes(second[2]), extremes(deeper[2])
    n_down = sum(1 for s in run.switches if s[1] == "down")
    msg = (f"event-split integrator (inertial above |ε| = {SWITCH:g}, slow manifold of order {ORDER} below; "
           f"{n_down} descent(s) per turn, {run.inertial_steps} inertial + {run.steps - run.inertial_steps} "
           f"reduced steps; series tail ≤ {max(tails):.1g}, transient ≤ {max(shifts):.1g})")
    return CycleResult("limit-cycle", msg, period, err(period, t2, t3), top, err(top, e2[0], e3[0]),
                       bottom, err(bottom, e2[1], e3[1]), v_lp * period, v_lp * err(period, t2, t3), mult,
                       steps), phase, w


def _none(status, message, steps=0):
    from .cycle import CycleResult

    return CycleResult(status, message, steps=steps), None, None


class _Lost(Exception):
    pass
