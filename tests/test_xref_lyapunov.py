"""The first Lyapunov coefficient l1 of the rate-and-state slider's Hopf point, and its Bautin points
(l1 = 0 along the Hopf curve in η = M V²/(a Dc)), against an independent reference
(tests/_xref_lyapunov.py: no code of the package; the projection formula of Kuznetsov's book as quoted
in arXiv:2511.08428, Eq. (1), evaluated in the physical variables (V, θ_i, F) with B and C contracted
from mpmath.diff partial derivatives at 40 digits, then carried to the engine's (ln V, ln θ_i, z) by
l1/|Tq|², T = diag(1/V*, 1/θ_i*, 1)).

Parameter sets used by no other test: quasi-static PRZ, damped aging, two state variables with and
without mass and damping, inertial aging, PRZ and slip (damped). Measured when written: every
non-degenerate l1 equal to the engine's as doubles (relative difference 0; in (V, θ, F) the values differ
by factors 0.08–470 from the engine's, so the comparison does test the coordinate change, not a copy),
the degenerate quasi-static slip law ≤ 5e-41 here (engine: "degenerate"). Held to 4.5e-16: both
sides are a 40–50-digit number rounded to a double, which may straddle a rounding boundary (≤ 1 ulp
each way, 2.2e-16 relative).

Bautin points (engine: ``two_parameter.bautin_point``, secant on double l1 in ln η, returned as
exp(float)): aging a 0.006, b 0.0095, Dc 0.3, V 0.4 at η = 0.137329734952326 (reference 4.4e-16 away);
PRZ a 0.008, b 0.014, Dc 0.02, V 1.5 at η = 0.0889722581796575 (1.1e-16). Held to 1.5e-15: a few ulps
of ln η (≈ −2, ulp 4.4e-16) through exp.
"""

from __future__ import annotations

import pytest

from bifurcation.models.rate_state.hopf import hopf_point
from bifurcation.models.rate_state.two_parameter import bautin_point

import _xref_lyapunov as ref

# (laws, a, b_i, Dc_i, V_lp, M, η)
L1_CASES = [
    (["prz"], 0.007, [0.019], [0.3], 2.5, None, 0.0),                       # subcritical, l1 = 0.1511
    (["aging"], 0.012, [0.02], [0.05], 0.8, 3e-4, 0.0),                     # supercritical, −0.0427
    (["slip"], 0.009, [0.016], [0.002], 0.05, 2e-5, 0.03),                  # supercritical, −0.0827
    (["prz"], 0.004, [0.0065], [7.0], 3.0, 0.5, 0.0),                       # supercritical, −0.00305
    (["aging"], 0.011, [0.02], [0.2], 1.7, None, 0.002),                    # supercritical, −0.0841
    (["aging", "slip"], 0.008, [0.007, 0.004], [0.03, 0.5], 1.3, None, 0.0),  # supercritical, −0.0351
    (["slip", "prz"], 0.005, [0.004, 0.006], [0.2, 0.01], 0.6, 1e-3, 0.004),  # supercritical, −0.0507
]


def _compare(laws, a, bs, dcs, v, mass, eta):
    h = hopf_point(a=a, b=bs, dc=dcs, state_law=laws, v_lp=v, mass=mass, damping=eta)
    r = ref.lyapunov(laws, a, bs, dcs, v, mass, eta, guess=(h.k_c * (1 + 1e-6), h.omega_c * (1 + 1e-6)))
    assert max(r["null_residuals"]) < 1e-30          # q, p are eigenvectors to the working precision
    expected = float(r["l1_engine_coords"])
    assert abs(h.lyapunov_coefficient - expected) <= 4.5e-16 * abs(expected), (h.lyapunov_coefficient, expected)
    assert h.criticality == ("subcritical" if expected > 0 else "supercritical")


def test_l1_fast():
    _compare(*L1_CASES[0])


@pytest.mark.slow
@pytest.mark.parametrize("case", L1_CASES[1:], ids=lambda c: "+".join(c[0]) + f"-M{c[5]}-eta{c[6]}")
def test_l1(case):
    _compare(*case)


