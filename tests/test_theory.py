"""The closed forms of ``bifurcation.theory``: algebra, limits, float64 vs mpmath, and the errata.

Comparisons with the exact cycle are in test_reference.py; here each formula is checked against
its defining property (the ODE it solves, the root it is, continuity), mostly in mpmath at dps 40.
"""

import dataclasses

import mpmath
import numpy as np
import pytest

import bifurcation.theory as theory
from bifurcation.errors import InputError
from bifurcation.theory.reference import limit_orbit_exact, piecewise_linear_exact

DPS = 40
#: mpmath at dps 40: identities hold to ~1e-38; numerical differentiation (mpmath.diff, default
#: step) is good to ~1e-30.
TIGHT = mpmath.mpf("1e-35")
DIFF = mpmath.mpf("1e-25")


@pytest.fixture(autouse=True)
def _dps():
    with mpmath.workdps(DPS):
        yield


def test_all_is_sorted_and_complete():
    assert theory.__all__ == sorted(theory.__all__)
    for name in theory.__all__:
        assert hasattr(theory, name), name


# -- parameters ----------------------------------------------------------------------------------------
def test_omega_near_one_half_has_no_cancellation():
    # ω = √|(1 − 2ν_f)(1 + 2ν_f)|/(2ν_f): at ν_f = 0.5 ± 1e-12 the naive √|α² − 1| loses ~4 digits.
    for nf in (0.5 - 1e-12, 0.5 + 1e-12, 0.3, 0.9):
        exact = mpmath.sqrt(abs(1 / (2 * mpmath.mpf(nf)) ** 2 - 1))
        # a few roundings: measured ≤ 1.3e-16; 1e-15 (4.5 ulp) is 1000 times below the naive loss
        assert abs(theory.omega(nf) / exact - 1) < 1e-15
    assert theory.omega(0.5) == 0 and theory.alpha(0.5) == 1


# -- creep, Eqs. (7)-(10) --------------------------------------------------------------------------------
CREEP_NU_F = ["0.51", "0.55", "0.7", "0.9", "0.99", "5"]


def _assert_solves_eq6(U, nu, a, t, scale):
    """U solves Eq. (6), Ü − 2αU̇ + U = νt, at t (residual within DIFF·ν·scale), from U(0) = U̇(0) = 0."""
    assert abs(mpmath.diff(U, t, 2) - 2 * a * mpmath.diff(U, t) + U(t) - nu * t) < DIFF * nu * scale
    assert abs(U(mpmath.mpf(0))) < TIGHT * nu and abs(mpmath.diff(U, 0)) < DIFF * nu


@pytest.mark.parametrize("nu_f", CREEP_NU_F)
def test_eq_7_solves_eq_6(nu_f):
    nu, n = mpmath.mpf("1e-9"), mpmath.mpf(nu_f)

    def U(t):
        return theory.displacement_creep(t, nu, n)
    t = mpmath.mpf("1.7")
    _assert_solves_eq6(U, nu, theory.alpha(n), t, scale=1)
    assert abs(mpmath.diff(U, t) - theory.velocity_linear(t, nu, n)) < DIFF * nu


@pytest.mark.parametrize("nu_f", CREEP_NU_F)
def test_eq_8_and_9(nu_f):
    nu, n = mpmath.mpf("1e-9"), mpmath.mpf(nu_f)
    w = theory.omega(n)
    # Eq. (8): U̇ at ωt = π, where Ü = ν e^{αt} sin(ωt)/ω vanishes.
    t_max = mpmath.pi / w
    assert abs(theory.velocity_linear(t_max, nu, n) / theory.max_velocity_creep(nu, n) - 1) < TIGHT
    assert abs(mpmath.diff(lambda t: theory.velocity_linear(t, nu, n), t_max)) < DIFF * nu
    # Eq. (9): t0 is the root of U̇ in (π/ω, 2π/ω).
    t0 = theory.stop_time_creep(n)
    assert mpmath.pi / w < t0 < 2 * mpmath.pi / w
    # U̇ = ν(1 + e^{αt}[...]) cancels terms of size ν·e^{αt0} at the root: scale the tolerance so.
    assert abs(theory.velocity_linear(t0, nu, n)) < TIGHT * nu * mpmath.exp(theory.alpha(n) * t0)


