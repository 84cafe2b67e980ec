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

__all__ = ["critical_perturbation", "fate_of_perturbation"]


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