@pytest.mark.slow
def test_l1_degenerate_quasi_static_slip():
    # One slip variable, quasi-static, undamped: l1 = 0 (docs/rate-state.md: degenerate at the docs'
    # parameters); here at others, and zero in the physical variables too (coordinate-free).
    laws, a, bs, dcs, v = ["slip"], 0.006, [0.011], [0.04], 0.3
    h = hopf_point(a=a, b=bs, dc=dcs, state_law=laws, v_lp=v)
    r = ref.lyapunov(laws, a, bs, dcs, v, guess=(h.k_c * (1 + 1e-6), h.omega_c * (1 + 1e-6)))
    assert h.criticality == "degenerate"
    assert abs(r["l1"]) < 1e-35                       # 40 digits; the terms of the sum are O(0.01–1)


@pytest.mark.slow
@pytest.mark.parametrize("law,a,b,dc,v", [("aging", 0.006, 0.0095, 0.3, 0.4), ("prz", 0.008, 0.014, 0.02, 1.5)])
def test_bautin_point(law, a, b, dc, v):
    found = bautin_point("eta", (1e-3, 3.0), state_law=law, a=a, b=b, dc=dc, v_lp=v)
    assert len(found) == 1 and found[0]["inside"]
    expected = float(ref.bautin_eta(law, a, b, dc, v, found[0]["bracket"]))
    assert abs(found[0]["value"] / expected - 1) <= 1.5e-15


# --- Branches of cycles from `continue_cycles` near the Hopf point --------------------------------------
#
# Reference: the cycle of the truncated normal form ż = λ(k) z + c1 z|z|² (``_xref_lyapunov.small_cycle``:
# c1 from the same bracket as l1, λ(k) ≈ iω_c + λ'(k − k_c) with λ' = ⟨p, ∂A/∂k q⟩, all in (V, θ, F) at
# 40 digits): half-range of ln V = 2|z||q_V|/V*, |z|² = −Re λ/Re c1 (∝ √|k − k_c|: the l1 coefficient),
# period 2π/(Im λ + Im c1|z|²). Its neglected order is |z|² ∝ |1 − κ| in amplitude and |1 − κ|² in period.
# Measured when written (6 points per branch, |1 − κ| from 2.4e-7 to 1.2e-2): amplitude ratio − 1 =
# C|1 − κ| with C = −0.115 (damped aging), 2.05–2.10 (inertial aging), 1.32–1.34 (PRZ, subcritical:
# the branch goes to κ > 1), −0.10 (damped inertial slip); period T/T_nf − 1 = C'(1 − κ)² with
# |C'| = 0.31, 1.2–1.35, 0.55, 1.11; and T ω_c/2π − 1 = C''|1 − κ|, C'' = 0.96, 2.12, 0.43, 1.18.
# Held to 3|1 − κ| (amplitude, bare period) and 2(1 − κ)² (period), plus at the two innermost points
# (|1 − κ| ~ 1e-7–1e-6) what a κ off by Newton's 1e-12 stop does: ½·1e-12/|1 − κ| on the amplitude
# (∝ √|1 − κ|; measured 1.6e-6 at |1 − κ| = 4.2e-7, slip) and 2e-12 on the period.
BRANCH_CASES = [
    (["aging"], 0.011, [0.02], [0.2], 1.7, None, 0.002),     # supercritical, quasi-static damped
    (["aging"], 0.012, [0.02], [0.05], 0.8, 3e-4, 0.0),      # supercritical, inertial
    (["prz"], 0.007, [0.019], [0.3], 2.5, None, 0.0),        # subcritical
    (["slip"], 0.009, [0.016], [0.002], 0.05, 2e-5, 0.03),   # supercritical, inertial damped
]


