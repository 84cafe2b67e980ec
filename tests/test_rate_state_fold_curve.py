"""The fold-of-cycles curve of the inertial aging law, continued in η up to its Bautin point."""

import math

import numpy as np
import pytest

from bifurcation.models.rate_state import SliderSpec, load_history
from bifurcation.models.rate_state.continuation import continue_cycles
from bifurcation.models.rate_state.simulate import run_spec
from bifurcation.models.rate_state.two_parameter import fold_curve

#: The Bautin point of the aging law (a = 0.01, b = 0.015, Dc = 0.01, V_lp = 1) in η = M V²/(a Dc):
#: secant root of l1 (two_parameter.bautin_point; tests/test_rate_state_two_parameter.py checks it
#: against the bracketing scan to 1e-10).
ETA_BAUTIN = 0.13807118745769834


def test_fold_curve_ends_at_the_bautin_point():
    # Start: the fold flagged on the branch in κ at η = 0.1 (continuation's tangent test); then 16 folds
    # in η up to 0.1378: every 4th of 52 equal steps and the last 3, so the end the extrapolation below
    # reads is as fine as with all 52. Each fold is a cycle (P(w) = w to 1e-12) with a multiplier 1 (to
    # 1e-9: the multiplier comes from central differences of P). Near η_B, κ_f − 1 ∝ (η_B − η)² (the fold
    # is born at zero amplitude at the Bautin point), so √(κ_f − 1) extrapolated linearly to 0 from the
    # last two points lands on η_B: measured 4.1e-6 relative from the l1 root (the same with all 52
    # steps; 1.4e-5 with 14 equal steps); 1e-5 allows for the next term.
    br = continue_cycles(state_law="aging", a=0.01, b=0.015, dc=0.01, v_lp=1.0, mass=1e-5, points=12,
                         max_step=0.04, kappa_range=(0.4, 20))
    start = br.points[br.folds[0]]
    steps = np.linspace(0.1, 0.1378, 52)
    etas = [*steps[:-3:4], *steps[-3:]]
    fc = fold_curve(etas, start.w, start.kappa, state_law="aging")
    assert len(fc) == 16 and all(f.status == "ok" for f in fc)
    assert max(f.residual for f in fc) < 1e-12 and max(f.fold_residual for f in fc) < 1e-9
    kappas = np.array([f.kappa for f in fc])
    assert np.all(kappas > 1) and np.all(np.diff(kappas) < 0)   # the fold moves down onto κ = 1
    amplitude = np.array([f.ln_v_max - f.ln_v_min for f in fc])
    assert np.all(np.diff(amplitude) < 0) and amplitude[-1] < 0.11 < 1.3 < amplitude[0]
    (e1, k1), (e2, k2) = [(f.eta, math.sqrt(f.kappa - 1)) for f in fc[-2:]]
    assert abs((e2 - k2 * (e2 - e1) / (k2 - k1)) / ETA_BAUTIN - 1) < 1e-5
    # every 3rd fold's period against a direct run (second turn, independent step grid): <= 1e-10
    for f in fc[::3]:
        spec = SliderSpec(a=0.01, b=0.015, dc=0.01, state_law="aging", k=f.k, mass=f.eta * 1e-4)
        r = run_spec(spec, load_history(1.0), [0.0, 2.5 * f.period], ln_v0=0.0, ln_theta0=[f.w[0]], z0=f.w[1],
                     thresholds=[1.0])
        ups = [c[0] for c in r.crossings if c[2] > 0]
        assert abs((ups[1] - ups[0]) / f.period - 1) < 1e-10


@pytest.mark.slow
def test_with_damping_the_fold_curve_joins_the_two_bautin_points():
    # ~8 s. Damping 1e-4 gives the aging law two Bautin points in η (0.025707, 0.112441: secant roots of
    # l1, tests/test_rate_state_two_parameter.py). The fold of cycles found on the branch at η = 0.07
    # continued both ways ends on each: √(κ_f − 1) extrapolated to 0 from the last two folds lands
    # within 1e-3 relative of them (measured 1.5e-5 and 7.5e-4: the lower end is steeper).
    br = continue_cycles(state_law="aging", a=0.01, b=0.015, dc=0.01, v_lp=1.0, mass=0.07e-4, damping=1e-4,
                         points=12, max_step=0.04, kappa_range=(0.4, 20))
    start = br.points[br.folds[0]]
    for end, eta_b in ((0.1122, 0.11244119819140375), (0.0259, 0.02570725865335719)):
        fc = fold_curve(list(np.linspace(0.07, end, 30)), start.w, start.kappa, state_law="aging", damping=1e-4)
        assert len(fc) == 30 and all(f.status == "ok" and f.kappa > 1 for f in fc)
        (e1, k1), (e2, k2) = [(f.eta, math.sqrt(f.kappa - 1)) for f in fc[-2:]]
        assert abs((e2 - k2 * (e2 - e1) / (k2 - k1)) / eta_b - 1) < 1e-3
