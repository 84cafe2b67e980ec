"""Periodic orbits of the rate-state slider from its Hopf point: shooting on a Poincaré section and
pseudo-arclength continuation in k/k_c, with Floquet multipliers, fold and period-doubling detection.

Section Σ: x = ln V_lp crossed upwards (ẋ > 0). A cycle is a fixed point w = P(w; κ) of the return
map on Σ, where w = (y_1..y_n[, z]) are the coordinates on Σ and κ = k/k_c. P is one heyoka integration
to the terminal section event (the compiled integrator of ``_system`` with ``section=True``); the
period T is its time. Continuation (Keller 1977; Kuznetsov 2004, §10.2): unknowns X = (w, κ),
residual G(X) = P(w; κ) − w, predictor X + s τ along the unit tangent τ (kernel of DG), corrector
Newton on [G(X); τ·(X − X_pred)] = 0, DG by central differences (h = 1e-7 relative). The nontrivial
Floquet multipliers are the eigenvalues of ∂P/∂w (the trivial multiplier 1 of the flow direction is
removed by the section). Fold: the κ-component of τ changes sign; period doubling: a multiplier
crosses −1.

Start: Newton on (w, κ) with the first section coordinate fixed at ε off the steady state along the
Hopf eigenvector (the cycle of amplitude ε), then arclength steps.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field

import numpy as np

from ._system import blowup_guard, compiled, parameters, rhs_expressions
from .hopf import HopfPoint, hopf_point, steady_state
from .spec import SliderSpec

__all__ = ["Branch", "BranchPoint", "ReturnMap", "continue_cycles", "continue_in_v_lp", "period_by_simulation"]


@dataclass(frozen=True)
class BranchPoint:
    """One periodic orbit of the branch."""

    kappa: float                 # k / k_c
    k: float
    period: float
    w: tuple                     # section coordinates (ln θ_i[, z]) at x = ln V_lp, ẋ > 0
    ln_v_max: float
    ln_v_min: float
    slip: float                  # slip per cycle = V_lp · T (the spring returns after a period)
    multipliers: tuple           # nontrivial Floquet multipliers (complex)
    residual: float              # |P(w) − w| at the converged point
    status: str                  # "ok", or "no-convergence" / "no-return" (not vouched for)
    v_lp: float = math.nan       # the load-point velocity of this cycle (set on a branch in V_lp)


@dataclass(frozen=True)
class Branch:
    spec: SliderSpec
    v_lp: float
    hopf: HopfPoint
    points: tuple
    folds: tuple = ()            # indices i where κ turns between points i and i + 1
    period_doublings: tuple = ()  # indices where a multiplier crosses −1
    meta: dict = field(default_factory=dict)


class ReturnMap:
    """P(w; k) on the section x = ln V_lp, with the period and the extrema of ln V over the cycle."""

    def __init__(self, spec: SliderSpec, v_lp: float, t_max: float, max_steps: int = 200_000) -> None:
        self.spec, self.v_lp, self.t_max, self.max_steps = spec, float(v_lp), float(t_max), max_steps
        self.c = compiled(spec.state_law, spec.inertial, 1, "double", section=True, damped=spec.damped)
        self.x0 = math.log(self.v_lp)
        self.last_failure = ""
        self.split = False   # set once the explicit run failed with mass: the event-split turn from then on
        self._split_steps = 0   # steps of the last event-split turn (bounds the next: ``_split_turn``)

    def __call__(self, w, k, v_lp=None):
        if v_lp is not None:   # a branch in V_lp: the section x = ln V_lp moves with it
            self.v_lp, self.x0 = float(v_lp), math.log(v_lp)
        if self.split:
            return self._split_turn(w, k)
        c, ta, spec = self.c, self.c.integrator, self.spec
        ta.time = 0.0
        ta.state[0] = self.x0
        ta.state[1:] = w
        ta.pars[:] = parameters(spec, k, self.v_lp, [self.x0])
        ta.reset_cooldowns()
        c.recorder.reset(0.0)
        c.recorder.x0 = self.x0
        steps = 0
        guard = blowup_guard(np.float64)
        while True:
            outcome, _, _, n, *_ = ta.propagate_until(self.t_max, max_steps=self.max_steps - steps,
                                                      callback=guard)
            steps += n
            if int(outcome) == -1 and ta.time == 0.0:
                continue  # the start itself is on Σ: the event's cooldown now lets the run leave it
            break
        if int(outcome) != -1:
            # With inertia the fast mode of ln V relaxes at a rate a/(M V): at low V the explicit Taylor
            # steps shrink to its stability limit and the step bound is hit (stiffness, not a bug).
            what = guard.reason or (outcome.name if hasattr(outcome, "name") else outcome)
            self.last_failure = (f"{what} at t = {ta.time:.6g}, "
                                 f"ln V = {ta.state[0]:.4g}, after {steps} steps")
            if spec.inertial and ta.state[0] < self.x0:   # stiff at small V (deep stick, slip-law plunge)
                self.split = True
                return self._split_turn(w, k)
            return None
        ext = np.array([e[1] for e in c.recorder.extrema] + [self.x0])
        return np.array(ta.state[1:]), float(ta.time), float(ext.max()), float(ext.min())

    def _split_turn(self, w, k):
        """One turn by the event-split integrator (``slow_manifold``: fast-time inertial phases, slow manifold
        at tiny V), section phase inertial; sticky, so a Jacobian never mixes the two integrators."""
        from dataclasses import replace

        from .slow_manifold import TURN_FACTOR, TURN_FLOOR, _turn

        # bounded like deep_cycle's Newton: after one turn, each at most TURN_FACTOR times the last one's steps
        last = self._split_steps
        budget = min(self.max_steps, max(TURN_FACTOR * last, TURN_FLOOR)) if last else self.max_steps
        ledger = [0, ""]
        got = _turn(replace(self.spec, k=float(k)), self.v_lp, "inertial", np.array(w, dtype=float),
                    self.t_max / 50, ledger, max_steps=budget)
        if got is None:
            self.last_failure += f"; event-split integrator: no return to the section in its phase ({ledger[1]})"
            return None
        w1, period, run = got
        self._split_steps = run.steps
        ext = np.array([e[1] for e in run.extrema] + [self.x0])
        return np.array(w1), float(period), float(ext.max()), float(ext.min())


def _jac(fun, x, h):
    f0 = fun(x)
    cols = []
    for j in range(x.size):
        d = np.zeros_like(x)
        d[j] = h[j]
        cols.append((fun(x + d) - fun(x - d)) / (2 * h[j]))
    return f0, np.array(cols).T


def continue_cycles(*, a, b, dc, state_law, v_lp, mass=None, damping=0.0, points: int = 60, eps: float = 1e-3,
                    step: float = 0.05, max_step: float = 2.0, kappa_range=(0.05, 20.0),
                    min_ln_v: float = -200.0, t_max_periods: float = 1e4, max_steps: int = 200_000) -> Branch:
    """Trace the branch of cycles born at the Hopf point of steady sliding at V_lp (module docstring)."""
    h = hopf_point(a=a, b=b, dc=dc, state_law=state_law, v_lp=v_lp, mass=mass, damping=damping, dps=30)
    spec = SliderSpec(a=a, b=b, dc=dc, state_law=state_law, k=h.k_c, mass=mass, damping=damping)
    period0 = 2 * math.pi / h.omega_c
    pmap = ReturnMap(spec, v_lp, t_max=t_max_periods * period0, max_steps=max_steps)
    u_star = np.array([float(v) for v in steady_state(spec, v_lp)])
    w_star = u_star[1:]
    q = np.array(h.eigenvector)
    direction = (cmath.exp(1j * (math.pi / 2 - cmath.phase(q[0]))) * q).real[1:]
    # Natural units of the section coordinates: 1 for ln θ_i, the friction drop Σb − a for the net force
    # z. (Scaling by the Hopf eigenvector instead stalled the arclength once z outgrew its tiny
    # eigenvector component: the steps became all z and no κ.)
    m = w_star.size
    scale = np.ones(m)
    if spec.inertial:
        scale[-1] = max(sum(spec.b) - spec.a, spec.a)
    weights = np.append(1 / scale, 1.0)

    def G(X):
        r = pmap(X[:m], X[m] * h.k_c)
        if r is None:
            raise _NoReturn
        return r[0] - X[:m]

    def newton(X, extra, extra_grad):
        return _newton(G, X, weights, m, extra, extra_grad)

    def point(X, J, ok):
        r = pmap(X[:m], X[m] * h.k_c)
        mult = np.linalg.eigvals(J[:, :m] + np.eye(m))
        resid = float(np.max(np.abs(r[0] - X[:m])))
        return BranchPoint(float(X[m]), float(X[m] * h.k_c), r[1], tuple(X[:m]), r[2], r[3], float(v_lp) * r[1],
                           tuple(complex(z) for z in mult), resid, "ok" if ok else "no-convergence")

    # Two starting cycles of amplitudes ε and 2ε (first section coordinate fixed), then arclength.
    # Oriented so that ẋ > 0 at the start (the section is crossed upwards, P is one full turn).
    par = parameters(spec, h.k_c, float(v_lp))
    xdot = rhs_expressions(spec.state_law, spec.inertial, np.append(u_star[0], w_star + 1e-6 * direction), par,
                           np.exp, np.log, damped=spec.damped)[0]
    sign = 1.0 if xdot > 0 else -1.0
    starts = []
    unit = direction / np.max(np.abs(direction) * weights[:m])
    for amp in (eps, 2 * eps):
        X = np.append(w_star + sign * amp * unit, 1.0)
        target = X[0]
        grad = np.zeros(m + 1)
        grad[0] = 1.0
        X, J, ok = newton(X, lambda Y, t=target: Y[0] - t, grad)
        starts.append((X, J, ok))
    out = [point(*s) for s in starts]
    X_prev, X = starts[0][0], starts[1][0]
    tau = (X - X_prev) * weights
    tau /= np.linalg.norm(tau)

    def leaves(X, p):
        if not (kappa_range[0] < X[m] < kappa_range[1]) or p.ln_v_min < min_ln_v:
            return f"left the range at κ = {X[m]:.6g} (κ in {kappa_range}, ln V_min > {min_ln_v})"
        return None

    folds, pds, stop = _arclength(X, tau, out, newton, point, weights, m, step=step, max_step=max_step,
                                  points=points, leaves=leaves, failure=lambda: pmap.last_failure,
                                  where=lambda X: f"κ = {X[m]:.6g}")
    return Branch(spec, float(v_lp), h, tuple(out), tuple(folds), tuple(pds), {"stop": stop})


class _NoReturn(Exception):
    pass


def _newton(G, X, weights, m, extra, extra_grad, iters=10):
    """Chord Newton on (G(X) = 0, extra(X) = 0) (DG from the predictor, fresh residuals), then DG once
    more at the solution. Returns (X, DG, converged).

    Converged when the step is below 1e-13 of the unknowns' size: P is computed to ~1e-15 relative,
    so the residual of a large cycle cannot go below ~1e-15·|w| and is not the test.
    """
    hvec = 1e-7 * np.maximum(np.abs(X), 1 / weights)
    g, J = _jac(G, X, hvec)
    A = np.vstack([J, extra_grad])
    ok = False
    for _ in range(iters):
        dX = np.linalg.solve(A, np.append(g, extra(X)))
        X = X - dX
        g = G(X)
        if np.max(np.abs(dX) * weights) < 1e-12 * max(1.0, np.max(np.abs(X) * weights)):
            ok = True
            break
    ok = ok and np.max(np.abs(g)) < 1e-10 * max(1.0, np.max(np.abs(X[:m])))
    if ok:
        _, J = _jac(G, X, hvec)
    return X, J, ok


def _arclength(X, tau, out, newton, point, weights, m, *, step, max_step, points, leaves, failure, where):
    """Pseudo-arclength predictor–corrector from (X, tau), appending ``point``s to ``out`` until
    ``points`` of them, ``leaves(X, p)`` names why the branch left its range, or the step falls below
    1e-4. Returns (fold indices, period-doubling indices, why it stopped).

    The parameter is X[m]. A fold is where its tangent component turns; on the vertical family of a
    degenerate Hopf point (the parameter fixed for every amplitude) that component is rounding noise
    whose sign means nothing: ignored below 1e-7. A period doubling is a real multiplier crossing −1.
    """
    s, folds, pds = step, [], []
    stop = f"reached {points} points"
    while len(out) < points:
        X_pred = X + s * tau / weights
        try:
            X_new, J, ok = newton(X_pred, lambda Y: np.dot((Y - X_pred) * weights, tau), tau * weights)
        except (_NoReturn, np.linalg.LinAlgError):
            ok = False
        if not ok:
            s /= 2
            if s < 1e-4:
                stop = (f"stopped at {where(X)}: no converged cycle within a step of 1e-4 (the return map "
                        f"failed: {failure() or 'no Newton convergence'})")
                break
            continue
        # the new tangent: the kernel of DG, oriented along the old one
        _, _, vt = np.linalg.svd(J * (1 / weights)[None, :])
        t_new = vt[-1] if np.dot(vt[-1], tau) >= 0 else -vt[-1]
        p = point(X_new, J, ok)
        if np.sign(t_new[m]) != np.sign(tau[m]) and min(abs(t_new[m]), abs(tau[m])) > 1e-7:
            folds.append(len(out) - 1)
        prev = np.array(out[-1].multipliers)
        if np.any(np.isclose(np.array(p.multipliers).imag, 0)) and \
                np.any((np.array(p.multipliers).real + 1) * (prev.real + 1) < 0):
            pds.append(len(out) - 1)
        out.append(p)
        X, tau = X_new, t_new
        s = min(s * 1.5, max_step)
        why = leaves(X, p)
        if why:
            stop = why
            break
    return folds, pds, stop


def period_by_simulation(branch: Branch, index: int, precision: str = "double") -> float:
    """The period of branch point ``index`` from a direct run of the engine (``run_spec``).

    Starts on the section at the point's (ln V_lp, w), integrates through 2.5 periods without stopping
    (non-terminal threshold events at V = V_lp, located on the dense output) and returns the time
    between the first and second upward crossings: a second turn of the cycle on a step grid that no
    longer starts at the section, so its rounding is independent of the shooting map's (the first
    turn alone reproduces the map's steps bit for bit in double). ``precision="quad"`` (real128)
    returns the first turn instead, in another arithmetic.
    """
    from .simulate import run_spec
    from .spec import load_history

    p = branch.points[index]
    spec = branch.spec
    v_lp = p.v_lp if math.isfinite(p.v_lp) else branch.v_lp
    run = SliderSpec(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, k=p.k, mass=spec.mass,
                     damping=spec.damping)
    n = spec.n_states
    turns = 1.5 if precision == "quad" else 2.5
    r = run_spec(run, load_history(v_lp), [0.0, turns * p.period], ln_v0=math.log(v_lp),
                 ln_theta0=list(p.w[:n]), z0=p.w[n] if spec.inertial else 0.0, thresholds=[v_lp],
                 precision=precision, max_steps=5_000_000)
    ups = [t for (t, s), c in zip(r.crossing_states, r.crossings) if c[2] > 0]
    if precision == "quad":
        return float(ups[0]) if ups else math.nan
    return float(ups[1] - ups[0]) if len(ups) > 1 else math.nan


def continue_in_v_lp(branch: Branch, index: int, *, points: int = 30, step: float = 0.05, max_step: float = 1.0,
                     v_lp_range=(1e-6, 1e6), max_steps: int = 200_000) -> Branch:
    """Continue the cycle ``branch.points[index]`` in the load-point velocity at fixed k.

    Unknowns X = (w, λ) with λ = ln V_lp (V_lp spans decades); residual P(w; k, V_lp) − w on the section
    x = ln V_lp, which moves with λ. Same predictor-corrector, tangent, fold and period-doubling tests as
    ``continue_cycles``. Quasi-static, V_lp only rescales a cycle (ln V − ln V_lp and V_lp·T do not
    depend on it: docs/rate-state.md); with inertia it moves k_c = (b − a)/Dc·[1 + M V_lp²/(a Dc)], so
    the branch ends where κ = k/k_c(V_lp) reaches the Hopf point. Each point's ``kappa`` is k over the
    closed-form k_c at its V_lp (NaN with two state variables).
    """
    from .hopf import closed_form

    spec, start = branch.spec, branch.points[index]
    k = start.k
    m = len(start.w)
    v0 = start.v_lp if math.isfinite(start.v_lp) else branch.v_lp
    pmap = ReturnMap(spec, v0, t_max=1e300, max_steps=max_steps)
    scale = np.ones(m)
    if spec.inertial:
        scale[-1] = max(sum(spec.b) - spec.a, spec.a)
    weights = np.append(1 / scale, 1.0)

    def G(X):
        r = pmap(X[:m], k, math.exp(X[m]))
        if r is None:
            raise _NoReturn
        return r[0] - X[:m]

    def kappa_at(v):
        k_c = closed_form(spec, v)[0]
        return k / float(k_c) if spec.n_states == 1 else math.nan

    def newton(X, extra, extra_grad):
        return _newton(G, X, weights, m, extra, extra_grad)

    def point(X, J, ok):
        v = math.exp(X[m])
        r = pmap(X[:m], k, v)
        mult = np.linalg.eigvals(J[:, :m] + np.eye(m))
        return BranchPoint(kappa_at(v), k, r[1], tuple(X[:m]), r[2], r[3], v * r[1],
                           tuple(complex(z) for z in mult), float(np.max(np.abs(r[0] - X[:m]))),
                           "ok" if ok else "no-convergence", v)

    X = np.append(np.array(start.w, dtype=float), math.log(v0))
    hvec = 1e-7 * np.maximum(np.abs(X), 1 / weights)
    _, J = _jac(G, X, hvec)
    _, _, vt = np.linalg.svd(J * (1 / weights)[None, :])
    tau = vt[-1]
    if tau[m] < 0:
        tau = -tau   # towards larger V_lp first
    out = [point(X, J, True)]
    lo, hi = math.log(v_lp_range[0]), math.log(v_lp_range[1])

    def leaves(X, p):
        if not lo < X[m] < hi:
            return f"left the range at V_lp = {math.exp(X[m]):.6g} (V_lp in {tuple(v_lp_range)})"
        return None

    folds, pds, stop = _arclength(X, tau, out, newton, point, weights, m, step=step, max_step=max_step,
                                  points=points, leaves=leaves, failure=lambda: pmap.last_failure,
                                  where=lambda X: f"V_lp = {math.exp(X[m]):.6g}")
    return Branch(spec, v0, branch.hopf, tuple(out), tuple(folds), tuple(pds),
                  {"stop": stop, "parameter": "v_lp", "k": k})
