"""Where a perturbed steady slide goes: steady sliding, a limit cycle, unbounded growth, or not resolved.

One point of the ``rate-state`` model (``model.py``): a slider (``SliderSpec`` at k = κ k_c) started at
steady sliding with ln V raised by ``PERTURBATION`` (θ_i and the net force at their steady values) is
integrated by the engine's compiled Taylor integrator (``_system.compiled``; non-terminal events at
V = V_lp give the state on the section x = ln V_lp, crossed upwards, at its exact times). After each
stretch of ``CHUNK_PERIODS`` linear periods 2π/ω_c:

- **steady sliding** when the state is within ``STEADY_TOL`` of the steady state (every component:
  ln V, ln θ_i, and the net force over Σb − a) and closer than at the previous check: at that
  distance the nonlinear terms are 1e-16 of the linear ones, so a decay that holds there goes on;
- **limit cycle** when two successive section states agree to ``CANDIDATE_TOL`` and Newton on the
  return map (``continuation.ReturnMap``; DP by central differences) converges to a fixed point whose
  Floquet multipliers are all inside the unit circle and which the run's last section state is
  within ``BASIN_TOL`` of (so the run is on its way there), spanning more than ``MIN_AMPLITUDE`` in
  ln V (not the trace of the steady state on the section); the outputs are that cycle's period,
  max and min ln V over it and slip V_lp·T, and its largest |multiplier|;
- **limit cycle, solved directly** when the approach is too slow for that (a multiplier ρ near 1, next
  to a Hopf point): the last ``SLOW_TURNS`` steps between section states shrink steadily by ``SLOW_RHO``
  or slower per turn and would not reach ``CANDIDATE_TOL`` within the budget (or the budget is spent).
  Full Newton on the return map from the last section state; accepted only if it converges, the fixed
  point is attracting (every multiplier inside the unit circle), has amplitude, and the run's last
  section states approach it monotonically at the rate its largest multiplier predicts (within
  ``SLOW_MATCH``·(1 − ρ)) — the run is in its linear neighbourhood, on its way there. A cycle that is not
  attracting is said (in the message of a not-resolved point), never given as the attractor. A run that
  ends its budget still growing steadily away from steady sliding (ρ ≥ 0.9995: the perturbation grows by
  ~(1 − ρ)/2 per turn) starts Newton at the amplitude a normal-form fit of its growth predicts, and the
  cycle is accepted if attracting and the return map takes the segment from the run's last state to it
  towards it (``_Direct._growing``);
- **unbounded growth** when ln(V/V_lp) exceeds ``BLOWUP`` or the integrator stalls with V large (the
  quasi-static slider below k_c: V → ∞ in finite time, the step size falls below the resolution of t);
- **not resolved** when the step or time budget ends first (``max_steps`` per point; ``MAX_PERIODS``),
  the integrator stalls at small V, or Newton does not converge: no number is given.

The time budget is ``MAX_PERIODS`` linear periods at the point's own k (``time_scale``), not only at
the Hopf point: far below k_c with mass the oscillation is the block's inertial one, 2π√(M/k) (slip
law, a = 0.01, b = 0.015, Dc = 0.01, k = 0.1, M = 1: 19.87 against 2π/ω_c = 0.089 at k_c = 5000.5),
and the perturbation grows at Re λ ≈ 0.0025 there, so the transient to the cycle takes ~1800 time units
— 20 000 Hopf periods but 95 periods at k.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["BASIN_TOL", "BLOWUP", "CANDIDATE_TOL", "CHUNK_PERIODS", "Fate", "MAX_PERIODS", "MIN_AMPLITUDE", "PERTURBATION",
           "SLOW_MATCH", "SLOW_RHO", "SLOW_TURNS", "STEADY_TOL", "fate", "time_scale"]

#: ln V − ln V_lp at the start (θ_i at steady state at V_lp; no net force).
PERTURBATION = 1e-2
#: Steady sliding: every scaled component of u − u* below this (the decay is linear there).
STEADY_TOL = 1e-9
#: Two successive section states this close (scaled): try Newton for a cycle.
CANDIDATE_TOL = 1e-5
#: The run's last section state must be this close (scaled) to the converged cycle.
BASIN_TOL = 1e-3
#: A cycle must span more than this in ln V (a fixed point of P that close to steady sliding is its trace).
MIN_AMPLITUDE = 1e-6
#: ln(V/V_lp) beyond which growth is called unbounded (V > 5.5e34 V_lp).
BLOWUP = 80.0
#: Integration stretch between checks, and the time budget, in linear periods 2π/ω_c.
CHUNK_PERIODS = 4.0
MAX_PERIODS = 4000.0
#: With mass, the explicit run gives up (not resolved: the event-split integrator takes over) once it spends
#: more than this many steps per linear period at k over ``STIFF_PERIODS`` of them: the fast mode a/(M V) of a
#: deep stick phase (aging, a 0.01, b 0.015, Dc 0.01, k 0.5, M 1: 370 000 steps per period of 8.9 at
#: ln V = −23, measured; a cycle the explicit run follows takes ~1 000–2 000).
STIFF_STEPS = 100_000
STIFF_PERIODS = 2.0
#: Slow approach (a multiplier near 1, next to a Hopf point): the last ``SLOW_TURNS`` steps between section
#: states shrink steadily, by ``SLOW_RHO`` or slower per turn, and at that rate would not reach
#: ``CANDIDATE_TOL`` within the budget: the fixed point is solved for directly (full Newton on the return
#: map) and accepted only if the run's last ``SLOW_TURNS`` + 1 section states approach it at the rate its
#: largest multiplier ρ predicts, within ``SLOW_MATCH``·(1 − ρ) (the run is in the cycle's linear
#: neighbourhood, on its way there). Slip law, a 0.0094, b 0.0218, Dc 0.0136, k 0.96 k_c, V_lp 8.96,
#: M 1.31e-4, η 4.77e-4: ρ = 0.9977, the steps still 6e-4 after the 4000 periods of the budget.
SLOW_RHO = 0.95
SLOW_TURNS = 8
SLOW_MATCH = 0.5


@dataclass(frozen=True)
class Fate:
    """The outcome of one point (``kind`` in steady / cycle / unbounded / unresolved)."""

    kind: str
    message: str = ""
    period: float = math.nan
    ln_v_max: float = math.nan
    ln_v_min: float = math.nan
    slip: float = math.nan
    multiplier_max: float = math.nan
    steps: int = 0
    w: tuple = ()       # a cycle's section coordinates (ln θ_i[, z]) at x = ln V_lp, ẋ > 0


def time_scale(spec, v_lp: float, period0: float) -> float:
    """The run's unit of time: the larger of ``period0`` (2π/ω_c at the Hopf point) and 2π/|λ| of the
    leading eigenvalue λ of steady sliding at the spec's own k (module docstring)."""
    import mpmath as mp

    from .hopf import jacobian

    try:
        with mp.workdps(20):
            ev = mp.eig(jacobian(spec, spec.k, v_lp), left=False, right=False)
        lam = complex(max(ev, key=lambda z: mp.re(z)))
    except (ValueError, ZeroDivisionError, ArithmeticError):   # mpmath's eigen-solver did not converge
        return period0
    size = abs(lam)
    return max(period0, 2 * math.pi / size) if size > 0 and math.isfinite(size) else period0