def test_creep_float64_matches_mpmath():
    # Float64 versions (bisection + Newton for t0) against mpmath, over the whole creep range.
    nu_f = np.array([0.5001, 0.501, 0.51, 0.6, 0.7, 0.9, 0.99, 2.0, 50.0])
    t0 = theory.stop_time_creep(nu_f)
    coeff = theory.creep_coefficient(nu_f)
    for i, nf in enumerate(nu_f):
        # 1e-14 for t0 = (π + φ + ψ)/ω, a few ulps (measured ≤ 2.2e-16). 1e-13 for the coefficient,
        # e^{αt0}-conditioned: relative error ~ αt0·ε, αt0 up to ~300 at ν_f = 0.5001 (measured 8.0e-15).
        assert abs(t0[i] / float(theory.stop_time_creep(mpmath.mpf(nf))) - 1) < 1e-14
        assert abs(coeff[i] / float(theory.creep_coefficient(mpmath.mpf(nf))) - 1) < 1e-13


def test_eq_10_erratum_printed_is_wrong_corrected_is_right():
    # Erratum (Eq. 10): both forms against the exact cycle; the corrected one (+α) must match to
    # float64 rounding, the printed one (−α) misses by 2α/(Δ/ν), over 2% here.
    erratum = next(e for e in theory.ERRATA if e.equation == "Eq. (10)")
    for nu_f, printed_miss in ((0.7, 0.023229), (0.9, 0.050915), (0.99, 0.057850)):
        nu = 1e-9
        exact = float(piecewise_linear_exact(nu, nu_f, dps=DPS)["delta"])
        a, w, t0 = theory.alpha(nu_f), theory.omega(nu_f), theory.stop_time_creep(nu_f)
        printed = nu * (np.sqrt(np.exp(2 * a * t0) - w ** 2) + t0 - a)
        corrected = theory.delta_creep(nu, nu_f)
        # float64 with αt0 ≤ 4 here: measured ≤ 8.9e-16 (4 ulp); 1e-14 allows the coefficient's
        # e^{αt0} conditioning even where it is far worse (8.0e-15 at ν_f = 0.5001, test above).
        assert abs(corrected / exact - 1) < 1e-14
        # The quoted misses are rounded to 6 decimals (≤ 5e-7 off; measured ≤ 3.9e-7).
        miss = abs(printed / exact - 1)
        assert abs(miss - printed_miss) < 1e-6
        assert f"{100 * miss:.2f}% " in erratum.evidence, (miss, erratum.evidence)


# -- Eq. (11) and the α = 1 limit ------------------------------------------------------------------------
@pytest.mark.parametrize("nu_f", ["0.05", "0.3", "0.49", "0.5"])
def test_eq_11_solves_eq_6(nu_f):
    nu, n = mpmath.mpf("1e-9"), mpmath.mpf(nu_f)

    def U(t):
        return theory.displacement_linear(t, nu, n)
    t = mpmath.mpf("0.8")
    _assert_solves_eq6(U, nu, theory.alpha(n), t, scale=max(1, U(t) / nu))


def test_eq_11_alpha_one_is_the_limit():
    # At ν_f = 1/2 exactly: ν[e^t(t − 2) + t + 2]; the neighbours ν_f = 1/2 ∓ 1e-25 agree to O(1e-25).
    nu, t = mpmath.mpf(1), mpmath.mpf(3)
    at_one = theory.displacement_linear(t, nu, mpmath.mpf("0.5"))
    assert abs(at_one - (mpmath.exp(t) * (t - 2) + t + 2)) < TIGHT
    # U moves by |∂U/∂ν_f|·1e-25 = 1.65e-23 (measured); 1e-22 is 6 times that, while a wrong branch at
    # α = 1 would be off by O(1).
    assert abs(theory.displacement_linear(t, nu, mpmath.mpf("0.5") - mpmath.mpf("1e-25")) - at_one) < 1e-22
    # float64 at U = 25.1: a few roundings of ulp(25) = 3.6e-15 (measured 0).
    assert abs(float(theory.displacement_linear(3.0, 1.0, 0.5)) - float(at_one)) < 1e-13


