"""The unstable cycle above k_c as the basin boundary of steady sliding (quasi-static PRZ law)."""

import pytest

from bifurcation.models.rate_state.basin import critical_perturbation, fate_of_perturbation
from bifurcation.models.rate_state.continuation import continue_cycles


@pytest.fixture(scope="module")
def prz_branch():
    # subcritical Hopf point (l1 = 0.0354, docs/rate-state.md): unstable cycles for κ > 1
    return continue_cycles(state_law="prz", a=0.01, b=0.015, dc=0.01, v_lp=1.0, points=8, max_step=0.5)


def test_critical_perturbation_grows_with_kappa(prz_branch):
    # Δ_c (ln θ on the section V = V_lp) from 0.001 at κ = 1 + 2e-7 to 0.56 at κ = 1.128 (the unstable
    # cycle's amplitude ∝ √(κ − 1) near the Hopf point)
    cp = critical_perturbation(prz_branch)
    kappas, deltas = zip(*cp)
    assert all(k > 1 for k in kappas) and list(deltas) == sorted(deltas) and deltas[-1] > 0.5


@pytest.mark.parametrize("index", [5, pytest.param(6, marks=pytest.mark.slow), pytest.param(7, marks=pytest.mark.slow)])
def test_unstable_cycle_separates_decay_from_runaway(prz_branch, index):
    # From steady sliding with ln θ raised by 0.999 Δ_c the slide returns to steady sliding (within 1e-6
    # in 400 linear periods); by 1.001 Δ_c it runs away (the quasi-static blow-up). κ = 1.051, 1.103, 1.128.
    kappa, delta = critical_perturbation(prz_branch)[index]
    assert fate_of_perturbation(prz_branch, kappa, delta * (1 - 1e-3)) == "decays"
    assert fate_of_perturbation(prz_branch, kappa, delta * (1 + 1e-3)) == "runs away"