def fate(spec, v_lp: float, period0: float, *, max_steps: int, t_max: float, progress=None) -> Fate:
    """Integrate the perturbed steady slide of ``spec`` at load-point velocity ``v_lp`` (module docstring).
    ``progress(text)``, if given, is called after each stretch (the caller decides what to show)."""
    import heyoka as hy

    from ._system import TAYLOR_BLOWUP, compiled, parameters

    c = compiled(spec.state_law, spec.inertial, 1, "double", damped=spec.damped)
    ta = c.integrator
    x_star = math.log(v_lp)
    y_star = np.array([math.log(law.steady_factor * d / v_lp) for law, d in zip(spec.laws, spec.dc)])
    u_star = np.concatenate([[x_star], y_star, [0.0] if spec.inertial else []])
    scale = np.ones(u_star.size)
    if spec.inertial:
        scale[-1] = max(sum(spec.b) - spec.a, spec.a)
    start = u_star.copy()
    start[0] += PERTURBATION
    ta.time = 0.0
    ta.state[:] = start
    ta.pars[:] = parameters(spec, spec.k, v_lp, [x_star])
    ta.reset_cooldowns()
    rec = c.recorder
    rec.reset(0.0)
    rec.x0 = float(start[0])
    # (the checks stay every CHUNK_PERIODS Hopf periods: results that resolved within the old budget are
    # unchanged to the bit; only runs that ran out of it go on)
    unit = time_scale(spec, v_lp, period0)
    t_end = min(MAX_PERIODS * unit, t_max)
    chunk = CHUNK_PERIODS * period0
    steps, last_dist, tried, seen = 0, math.inf, math.inf, 0
    direct = _Direct(spec, v_lp, scale[1:], period0, max_steps, u_star[1:])

    last_x = [float(start[0])]   # ln V after the last successful step
    marks = [(0.0, 0)]            # (time, steps) at the chunks' ends within the last STIFF_PERIODS units

    def below_blowup(integrator) -> bool:
        last_x[0] = float(integrator.state[0])
        # the second test stops a finite-time blow-up before its next step overflows (_system.py)
        return last_x[0] - x_star <= BLOWUP and abs(integrator.tc[0, -1]) < TAYLOR_BLOWUP

    while True:
        target = min(float(ta.time) + chunk, t_end)
        # the callback stops the run once ln(V/V_lp) passes BLOWUP, before exp(x) can overflow in a step
        res = ta.propagate_until(target, max_steps=max(max_steps - steps, 1), callback=below_blowup)
        outcome = res[0]
        steps += res[3]
        x = float(ta.state[0])
        where = f"t = {float(ta.time):.6g} (ln V/V_lp = {x - x_star:.4g}) after {steps} Taylor steps"
        if progress is not None:
            progress(f"transient run: {where} (budget t = {t_end:.6g}, {max_steps} steps)")
        top = max([e[1] for e in rec.extrema[seen:]] + [x])
        seen = len(rec.extrema)
        if top - x_star > BLOWUP or (outcome != hy.taylor_outcome.time_limit and x - x_star > 10
                                     and steps < max_steps) or (outcome == hy.taylor_outcome.cb_stop):
            if spec.damped:
                # with radiation damping V stays bounded (ηV caps the slip rate): what stopped the run is
                # the integrator — at slip rates e^x/Dc beyond ~1e15 the Taylor coefficients (rate^order)
                # overflow a double — not a blow-up
                return Fate("unresolved", f"the integrator could not follow the slip spike (Taylor "
                            f"coefficients overflow at slip rates ~ e^x/Dc > 1e15): {where}", steps=steps)
            if spec.inertial and outcome != hy.taylor_outcome.time_limit and x < x_star:
                # stopped by the Taylor-coefficient guard with V small (an extremum of that last step may read
                # as huge): the fast mode a/(M V) of a deep stick phase (aging, a 0.01, b 0.015, Dc 0.01, k 0.5,
                # M 10: at ln V/V_lp = −39.2), not a blow-up
                return Fate("unresolved", f"the Taylor coefficients of ln V overflow at small V (the fast mode "
                            f"a/(M V) of a deep stick phase): {where}", steps=steps)
            return Fate("unbounded", f"V grows without bound: {where}", steps=steps)
        if outcome == hy.taylor_outcome.err_nf_state:
            if last_x[0] - x_star > 20 and not spec.damped:   # the step from V > 5e8 V_lp overflowed: V blows up in finite time
                return Fate("unbounded", f"V grows without bound: non-finite after ln V/V_lp = "
                            f"{last_x[0] - x_star:.4g}, {steps} Taylor steps", steps=steps)
            return Fate("unresolved", f"non-finite state after ln V/V_lp = {last_x[0] - x_star:.4g}, {steps} "
                        "Taylor steps", steps=steps)
        if outcome != hy.taylor_outcome.time_limit:
            why = "step budget spent" if steps >= max_steps else "step size fell below the resolution of t"
            # with inertia the fast mode a/(M V) limits explicit steps at small V (docs/rate-state.md)
            return Fate("unresolved", f"{why} at {where}", steps=steps)
        if spec.inertial:
            now = float(ta.time)
            marks.append((now, steps))
            while len(marks) > 1 and marks[1][0] <= now - STIFF_PERIODS * unit:
                marks.pop(0)
            t0, s0 = marks[0]
            if now - t0 >= STIFF_PERIODS * unit and steps - s0 > STIFF_STEPS * STIFF_PERIODS:
                return Fate("unresolved", f"stiff: {steps - s0} Taylor steps in the last {now - t0:.4g} (linear "
                            f"periods {unit:.4g}) at {where}; the fast mode a/(M V) of a deep stick phase",
                            steps=steps)
        dist = float(np.max(np.abs(np.asarray(ta.state, dtype=float) - u_star) / scale))
        if dist < STEADY_TOL and dist < last_dist:
            return Fate("steady", steps=steps)
        last_dist = dist
        ups = _last_upward(rec, 2)
        if len(ups) >= 2:
            w_scale = scale[1:]
            moved = float(np.max(np.abs(ups[-1] - ups[-2]) / w_scale))
            if moved < CANDIDATE_TOL * max(1.0, float(np.max(np.abs(ups[-1]) / w_scale))) and moved < tried / 10:
                tried = moved
                found = _cycle(spec, v_lp, ups[-1], w_scale, t_max=period0 * 1e3, max_steps=max_steps)
                if found is not None:
                    w, period, top_c, bottom_c, mult = found
                    # a fixed point of P at the steady state's trace (amplitude ~ 0) is not a cycle
                    if top_c - bottom_c > MIN_AMPLITUDE and np.max(np.abs(ups[-1] - w) / w_scale) < BASIN_TOL \
                            and mult < 1:
                        return Fate("cycle", period=period, ln_v_max=top_c, ln_v_min=bottom_c, slip=v_lp * period,
                                    multiplier_max=mult, steps=steps, w=tuple(float(v) for v in w))
                # the return map has its own compiled integrator (section=True): the run resumes here
        found = direct.attempt(rec, float(ta.time), t_end, steps)
        if found is not None:
            return found
        if float(ta.time) >= t_end:
            if direct.verdict:
                return Fate("unresolved", f"neither steady sliding nor a cycle within {float(ta.time):.6g} "
                            f"({float(ta.time) / unit:.0f} linear periods): {direct.verdict}", steps=steps)
            return Fate("unresolved", f"neither steady sliding nor a cycle within {float(ta.time):.6g} "
                        f"({float(ta.time) / unit:.0f} linear periods); last distance to steady sliding "
                        f"{dist:.3g}", steps=steps)


