"""The rate-and-state slider against independent references at parameters no other test uses.

References (tests/_indep_rate_state.py, no code of the package):
* the Hopf point of one state variable in closed form, derived there (k_c = (b − a')/Dc ·
  (1 + MV²/(a'Dc)), ω_c = (V/Dc)√((b − a')/a'), a' = a + ηV), itself checked against the zero of the
  largest real part of the eigenvalues of the Jacobian of the (τ, V, θ) / (V, θ) right-hand side
  (mpmath.diff, mpmath.eig, findroot at 40 digits): they agree to ≤ 2e-40 on the 12 random sets below;
* the same numerical Hopf point for two state variables (no closed form);
* the attracting cycle by Newton shooting on V = V_lp at 45 digits with the Taylor integrator of
  tests/_indep_taylor.py in (V, θ), started from a scipy LSODA transient; the shooting residual
  (closure) is asserted below 1e-30.

Parameters: drawn from numpy default_rng(7) (Hopf) and default_rng(99) (cycles): a ∈ [0.003, 0.02],
b/a ∈ [1.1, 3], Dc and V_lp log-uniform, ηV_lp up to 0.6 (b − a), M log-uniform or 0; cycles at
κ = k/k_c ∈ [0.6, 0.9] with ηV_lp ∈ [0.1, 0.3](b − a).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner
from mpmath import mp, mpf

from bifurcation.cli import cli

import _indep_rate_state as ref
from _indep_sample import sample


def _hopf_sets():
    rng = np.random.default_rng(7)
    out = []
    for i in range(12):
        law = ["aging", "slip", "prz"][i % 3]
        a = float(rng.uniform(0.003, 0.02))
        b = float(a * rng.uniform(1.1, 3))
        dc = float(10 ** rng.uniform(-4, 0))
        v = float(10 ** rng.uniform(-6, 1))
        mass = float(10 ** rng.uniform(-7, -2)) if i % 2 else 0.0
        eta = float((b - a) / v * rng.uniform(0, 0.6)) if i % 4 != 3 else 0.0
        out.append((law, a, b, dc, v, mass, eta))
    return out


HOPF = _hopf_sets()


def _cli_json(args):
    res = CliRunner().invoke(cli, args)
    assert res.exit_code in (0, 2), res.output
    return json.loads(res.output)


def _hopf_case(law, a, b, dc, v, mass, eta):
    args = ["hopf", "--state-law", law, "--a", repr(a), "--b", repr(b), "--dc", repr(dc), "--v-lp", repr(v),
            "--damping", repr(eta), "--json"] + (["--mass", repr(mass)] if mass else [])
    out = _cli_json(args)
    with mp.workdps(40):
        kc, wc = ref.hopf_closed_form(a, b, dc, v, mass, eta)
        # The package finds k_c at 50 digits and prints the double: its rounding, 1.1e-16 relative,
        # is the whole error budget (measured ≤ 6.2e-17); 2.3e-16 allows one ulp either way.
        assert abs(out["k_c"] - kc) / kc <= 2.3e-16
        assert abs(out["omega_c"] - wc) / wc <= 2.3e-16
        return kc


def test_hopf_closed_form_fast():
    _hopf_case(*HOPF[0])                      # aging, damped, quasi-static


@pytest.mark.slow
@pytest.mark.parametrize("case", sample(HOPF[1:], 4))
def test_hopf_closed_form(case):
    kc = _hopf_case(*case)
    with mp.workdps(40):                      # the closed form checked by the second method
        law, a, b, dc, v, mass, eta = case
        kn, _wn = ref.hopf_numeric([law], a, [b], [dc], v, mass, eta, k_guess=kc * (1 + mpf(10) ** -6))
        assert abs(kn - kc) / kc <= mpf(10) ** -35


@pytest.mark.slow
def test_hopf_two_state_variables():
    """No closed form: the package's k_c against the zero of max Re λ of our own Jacobian."""
    a, bs, dcs, v = 0.0083, [0.0071, 0.0052], [0.023, 0.31], 0.47
    out = _cli_json(["hopf", "--state-law", "aging,slip", "--a", repr(a), "--b", ",".join(map(repr, bs)),
                     "--dc", ",".join(map(repr, dcs)), "--v-lp", repr(v), "--json"])
    with mp.workdps(40):
        # bracket around the one-variable closed form with b = Σb and the first Dc (a scale only)
        g, _ = ref.hopf_closed_form(a, sum(bs), dcs[0], v)
        kn, wn = ref.hopf_numeric(["aging", "slip"], a, bs, dcs, v, k_guess=g, bracket=True)
        assert abs(out["k_c"] - kn) / kn <= 2.3e-16
        assert abs(out["omega_c"] - wn) / wn <= 2.3e-16


def _cycle_sets():
    rng = np.random.default_rng(99)
    out = []
    for i in range(7):
        law = ["aging", "slip", "prz"][i % 3]
        a = round(float(rng.uniform(0.006, 0.015)), 4)
        b = round(a * float(rng.uniform(1.4, 2.5)), 4)
        dc = float(f"{10 ** rng.uniform(-3, -1):.3g}")
        v = float(f"{10 ** rng.uniform(-2, 1):.3g}")
        eta = float(f"{(b - a) / v * rng.uniform(0.1, 0.3):.3g}")
        mass = float(f"{10 ** rng.uniform(-6, -4):.3g}") if i == 6 else 0.0
        kc, _ = ref.hopf_closed_form(a, b, dc, v, mass, eta)
        k = float(f"{float(kc) * rng.uniform(0.6, 0.9):.4g}")
        out.append((law, a, b, dc, v, eta, mass, k))
    return out


CYCLES = _cycle_sets()


@pytest.mark.slow
@pytest.mark.parametrize("case", sample(CYCLES, 3))
def test_limit_cycle_against_mpmath_shooting(case):
    law, a, b, dc, v, eta, mass, k = case
    args = ["rate-state", "--state-law", law, "--a", repr(a), "--b", repr(b), "--dc", repr(dc), "--v-lp", repr(v),
            "--damping", repr(eta), "--k", repr(k), "--cycle", "--json"] + (["--mass", repr(mass)] if mass else [])
    out = _cli_json(args)
    assert out["status"] == "limit-cycle"
    r = ref.cycle_period([law], a, [b], [dc], v, k, mass, eta)
    assert r["closure"] < 1e-30
    # docs/rate-state.md ("Deep stick-slip cycles") asserts 1e-13 on the period and 1e-12 on the ln V
    # extrema against its mpmath reference; these cycles are shallower (spans ≤ 4), the same bounds.
    assert abs(out["period"] - r["period"]) / r["period"] <= 1e-13
    assert abs(out["ln_v_max"] - r["ln_v_max"]) <= 1e-12
    assert abs(out["ln_v_min"] - r["ln_v_min"]) <= 1e-12