def test_eq_13_is_the_fast_mode_root():
    # Eq. (13) is where the fast mode alone, ν(α − ω)/(2ω)e^{(α+ω)t}, equals ν_f.
    nu, n = mpmath.mpf("1e-12"), mpmath.mpf("0.3")
    a, w = theory.alpha(n), theory.omega(n)
    t1 = theory.creep_time_asymptotic(nu, n)
    assert abs(nu * (a - w) / (2 * w) * mpmath.exp((a + w) * t1) / n - 1) < TIGHT
    with pytest.raises(InputError, match="nu_f=.*must be below 1/2"):
        theory.creep_time_asymptotic(1e-9, 0.5)


# -- the ν → 0 slip, Eqs. (14)-(18) ------------------------------------------------------------------------
LIMIT_NU_F = ["0.05", "0.2", "0.4", "0.49", "0.5"]


@pytest.mark.parametrize("nu_f", LIMIT_NU_F)
def test_eq_15_corrected_is_a_continuous_solution(nu_f):
    n = mpmath.mpf(nu_f)
    a, w = theory.alpha(n), theory.omega(n)
    t1, t2 = theory.tau1(n), theory.tau2(n)

    def U(tau):
        return theory.displacement_limit_piecewise_linear(tau, n)

    def left(tau):
        return mpmath.diff(U, tau, direction=-1)

    def right(tau):
        return mpmath.diff(U, tau, direction=1)
    # Position and velocity continuous at τ = 0 and τ1; U̇ = ν_f at both, U̇(τ2) = 0.
    for tau in (mpmath.mpf(0), t1):
        assert abs(U(tau - mpmath.mpf("1e-30")) - U(tau + mpmath.mpf("1e-30"))) < DIFF
        assert abs(left(tau) - n) < DIFF and abs(right(tau) - n) < DIFF
    assert abs(left(t2)) < DIFF
    # Each piece solves its equation: Ü = 1 − U (frictionless), Ü − 2αU̇ + U = 0 (Eq. 6, ν = 0).
    mid, last = t1 / 2, (t1 + t2) / 2
    assert abs(mpmath.diff(U, mid, 2) + U(mid) - 1) < DIFF
    assert abs(mpmath.diff(U, last, 2) - 2 * a * mpmath.diff(U, last) + U(last)) < DIFF
    # Eq. (16): sin τ1 = 1/α, cos τ1 = −ω/α; U(τ1) = ν_f(3α + ω); Eq. (14) below τ = 0.
    assert abs(mpmath.sin(t1) - 1 / a) < TIGHT and abs(mpmath.cos(t1) + w / a) < TIGHT
    assert abs(U(t1) - n * (3 * a + w)) < TIGHT
    assert abs(U(mpmath.mpf(-2)) - theory.displacement_limit_linear(mpmath.mpf(-2), n)) < TIGHT
    # U(τ2) is Eq. (18), and the block stays there.
    assert abs(U(t2) - theory.delta0_piecewise_linear(n)) < TIGHT
    assert U(t2 + 1) == U(t2)


@pytest.mark.parametrize("nu_f", LIMIT_NU_F)
def test_eq_15_printed_middle_piece_is_wrong(nu_f):
    # Erratum (Eq. 15): the printed ν_f[sin τ − (α + ω)cos τ + 1] jumps at τ = 0 by ν_f − 1 and
    # misses Ü = 1 − U by the same constant.
    n = mpmath.mpf(nu_f)
    a, w = theory.alpha(n), theory.omega(n)

    def printed(tau):
        return n * (mpmath.sin(tau) - (a + w) * mpmath.cos(tau) + 1)
    jump = printed(mpmath.mpf(0)) - theory.displacement_limit_linear(mpmath.mpf(0), n)
    assert abs(jump - (n - 1)) < TIGHT and abs(jump) >= 0.5
    # It differs from the corrected piece (which solves Ü = 1 − U, test above) by the constant ν_f − 1
    # over the whole swing, so it misses Ü = 1 − U by ν_f − 1 too.
    t1 = theory.tau1(n)
    for tau in (t1 / 4, t1 / 2, 3 * t1 / 4):
        assert abs(printed(tau) - theory.displacement_limit_piecewise_linear(tau, n) - (n - 1)) < TIGHT
    if nu_f == "0.4":
        erratum = next(e for e in theory.ERRATA if e.equation.startswith("Eq. (15), middle piece"))
        assert f"{float(jump):.1f} at ν_f = 0.4".replace("-", "\u2212") in erratum.evidence