def _last_upward(rec, count: int) -> list:
    """The section coordinates (ln θ_i[, z]) of the last ``count`` upward crossings of V = V_lp, oldest first."""
    out = []
    for (_, state), crossing in zip(reversed(rec.crossing_states), reversed(rec.crossings)):
        if crossing[2] > 0:
            out.append(np.asarray(state[1:], dtype=float))
            if len(out) == count:
                break
    return out[::-1]


class _Direct:
    """The slow-approach path of ``fate`` (``SLOW_RHO``): Newton on the return map from the run's last
    section state, vouched for by the run's own approach to the fixed point found."""

    def __init__(self, spec, v_lp, w_scale, period0, max_steps, w_steady):
        self.spec, self.v_lp, self.w_scale, self.period0, self.max_steps = spec, v_lp, w_scale, period0, max_steps
        self.w_steady = np.asarray(w_steady, dtype=float)   # steady sliding's trace on the section
        self.tried = math.inf     # the step size at the last attempt: the next one waits for it to halve
        self.verdict = ""         # why the last attempt was not accepted (said if the run ends unresolved)

    def attempt(self, rec, now, t_end, steps):
        ups, times = _last_upward_timed(rec, SLOW_TURNS + 1)
        if len(ups) < SLOW_TURNS + 1:
            return None
        moved = [float(np.max(np.abs(b - a) / self.w_scale)) for a, b in zip(ups, ups[1:])]
        at_end = now >= t_end
        if at_end and moved[0] > 0 and all(b > a for a, b in zip(moved, moved[1:])):
            return self._growing(rec, steps)
        if not (moved[-1] > 0 and all(b < a for a, b in zip(moved, moved[1:]))):
            return None   # not contracting steadily (growing, oscillating, or on the fixed point already)
        rho = (moved[-1] / moved[0]) ** (1.0 / (len(moved) - 1))
        norm = max(1.0, float(np.max(np.abs(ups[-1]) / self.w_scale)))
        turn = (times[-1] - times[0]) / SLOW_TURNS
        needed = math.log(moved[-1] / (CANDIDATE_TOL * norm)) / -math.log(rho) if rho < 1 else math.inf
        # the usual path (two section states within CANDIDATE_TOL) still decides every run it can finish in
        # its budget, so what it resolved before is unchanged to the bit
        if not (rho >= SLOW_RHO or at_end) or (now + needed * turn <= t_end and not at_end):
            return None
        if not moved[-1] < self.tried / 2 and not at_end:
            return None
        self.tried = moved[-1]
        found = _cycle(self.spec, self.v_lp, ups[-1], self.w_scale, t_max=self.period0 * 1e3,
                       max_steps=self.max_steps, full=True)
        if found is None:
            self.verdict = (f"slow approach (steps shrink by {rho:.6g} per turn); Newton on the return map "
                            "from the last section state did not converge")
            return None
        w, period, top_c, bottom_c, mult = found
        if not top_c - bottom_c > MIN_AMPLITUDE:
            self.verdict = "slow approach; Newton converged to the trace of steady sliding (no amplitude)"
            return None
        if not mult < 1:
            self.verdict = (f"slow approach; Newton converged to a cycle that is not attracting (largest |multiplier| "
                            f"{mult:.6g}), so not where the run goes")
            return None
        dist = [float(np.max(np.abs(u - w) / self.w_scale)) for u in ups]
        rate = (dist[-1] / dist[0]) ** (1.0 / SLOW_TURNS) if dist[0] > 0 else math.nan
        if not (all(b < a for a, b in zip(dist, dist[1:])) and abs(rate - mult) <= SLOW_MATCH * (1 - mult)):
            self.verdict = (f"slow approach; the run's last section states approach the cycle Newton found at "
                            f"{rate:.6g} per turn, not at its largest multiplier {mult:.6g}")
            return None
        return Fate("cycle", f"solved by Newton on the return map: the transient approaches the cycle at "
                    f"{rate:.6g} per turn (largest multiplier {mult:.6g}, distance {dist[-1]:.3g} after {steps} "
                    "Taylor steps)", period=period, ln_v_max=top_c, ln_v_min=bottom_c, slip=self.v_lp * period,
                    multiplier_max=mult, steps=steps, w=tuple(float(v) for v in w))


    def _growing(self, rec, steps):
        """The budget ended with the run still spiralling out of steady sliding (growth ~ (1 − ρ)/2 per turn
        next to a Hopf point: ρ = 0.9997 needs ~10⁴ turns). The amplitude A_n = |w_n − w_steady| of the run's
        later half is fitted by A_{n+1}/A_n − 1 = c − d A_n² (the Hopf normal form ṙ = σr + l1 r³ over one turn); Newton
        starts at the predicted amplitude √(c/d) along the run's direction. The cycle found is accepted if
        attracting and if the return map takes each of 8 points on the segment from the run's last state to
        it closer to it (no other fixed point there at that resolution: the run is on its way there)."""
        ups, _ = _last_upward_timed(rec, 10 ** 9)
        if len(ups) < 40:
            return None
        amp = np.array([float(np.max(np.abs(u - self.w_steady) / self.w_scale)) for u in ups])
        late = amp[len(amp) // 2:]
        if not np.all(np.diff(late) > 0):
            self.verdict = "still moving away from steady sliding, not steadily"
            return None
        slope, c = np.polyfit(late[:-1] ** 2, late[1:] / late[:-1] - 1, 1)
        if not (c > 0 and slope < 0) or not c / -slope > late[-1] ** 2:
            self.verdict = (f"still growing away from steady sliding (section amplitude {late[-1]:.3g}); its growth "
                            "does not slow as a supercritical Hopf cycle's would")
            return None
        target = math.sqrt(c / -slope)
        start = self.w_steady + (ups[-1] - self.w_steady) * (target / late[-1])
        found = _cycle(self.spec, self.v_lp, start, self.w_scale, t_max=self.period0 * 1e3,
                       max_steps=self.max_steps, full=True)
        if found is None:
            self.verdict = (f"still growing away from steady sliding; Newton on the return map from the predicted "
                            f"amplitude {target:.3g} did not converge")
            return None
        w, period, top_c, bottom_c, mult = found
        if not (top_c - bottom_c > MIN_AMPLITUDE and mult < 1):
            self.verdict = (f"still growing away from steady sliding; Newton converged to a fixed point that is not an "
                            f"attracting cycle (largest |multiplier| {mult:.6g}, ln V span {top_c - bottom_c:.3g})")
            return None
        from .continuation import ReturnMap

        pmap = ReturnMap(self.spec, self.v_lp, t_max=self.period0 * 1e3, max_steps=self.max_steps)
        for j in range(8):
            u = ups[-1] + (w - ups[-1]) * (j / 8)
            r = pmap(u, self.spec.k)
            if r is None or not np.max(np.abs(r[0] - w) / self.w_scale) < np.max(np.abs(u - w) / self.w_scale):
                self.verdict = (f"still growing away from steady sliding; the return map does not take the segment "
                                f"from the run's last state to the cycle Newton found towards it (point {j} of 8)")
                return None
        return Fate("cycle", f"solved by Newton on the return map: at the end of its budget the run was still "
                    f"growing away from steady sliding (section amplitude {late[-1]:.3g} of {_amplitude(w, self):.3g}); "
                    f"started at the normal form's amplitude {target:.3g}, the return map takes the segment between "
                    f"to the cycle (largest multiplier {mult:.6g}, after {steps} Taylor steps)", period=period,
                    ln_v_max=top_c, ln_v_min=bottom_c, slip=self.v_lp * period, multiplier_max=mult, steps=steps,
                    w=tuple(float(v) for v in w))


def _amplitude(w, direct):
    """|w − w_steady|, scaled: the section amplitude of a cycle's fixed point."""
    return float(np.max(np.abs(np.asarray(w) - direct.w_steady) / direct.w_scale))


def _last_upward_timed(rec, count: int):
    """``_last_upward`` with the crossings' times."""
    out, times = [], []
    for (_, state), crossing in zip(reversed(rec.crossing_states), reversed(rec.crossings)):
        if crossing[2] > 0:
            out.append(np.asarray(state[1:], dtype=float))
            times.append(float(crossing[0]))
            if len(out) == count:
                break
    return out[::-1], times[::-1]


def _cycle(spec, v_lp, w0, w_scale, *, t_max, max_steps, full=False):
    """Newton on the return map P(w) − w = 0 from ``w0``: (w, period, max ln V, min ln V, max |μ|) or None.
    Chord steps (the Jacobian at ``w0``) from a candidate of the usual path, full Newton (``full``) from the
    slow path's farther start."""
    from .continuation import ReturnMap

    pmap = ReturnMap(spec, v_lp, t_max=t_max, max_steps=max_steps)

    def G(w):
        r = pmap(w, spec.k)
        if r is None:
            raise _NoReturn
        return r[0] - w

    def jac(w):
        h = 1e-7 * np.maximum(np.abs(w), w_scale)
        cols = [(G(w + h[j] * e) - G(w - h[j] * e)) / (2 * h[j]) for j, e in enumerate(np.eye(w.size))]
        return np.array(cols).T

    w = np.array(w0, dtype=float)
    try:
        J = jac(w)
        for i in range(12 if full else 8):
            if full and i:
                J = jac(w)
            g = G(w)
            dw = np.linalg.solve(J, -g)
            w = w + dw
            if np.max(np.abs(dw) / w_scale) < 1e-12 * max(1.0, float(np.max(np.abs(w) / w_scale))):
                break
        else:
            return None
        J = jac(w)
        # Polish with the Jacobian at the solution: the chord steps above (J from w0) converge only
        # linearly and stop at 1e-12, which left the fixed point ~1e-13 off near a Hopf point (ln V
        # extrema 1.2e-13 from an mpmath shooting at multiplier 0.984, tests/test_indep3_rate_state.py)
        # while the second-turn error estimate said 3e-16. Until a step is at the map's rounding.
        for _ in range(4):
            dw = np.linalg.solve(J, -G(w))
            w = w + dw
            if np.max(np.abs(dw) / w_scale) < 1e-15 * max(1.0, float(np.max(np.abs(w) / w_scale))):
                break
        r = pmap(w, spec.k)
    except (_NoReturn, np.linalg.LinAlgError):
        return None
    if r is None or np.max(np.abs(r[0] - w) / w_scale) > 1e-10 * max(1.0, float(np.max(np.abs(w) / w_scale))):
        return None
    mult = float(np.max(np.abs(np.linalg.eigvals(J + np.eye(w.size)))))
    return w, r[1], r[2], r[3], mult


class _NoReturn(Exception):
    pass
