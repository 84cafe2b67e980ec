"""The finite-amplitude instability above k_c: the unstable cycle as the basin boundary of steady sliding.

Where the Hopf point is subcritical (quasi-static PRZ law; the aging law with little inertia), a branch
of unstable cycles leaves k_c towards κ > 1 (``continuation.continue_cycles``). With one state variable
and no inertia the phase space is the plane (ln V, ln θ), so the unstable cycle is the boundary of the
basin of steady sliding: on the section V = V_lp a perturbation of ln θ smaller than the cycle's
crossing decays, a larger one runs away. ``critical_perturbation`` reads the critical size off the
branch (Δ_c = w − ln θ*, the cycle's upward crossing) and ``fate_of_perturbation`` checks it by direct
runs from just inside and just outside.
"""

from __future__ import annotations

import math

__all__ = ["critical_in_slip", "critical_perturbation", "fate_of_perturbation", "in_slip"]


def critical_perturbation(branch) -> list:
    """(κ, Δ_c) along a branch of unstable cycles: Δ_c = ln θ on the cycle at V = V_lp (ẋ > 0) − ln θ*."""
    spec = branch.spec
    law = spec.laws[0]
    y_star = math.log(law.steady_factor * spec.dc[0] / branch.v_lp)
    return [(p.kappa, p.w[0] - y_star) for p in branch.points if p.status == "ok"]


def fate_of_perturbation(branch, kappa: float, delta: float, *, periods: float = 400.0,
                         max_steps: int = 2_000_000) -> str:
    """"decays", "runs away" or "undecided": steady sliding at V_lp with ln θ raised by ``delta``, at κ.

    Decays: ln V and ln θ within 1e-6 of steady sliding at the end of ``periods`` linear periods; runs
    away: V crosses e^60 V_lp, or the run stalls with V above V_lp after its last crossing (the
    quasi-static blow-up in finite time).
    A large transient slip event that comes back down is neither: it ends as "decays" or "undecided".
    """
    from .simulate import run_spec
    from .spec import SliderSpec, load_history

    spec = branch.spec
    law = spec.laws[0]
    v_lp = branch.v_lp
    y_star = math.log(law.steady_factor * spec.dc[0] / v_lp)
    run = SliderSpec(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, k=kappa * branch.hopf.k_c,
                     mass=spec.mass, damping=spec.damping)
    t_end = periods * 2 * math.pi / branch.hopf.omega_c
    r = run_spec(run, load_history(v_lp), [0.0, t_end], ln_v0=math.log(v_lp), ln_theta0=[y_star + delta],
                 thresholds=[v_lp, v_lp * math.exp(60.0)], max_steps=max_steps)
    if any(c[1] == 1 and c[2] > 0 for c in r.crossings):
        return "runs away"
    ups = [c for c in r.crossings if c[1] == 0]
    if r.status in ("stalled", "nonfinite") and ups and ups[-1][2] > 0:
        # the step size collapsed with V above V_lp and rising: the finite-time blow-up (its Taylor
        # coefficients overflow before V reaches e^60 V_lp)
        return "runs away"
    if r.status == "ok" and abs(r.ln_v[-1] - math.log(v_lp)) < 1e-6 and abs(r.ln_theta[0][-1] - y_star) < 1e-6:
        return "decays"
    return "undecided"


def in_slip(state_law: str, kappa: float, delta: float, *, a=0.01, b=0.015, dc=0.01, slip_max: float = 50.0,
            ln_v_cap: float = 600.0):
    """The quasi-static slide from steady sliding with ln θ raised by ``delta``, with slip as the clock.

    An independent check of the engine's runs (scipy's Radau, rtol 1e-10, V_lp = 1): in slip δ the spike
    is gentle — x = ln V, y = ln θ, dt/dδ = e^{−x}, dy/dδ = θ̇/(θV), a dx/dδ = k(e^{−x} − 1) − b dy/dδ —
    so a transient to V ~ e^{100} is followed to its end, where a run in time stalls (steps below the
    resolution of t). Returns (outcome, max ln V, slip at the max in units of Dc): "runs away" when ln V
    passes ``ln_v_cap`` (blow-up: the slip law's V grows like exp(exp(cδ))), "returns" when the first
    spike ends (ln V back below −0.5; where the boundary is a cycle, as for PRZ, both sides of it do
    that, so this decides only one-shot runaways), "open" when neither happens within ``slip_max`` (in
    units of Dc) or the solver gives up first (steps below the spacing of δ).
    """
    import numpy as np
    from scipy.integrate import solve_ivp

    from .laws import resolve_state_law

    law = resolve_state_law(state_law)
    k = kappa * (b - a) / dc

    def dy(x, y):
        if law.name == "aging":
            return math.exp(-x - y) - 1 / dc
        if law.name == "slip":
            return -(x + y - math.log(dc)) / dc
        return math.exp(-x - y) - math.exp(x + y) / (4 * dc * dc)

    def f(_, u):
        x, y = u
        g = dy(x, y)
        return [(k * (math.exp(-x) - 1) - b * g) / a, g]

    def cap(_, u):
        return u[0] - ln_v_cap
    cap.terminal = True

    def back(_, u):   # V back below V_lp after its spike (half a unit of ln V, clear of the start)
        return u[0] + 0.5
    back.terminal, back.direction = True, -1

    y0 = math.log(law.steady_factor * dc) + delta
    sol = solve_ivp(f, (0.0, slip_max * dc), [0.0, y0], method="Radau", rtol=1e-10, atol=1e-12,
                    events=[cap, back], dense_output=False, max_step=dc / 10)
    x = sol.y[0]
    i = int(np.argmax(x))
    if sol.status == 1 and sol.t_events[0].size:
        return "runs away", float(x[i]), float(sol.t[i] / dc)
    after = x[i:]
    if after.size and after.min() < 0.0 and i > 0:
        return "returns", float(x[i]), float(sol.t[i] / dc)
    return "open", float(x[i]), float(sol.t[i] / dc)


def critical_in_slip(state_law: str, kappa: float, lo: float, hi: float, *, rel: float = 1e-3, **slider) -> tuple:
    """Bracket the critical raise Δ_c of ln θ at κ by bisection on ``in_slip`` ("returns" / "runs away").

    Where the boundary is not a cycle (the quasi-static slip law above k_c: its branch of cycles stays at
    κ = 1) this is the way to it; a run in time cannot tell a blow-up from a transient to V ~ e^50 (both
    stall near ln V ≈ 30). ``lo`` must return and ``hi`` run away (``ValueError`` otherwise). Returns the
    final (lo, hi), hi − lo ≤ ``rel``·hi; an "open" run stops it early.
    """
    f_lo, f_hi = in_slip(state_law, kappa, lo, **slider)[0], in_slip(state_law, kappa, hi, **slider)[0]
    if f_lo != "returns" or f_hi != "runs away":
        raise ValueError(f"not a bracket at κ = {kappa}: {lo} {f_lo}, {hi} {f_hi}")
    while hi - lo > rel * abs(hi):
        mid = 0.5 * (lo + hi)
        f = in_slip(state_law, kappa, mid, **slider)[0]
        if f == "returns":
            lo = mid
        elif f == "runs away":
            hi = mid
        else:
            break
    return lo, hi