def test_eq_18_values_and_limits():
    # √e at ν_f = 1/2 (the limit ω → 0), 2 as ν_f → 0 (frictionless swing), 0 in creep.
    # √e: a couple of roundings, 4e-16 ≈ 2 ulp(√e) (measured 0).
    assert abs(theory.delta0_piecewise_linear(0.5) - np.sqrt(np.e)) < 4e-16
    # Δ0 → 2 from below as 2 − 2(1 − ln 2)ν_f²: 6.1e-13 at ν_f = 1e-6 (measured 6.1e-13); 1e-11 leaves
    # room for float64 and still catches an approach slower than ν_f² (≥ 1e-6 for O(ν_f)).
    assert 0 < 2 - theory.delta0_piecewise_linear(1e-6) < 1e-11
    assert theory.delta0_piecewise_linear(0.7) == 0
    # float64 vs mpmath (log1p form), including next to ν_f = 1/2 where ω/α → 0.
    nu_f = np.array([1e-3, 0.05, 0.2, 0.4, 0.49, 0.499999, 0.5 - 1e-12, 0.5])
    values = theory.delta0_piecewise_linear(nu_f)
    for nf, v in zip(nu_f, values):
        # log1p form, no cancellation as ω/α → 0: measured ≤ 2.2e-16 (1 ulp); 1e-15 ≈ 4.5 ulp
        assert abs(v / float(theory.delta0_piecewise_linear(mpmath.mpf(nf))) - 1) < 1e-15
    # ... and the exact ν = 0 motion (independent of Eq. 18) agrees, as do Eqs. (16), (17): float64
    # closed forms against dps-40 values, a few roundings (measured 0), 1e-15 ≈ 4.5 ulp.
    orbit = limit_orbit_exact(0.3, dps=DPS)
    assert abs(theory.delta0_piecewise_linear(0.3) / float(orbit["delta0"]) - 1) < 1e-15
    assert abs(theory.tau2(0.3) / float(orbit["tau2"]) - 1) < 1e-15


def test_vectorised_broadcasting():
    tau = np.linspace(-3, 4, 8)
    nu_f = np.array([[0.1], [0.3], [0.5]])
    assert theory.displacement_limit_piecewise_linear(tau, nu_f).shape == (3, 8)
    assert theory.velocity_linear(tau[:, None], 1e-9, np.array([0.3, 0.5, 0.7])).shape == (8, 3)
    assert np.ndim(theory.tau1(0.3)) == 0 and isinstance(theory.tau1(mpmath.mpf("0.3")), mpmath.mpf)


# -- bad input -----------------------------------------------------------------------------------------------
def test_wrong_regime_teaches():
    with pytest.raises(InputError, match=r"nu_f=.*not in the creep regime.*use nu_f > 1/2"):
        theory.delta_creep(1e-9, 0.4)
    with pytest.raises(InputError, match=r"nu_f=.*not in the stick-slip regime"):
        theory.tau2(np.array([0.3, 0.6]))
    with pytest.raises(InputError, match=r"nu_f=.*must be positive"):
        theory.alpha(-1.0)


# -- the errata records -----------------------------------------------------------------------------------------
def test_errata_records():
    assert len(theory.ERRATA) >= 4
    equations = [e.equation for e in theory.ERRATA]
    assert any(eq.startswith("Eq. (10)") for eq in equations)
    assert any(eq.startswith("Eq. (15)") for eq in equations)
    for record in theory.ERRATA:
        assert record.printed != record.corrected
        with pytest.raises(dataclasses.FrozenInstanceError):
            record.corrected = "x"
    with pytest.raises(ValueError, match="evidence is empty"):
        theory.Erratum("Eq. (1)", "a", "b", " ")