def _branch(laws, a, bs, dcs, v, mass, eta):
    import math

    from mpmath import mpf, pi

    from bifurcation.models.rate_state.continuation import continue_cycles

    br = continue_cycles(a=a, b=bs[0], dc=dcs[0], state_law=laws[0], v_lp=v, mass=mass, damping=eta, points=6,
                         eps=1e-3, step=0.02, max_step=0.05)
    r = ref.lyapunov(laws, a, bs, dcs, v, mass, eta, guess=(br.hopf.k_c * (1 + 1e-6), br.hopf.omega_c * (1 + 1e-6)))
    period0 = float(2 * pi / r["omega_c"])
    assert len(br.points) == 6
    sub = float(r["l1"]) > 0
    for p in br.points:
        d = abs(1 - p.kappa)
        assert p.status == "ok" and 1e-7 < d < 2e-2 and (p.kappa > 1) == sub
        half, period = (float(x) for x in ref.small_cycle(r, mpf(p.kappa)))
        assert abs((p.ln_v_max - p.ln_v_min) / 2 / half - 1) <= 3 * d + 0.5e-12 / d, (p.kappa, "amplitude")
        assert abs(p.period / period - 1) <= 2 * d * d + 2e-12, (p.kappa, "period")
        assert abs(p.period / period0 - 1) <= 3 * d, (p.kappa, "period → 2π/ω_c")
    assert math.isclose(br.hopf.lyapunov_coefficient, float(r["l1_engine_coords"]), rel_tol=4.5e-16)


def test_branch_near_hopf_fast():
    _branch(*BRANCH_CASES[0])


@pytest.mark.slow
@pytest.mark.parametrize("case", BRANCH_CASES[1:], ids=lambda c: c[0][0] + f"-M{c[5]}-eta{c[6]}")
def test_branch_near_hopf(case):
    _branch(*case)


@pytest.mark.slow
def test_period_doubling_multiplier():
    # ~80 s. The one period doubling the package reports (docs/rate-state.md: two slip-law variables,
    # b = 0.012, 0.006, Dc = 0.01, 0.1, quasi-static, κ_PD = 0.87463132, μ = −1 + 3.4e-8). At the
    # engine's (κ_PD, section point w_PD) the multipliers of the return map by mpmath.odefun at 20 digits
    # (tests/_xref_lyapunov.return_map_multipliers). Measured: −0.99999999099654 (20 digits, h = 1e-8;
    # at 30 digits and h = 1e-9 −0.99999999099869, 2.2e-12 away) against the engine's −0.9999999663
    # (double central differences),
    # so μ + 1 = 9.0e-9 at κ_PD: with dμ/dκ ≈ 70 (the flagged points' multipliers), κ_PD is within
    # ~1.3e-10 of the doubling. The period agrees to 2.6e-16 relative. Held to: |μ + 1| ≤ 1e-7 (the
    # package's own claim is 3.4e-8 for its μ; 1e-7 is κ within 1.5e-9), |μ_engine − μ| ≤ 1e-7 (double
    # differences of a map known to ~1e-14), period within 1e-13 (the start's 1e-12 Newton closure).
    from bifurcation.models.rate_state.continuation import continue_cycles
    from bifurcation.models.rate_state.two_parameter import period_doubling

    laws, a, bs, dcs = ["slip", "slip"], 0.01, [0.012, 0.006], [0.01, 0.1]
    br = continue_cycles(state_law="slip", a=a, b=bs, dc=dcs, v_lp=1.0, points=16, max_step=0.3,
                         kappa_range=(0.05, 20), max_steps=500_000)
    assert len(br.period_doublings) == 1
    pd = period_doubling(br, br.period_doublings[0])
    period, mults = ref.return_map_multipliers(laws, a, bs, dcs, pd.kappa * br.hopf.k_c, 1.0, pd.w)
    mu = min(float(m.real) for m in mults)
    assert all(abs(float(m.imag)) < 1e-15 for m in mults)
    assert abs(mu + 1) <= 1e-7
    assert abs(pd.multiplier - mu) <= 1e-7
    assert abs(pd.period / float(period) - 1) <= 1e-13
