"""A period doubling detected from Floquet multipliers, located, and its period-2 cycle switched onto."""

import numpy as np

from bifurcation.models.rate_state import SliderSpec, load_history
from bifurcation.models.rate_state.continuation import continue_cycles
from bifurcation.models.rate_state.simulate import run_spec
from bifurcation.models.rate_state.two_parameter import period_doubling


def test_two_state_slip_law_doubles_its_period():
    # Quasi-static slider, two slip-law state variables (b = 0.012, 0.006; Dc = 0.01, 0.1; the case of
    # docs/rate-state.md with a supercritical Hopf point). Along the branch from the Hopf point the
    # complex pair of multipliers turns real and one crosses −1 (the branch's detector flags it); the
    # located point has multiplier −1 to 1e-6, and the period-2 cycle through w_PD + 1e-3 v lies on
    # the side where the period-1 cycle is unstable (supercritical doubling) with its multipliers
    # inside 1. A direct run from it (non-terminal events at V = V_lp) alternates two return times
    # that equal the shooting map's to 1e-10 (measured 1e-15-level).
    br = continue_cycles(state_law="slip", a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], v_lp=1.0, points=16,
                         max_step=0.3, kappa_range=(0.05, 20), max_steps=500_000)
    assert len(br.period_doublings) == 1
    i = br.period_doublings[0]
    a, b = br.points[i], br.points[i + 1]
    pd = period_doubling(br, i)
    assert min(a.kappa, b.kappa) < pd.kappa < max(a.kappa, b.kappa)
    assert abs(pd.multiplier + 1) < 1e-6
    assert np.max(np.abs(np.subtract(*pd.w_2))) > 1e-4 and pd.residual_2 < 1e-12
    unstable_side = b.kappa if min(z.real for z in b.multipliers) < -1 else a.kappa
    assert (pd.kappa_2 - pd.kappa) * (unstable_side - pd.kappa) > 0
    assert max(abs(z) for z in pd.multipliers_2) < 1
    spec = br.spec
    run = SliderSpec(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, k=pd.kappa_2 * br.hopf.k_c)
    r = run_spec(run, load_history(1.0), [0.0, 2.6 * pd.period_2], ln_v0=0.0, ln_theta0=list(pd.w_2[0]),
                 thresholds=[1.0])
    gaps = np.diff([c[0] for c in r.crossings if c[2] > 0])
    assert len(gaps) >= 4 and abs(gaps[0] - gaps[1]) > 1e-5
    assert abs(gaps[0] - gaps[2]) < 1e-10 * pd.period_2 and abs(gaps[1] - gaps[3]) < 1e-10 * pd.period_2
    assert abs((gaps[0] + gaps[1]) / pd.period_2 - 1) < 1e-10
