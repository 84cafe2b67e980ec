"""The Hopf point of the rate-state slider: numerical k_c, ω_c vs closed forms; l1 vs direct simulation."""

import json
import math

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models.rate_state import SliderSpec
from bifurcation.models.rate_state.hopf import hopf_point, lyapunov_by_simulation

# Corners of the parameter box (b/a ∈ [1.1, 10], V_lp over 6 decades); the report sweeps it.
BOX = [(law, ratio, v, m) for law in ("aging", "slip") for ratio in (1.1, 10.0) for v in (1e-3, 1e3)
       for m in (None, 0.3)]


@pytest.mark.parametrize("law,ratio,v_lp,mass", BOX)
def test_critical_stiffness_and_frequency_match_the_closed_forms(law, ratio, v_lp, mass):
    # Closed forms (Ruina 1983; Rice & Ruina 1983; docs/rate-state.md): k_c = (b − a)/Dc·[1 + M V²/(a Dc)],
    # ω_c = (V/Dc)√((b − a)/a). The numerical root is found at 30 digits from the eigenvalues alone,
    # so 1e-12 (the goal) is a loose bound on a ~1e-16 (double rounding of the result) agreement.
    a, dc = 0.01, 0.02
    h = hopf_point(a=a, b=ratio * a, dc=dc, state_law=law, v_lp=v_lp, mass=mass, dps=30, lyapunov=False)
    assert h.k_c == pytest.approx(h.k_c_closed_form, rel=1e-12)
    assert h.omega_c == pytest.approx(h.omega_c_closed_form, rel=1e-12)
    k_cf = (ratio * a - a) / dc * (1 + (mass or 0) * v_lp ** 2 / (a * dc))
    assert h.k_c == pytest.approx(k_cf, rel=1e-12)   # the formula typed here, not the module's


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_quasi_static_aging_and_slip_laws_are_degenerate(law):
    # Ranjith & Rice (1999): the quasi-static aging law has a family of cycles at k_c, so l1 = 0. We find
    # the same for the slip law (l1 ~ 1e-31 at 30 digits), and the direct simulation confirms it: the
    # amplitude of a cycle at k_c does not change over a period to rounding (1e-10 of the ε³ scale).
    h = hopf_point(a=0.01, b=0.015, dc=0.01, state_law=law, v_lp=1.0, dps=30)
    assert h.criticality == "degenerate" and abs(h.lyapunov_coefficient) < 1e-25
    spec = SliderSpec(a=0.01, b=0.015, dc=0.01, state_law=law, k=h.k_c)
    assert abs(lyapunov_by_simulation(spec, h, 1.0, 0.05)) < 1e-8


@pytest.mark.parametrize("law,mass,expected", [("prz", None, "subcritical"), ("prz", 1e-2, "supercritical"),
                                                ("aging", 1e-3, "supercritical"), ("slip", 1e-2, "supercritical")])
def test_lyapunov_coefficient_agrees_with_direct_simulation(law, mass, expected):
    # The growth of a small cycle at k_c over one period (engine, exact section events) is 2π l1 |z|³ + O(|z|⁴):
    # at ε = 5e-3 the measured relative gap to the normal-form l1 was 1.5e-3 (PRZ quasi-static) and
    # ≤ 1e-4 (inertial); 1e-2 allows for the O(ε) term and fails on any error of sign or factor.
    h = hopf_point(a=0.01, b=0.015, dc=0.01, state_law=law, v_lp=1.0, mass=mass, dps=30)
    assert h.criticality == expected
    spec = SliderSpec(a=0.01, b=0.015, dc=0.01, state_law=law, k=h.k_c, mass=mass)
    assert lyapunov_by_simulation(spec, h, 1.0, 5e-3) == pytest.approx(h.lyapunov_coefficient, rel=1e-2)


def test_two_state_variables_have_a_hopf_point_where_the_eigenvalues_cross():
    h = hopf_point(a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], state_law="aging", v_lp=1.0, dps=30)
    assert math.isnan(h.k_c_closed_form) and h.k_c > 0 and h.omega_c > 0
    # Just above k_c steady sliding is stable, just below it is not (eigenvalues at 30 digits).
    from bifurcation.models.rate_state.hopf import _max_real
    import mpmath as mp
    spec = SliderSpec(a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], state_law="aging", k=1)
    with mp.workdps(30):
        assert mp.re(_max_real(spec, h.k_c * (1 + 1e-9), 1.0)) < 0 < mp.re(_max_real(spec, h.k_c * (1 - 1e-9), 1.0))


def test_no_hopf_point_when_velocity_strengthening():
    with pytest.raises(InputError, match="velocity strengthening"):
        hopf_point(a=0.01, b=0.005, dc=0.01, state_law="aging", v_lp=1.0)


def test_hopf_cli_json_keys_and_bad_input():
    r = CliRunner().invoke(cli, ["hopf", "--state-law", "prz", "--a", "0.01", "--b", "0.015", "--dc", "0.01",
                                 "--v-lp", "1", "--json"])
    assert r.exit_code == 0, r.output
    rec = json.loads(r.output)
    assert {"k_c", "omega_c", "lyapunov_coefficient", "criticality"} <= set(rec)
    assert rec["criticality"] == "subcritical" and rec["k_c"] == pytest.approx(0.5, rel=1e-12)
    for bad, msg in [(["--dc", "-1"], "dc=-1.0: must be > 0"), (["--v-lp", "0"], "--v-lp=0.0: must be > 0"),
                     (["--state-law", "nope"], "is not a known state law"), (["--b", "nan"], "b=nan")]:
        args = {"--state-law": "prz", "--a": "0.01", "--b": "0.015", "--dc": "0.01", "--v-lp": "1"}
        args[bad[0]] = bad[1]
        r = CliRunner().invoke(cli, ["hopf", *[x for kv in args.items() for x in kv]])
        assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1 and msg in r.output, r.output


def test_two_state_variables_aging_stays_degenerate_and_slip_is_supercritical():
    # Two state variables, quasi-static: the aging law's l1 is still zero (3e-31 at 30 digits; the
    # simulated growth shrinks like ε² — a higher-order term — from 5.6e-8 at ε = 2e-2 to 1.5e-8 at 1e-2),
    # the slip law's is −0.01238 (simulation −0.01242 at ε = 1e-2: within the O(ε) term).
    kw = dict(a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], v_lp=1.0, dps=30)
    aging = hopf_point(state_law="aging", **kw)
    assert aging.criticality == "degenerate"
    spec = SliderSpec(a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], state_law="aging", k=aging.k_c)
    assert abs(lyapunov_by_simulation(spec, aging, 1.0, 1e-2)) < 1e-6
    slip = hopf_point(state_law="slip", **kw)
    assert slip.criticality == "supercritical" and slip.k_c == pytest.approx(aging.k_c, rel=1e-14)
    spec = SliderSpec(a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], state_law="slip", k=slip.k_c)
    assert lyapunov_by_simulation(spec, slip, 1.0, 1e-2) == pytest.approx(slip.lyapunov_coefficient, rel=1e-2)
