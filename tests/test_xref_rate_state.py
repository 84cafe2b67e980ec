"""The rate-and-state slider's Hopf points and a velocity-step series against a second independent
reference (tests/_xref_rate_state.py: no code of the package nor of tests/_indep_rate_state.py).

Hopf: (k_c, ω_c) as the root of det(J(k) − iωI) = 0, J the Jacobian of the right-hand side in
(V, θ_i[, F]) at steady sliding by mpmath.diff, 40 digits — no closed form, no eigenvalue routine.
Sets no other test uses: two state variables with mass and damping (PRZ+aging, aging+slip), a
quasi-dynamic slip+PRZ pair, one slip variable with a ≪ b and V_lp = 12, PRZ with V_lp = 1e-6 and
η = 2000, an inertial aging slider with b/a = 1.02. Measured when written: k_c within 6.1e-17 and
ω_c within 6.2e-17 relative of the package's (which finds them at 50 digits and rounds to doubles);
held to 2.3e-16 (one ulp either way).

Series: μ, V, θ after a load-point step 1 → 2.5 at t = 5 (slip law, Dc = 0.5, η = 0.05, k = 0.05), by
mpmath.odefun in (V, θ). Measured: μ within 4.9e-17, V 1.3e-16, θ 7.1e-17 relative (two other
sets, two state variables with and without mass, ≤ 1.9e-16 / 3.7e-16 / 2.2e-16). docs/rate-state.md: "our μ is
within 2e-16 relative" of the package's own mpmath reference; held to 2.3e-16 for μ and 5e-16 for V
and θ (V carries the error of ln V times e^x: a few ulps).
"""

from __future__ import annotations

import pytest

from bifurcation.models.rate_state import load_history, rate_state
from bifurcation.models.rate_state.hopf import hopf_point

import _xref_rate_state as ref
from _indep_sample import sample

HOPF = [
    (["prz"], 0.05, [0.06], [33.0], 1e-6, None, 2000.0),
    (["prz", "aging"], 0.004, [0.003, 0.005], [0.02, 0.7], 3.0, 2e-3, 0.0007),
    (["slip", "prz"], 0.011, [0.009, 0.0085], [3e-4, 5e-3], 0.07, None, 0.05),
    (["aging", "slip"], 0.0021, [0.0013, 0.0027], [1.3, 0.011], 1e-4, 0.37, 1.5),
    (["slip"], 0.0007, [0.0152], [0.0009], 12.0, 4e-6, 1e-5),
    (["aging"], 0.0132, [0.0135], [0.4], 0.9, 0.2, 0.0),
]


def _hopf(laws, a, bs, dcs, v, mass, eta):
    h = hopf_point(a=a, b=bs, dc=dcs, state_law=laws, v_lp=v, mass=mass, damping=eta, lyapunov=False)
    k, w = ref.hopf(laws, a, bs, dcs, v, mass, eta, guess=(h.k_c * (1 + 1e-6), h.omega_c * (1 + 1e-6)))
    assert abs(h.k_c - k) / k <= 2.3e-16
    assert abs(h.omega_c - w) / w <= 2.3e-16


def test_hopf_fast():
    _hopf(*HOPF[0])


@pytest.mark.slow
@pytest.mark.parametrize("case", sample(HOPF[1:], 2))
def test_hopf(case):
    _hopf(*case)


@pytest.mark.slow
def test_velocity_step_series():
    times = [0, 4, 5.5, 7, 12, 20]
    laws, a, bs, dcs, k, eta = ["slip"], 0.011, [0.0085], [0.5], 0.05, 0.05
    r = rate_state(a=a, b=bs, dc=dcs, state_law=laws, k=k, v_lp=load_history([1, 2.5], at=[5]), t=times,
                   damping=eta)
    expected = ref.series(laws, a, bs, dcs, k, [1, 2.5], [5], times, eta=eta, dps=24)
    for i, (mu, v, th) in enumerate(expected):
        assert abs(r.mu[i] - mu) / mu <= 2.3e-16, (i, "mu")
        assert abs(r.v[i] - v) / v <= 5e-16, (i, "v")
        assert abs(r.theta[0][i] - th[0]) / th[0] <= 5e-16, (i, "theta")
