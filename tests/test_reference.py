"""The mpmath references against the paper's closed forms and an independent integrator.

The reference (``bifurcation.theory.reference``) and the closed forms (``bifurcation.theory``) share no code:
the reference continues general closed-form pieces through event roots, the theory module has the
paper's formulas. Tolerances say where they come from.
"""

import math

import mpmath
import pytest
from scipy.integrate import solve_ivp

from bifurcation import theory
from bifurcation.errors import InputError
from bifurcation.theory.reference import limit_orbit_exact, piecewise_linear_exact

DPS = 40
#: At dps 40 (computed with 20 guard digits) the reference and the mpmath closed forms agree to
#: ~1e-40; 1e-30 leaves room for the conditioning of the stop-time root, without hiding any error.
EXACT = mpmath.mpf("1e-30")


def _rel(a, b):
    return abs(a - b) / abs(b)


# -- creep: Eq. (6) is exact, so Eqs. (7)-(10) must hold to working precision -------------------------
@pytest.mark.parametrize("nu_f", [0.7, 0.9])
@pytest.mark.parametrize("nu", [1e-3, 1e-9])
def test_creep_cycle_is_eqs_7_to_10(nu, nu_f):
    ref = piecewise_linear_exact(nu, nu_f, dps=DPS)
    # Eq. (8) stays below ν_f here (0.026 at ν_f = 0.7, ν = 1e-3), so the cycle never leaves Eq. (6).
    assert ref["status"] == "creep" and ref["creep_time"] is None and ref["switch_times"] == []
    assert ref["slip_duration"] is None
    with mpmath.workdps(DPS):
        nu_m, nu_f_m = mpmath.mpf(nu), mpmath.mpf(nu_f)
        assert _rel(ref["stop_time"], theory.stop_time_creep(nu_f_m)) < EXACT            # Eq. (9)
        assert _rel(ref["max_velocity"], theory.max_velocity_creep(nu_m, nu_f_m)) < EXACT  # Eq. (8)
        assert _rel(ref["delta"], theory.delta_creep(nu_m, nu_f_m)) < EXACT             # Eq. (10) corr.
        assert _rel(ref["delta"], theory.displacement_creep(ref["stop_time"], nu_m, nu_f_m)) < EXACT  # (7)


# -- stick-slip: the ν → 0 asymptotes ------------------------------------------------------------------
STICK_SLIP_NU_F = [0.2, 0.3, 0.4, 0.45]


@pytest.fixture(scope="module")
def stick_slip_runs():
    """Reference cycles on ν = 1e-6 … 1e-15 (one per decade), computed once: ~40 runs, < 2 s."""
    nus = [10.0 ** -k for k in range(6, 16)]
    return {nu_f: {nu: piecewise_linear_exact(nu, nu_f, dps=DPS) for nu in nus} for nu_f in STICK_SLIP_NU_F}


@pytest.mark.parametrize("nu_f", STICK_SLIP_NU_F)
def test_creep_time_tends_to_eq_13(stick_slip_runs, nu_f):
    runs = stick_slip_runs[nu_f]
    nus = [1e-6, 1e-9, 1e-12]
    errors = [abs(float(runs[nu]["creep_time"] - theory.creep_time_asymptotic(mpmath.mpf(nu), mpmath.mpf(nu_f))))
              for nu in nus]
    # Eq. (13) keeps only the fast mode of Eq. (11); the slow mode's relative weight at t1 is
    # e^{(λ− − λ+) t1} ∝ ν^{1 − (α − ω)²} (λ−/λ+ = (α − ω)²), so the error must fall by 1000^{that}
    # per three decades: check the slope to ±0.05 (measured: within 0.003 for ν_f ≥ 0.4; 0.016 low at
    # ν_f = 0.3 and 0.03 at 0.2, where the forcing's ν·ln(1/ν) terms, local slope 1 − 1/ln(1/ν), are as large).
    a, w = theory.alpha(nu_f), theory.omega(nu_f)
    expected_slope = 1 - (a - w) ** 2
    slopes = [math.log(e0 / e1) / math.log(1e3) for e0, e1 in zip(errors, errors[1:])]
    assert all(abs(s - expected_slope) < 0.05 for s in slopes), (errors, slopes, expected_slope)
    assert errors[-1] < 1e-6  # largest at ν_f = 0.45: 1.0e-7


@pytest.mark.parametrize("nu_f", STICK_SLIP_NU_F)
def test_delta_tends_to_eq_18(stick_slip_runs, nu_f):
    with mpmath.workdps(DPS):
        delta0 = theory.delta0_piecewise_linear(mpmath.mpf(nu_f))
        gaps = [abs(r["delta"] - delta0) for nu, r in sorted(stick_slip_runs[nu_f].items(), reverse=True)]
    assert all(g1 < g0 for g0, g1 in zip(gaps, gaps[1:])), [mpmath.nstr(g, 3) for g in gaps]
    # Same slow-mode argument: the gap ∝ ν^{1 − (α − ω)²}; at ν = 1e-15 it is 2.8e-14 (ν_f = 0.2)
    # up to 9.8e-10 (ν_f = 0.45).
    assert gaps[-1] < 1e-8


@pytest.mark.parametrize("nu_f", [0.05, 0.2, 0.4, 0.45, 0.49, 0.5])
def test_limit_orbit_is_eqs_16_to_18(nu_f):
    # Independent of Eq. (18): the exact ν = 0 piecewise motion from the fast eigen-solution.
    orbit = limit_orbit_exact(nu_f, dps=DPS)
    with mpmath.workdps(DPS):
        n = mpmath.mpf(nu_f)
        assert abs(orbit["tau1"] - theory.tau1(n)) < EXACT
        assert abs(orbit["tau2"] - theory.tau2(n)) < EXACT
        assert abs(orbit["delta0"] - theory.delta0_piecewise_linear(n)) < EXACT


# -- α = 1 exactly (the double root) --------------------------------------------------------------------
def test_alpha_one_is_continuous():
    # ν_f = 1/2 takes the double-root branch (C = 1, S = s); its neighbours take sinh/sin branches.
    # The cycle depends smoothly on ν_f, so ±1e-12 must move Δ by |dΔ/dν_f|·1e-12 (measured 8.8e-12,
    # antisymmetric to 1e-21: no jump between the branches).
    mid = piecewise_linear_exact(1e-9, 0.5, dps=DPS)
    assert mid["status"] == "stick-slip" and len(mid["switch_times"]) == 2
    shifts = [piecewise_linear_exact(1e-9, side, dps=DPS)["delta"] - mid["delta"]
              for side in ("0.499999999999", "0.500000000001")]
    assert all(abs(d) < 1e-10 for d in shifts)
    assert abs(shifts[0] + shifts[1]) < 1e-18  # second difference ~ Δ''·1e-24: no jump at α = 1
    # Eq. (11) at α = 1, ν[e^t(t − 2) + t + 2], reaches U̇ = ν_f exactly at the reference's creep time.
    with mpmath.workdps(DPS):
        v = theory.velocity_linear(mid["creep_time"], mpmath.mpf(1e-9), mpmath.mpf(0.5))
        assert abs(v - mpmath.mpf(0.5)) < EXACT


def test_alpha_one_tends_to_sqrt_e_slowly():
    # At ν_f = 1/2 the approach is logarithmic (PHYSICS.md); Δ still decreases towards √e.
    deltas = [piecewise_linear_exact(nu, 0.5, dps=DPS)["delta"] for nu in (1e-3, 1e-9, 1e-15)]
    assert deltas[0] > deltas[1] > deltas[2] > mpmath.sqrt(mpmath.e)


# -- against an independent integrator -----------------------------------------------------------------
def _scipy_piecewise(nu, nu_f):
    """DOP853 at rtol 1e-13 with switch events: good to ~1e-12 relative at ν = 1e-3."""
    a = 1 / (2 * nu_f)

    def linear(t, y):
        return [y[1], nu * t - y[0] + 2 * a * y[1]]

    def free(t, y):
        return [y[1], nu * t - y[0] + 1]

    def up(t, y):
        return y[1] - nu_f
    up.terminal, up.direction = True, 1

    def down(t, y):
        return y[1] - nu_f
    down.terminal, down.direction = True, -1

    def stop(t, y):
        return y[1]
    stop.terminal, stop.direction = True, -1

    t, y, rhs, events = 0.0, [0.0, 0.0], linear, [up, stop]
    for _ in range(10):
        sol = solve_ivp(rhs, (t, 1e3), y, method="DOP853", rtol=1e-13, atol=1e-22, events=events,
                        first_step=1e-3)
        if rhs is linear and sol.t_events[1].size:
            return sol.y_events[1][0][0], sol.t_events[1][0]
        hit = sol.t_events[0]
        t, y = hit[0], sol.y_events[0][0]
        rhs, events = (free, [down]) if rhs is linear else (linear, [up, stop])
    raise AssertionError("no stop")


@pytest.mark.parametrize("nu_f", [0.05, 0.4, 0.5, 0.501, 0.7])
def test_reference_matches_scipy(nu_f):
    ref = piecewise_linear_exact(1e-3, nu_f, dps=DPS)
    delta, stop_time = _scipy_piecewise(1e-3, nu_f)
    # 1e-11: the DOP853 run's own error (measured ≤ 1e-13) with a margin.
    assert abs(float(ref["delta"]) / delta - 1) < 1e-11
    assert abs(float(ref["stop_time"]) / stop_time - 1) < 1e-11


def test_carlson_langer_matches_scipy(carlson_langer_reference):
    # ν = 1e-3, ν_f = 0.4: odefun at dps 30 vs DOP853 at rtol 3e-14 (scipy's floor; measured 1.5e-15).
    nu, nu_f = 1e-3, 0.4
    ref = carlson_langer_reference(nu)

    def stop(t, y):
        return y[1] if t > 1 else 1.0
    stop.terminal, stop.direction = True, -1
    sol = solve_ivp(lambda t, y: [y[1], t - y[0] + y[1] / (nu_f + nu * y[1])], (0, 100), [0.0, 0.0],
                    method="DOP853", rtol=3e-14, atol=1e-25, events=stop, first_step=1e-4)
    assert abs(float(ref["delta"]) / (nu * sol.y_events[0][0][0]) - 1) < 1e-12
    assert abs(float(ref["stop_time"]) / sol.t_events[0][0] - 1) < 1e-12
    # For this law U̇ stays below ν_f at ν_f = 0.4 (max 0.355): no creep time.
    assert ref["creep_time"] is None and 0.35 < ref["max_velocity"] < 0.36


# -- bad input and bounded runs ---------------------------------------------------------------------------
def test_bad_input_names_the_argument():
    with pytest.raises(InputError, match=r"nu=-1.0: must be positive"):
        piecewise_linear_exact(-1.0, 0.4)
    with pytest.raises(InputError, match=r"nu_f='x': is not a real number"):
        piecewise_linear_exact(1e-3, "x")
    with pytest.raises(InputError, match="no stick-slip limit orbit"):
        limit_orbit_exact(0.7)


def test_no_stop_is_bounded():
    with pytest.raises(ArithmeticError, match="no stop before t = 1"):
        piecewise_linear_exact(1e-3, 0.4, t_max=1)


def test_float_and_string_inputs():
    # A float is its exact binary value (what the engine sees); a string is the decimal number.
    binary = piecewise_linear_exact(1e-3, 0.7)["delta"]
    decimal = piecewise_linear_exact("1e-3", "0.7")["delta"]
    assert binary != decimal
    # The inputs differ by 6.3e-17 relative (0.7 as a double; 1e-3 by 2e-20) and Δ moves κ ≈ 7 times
    # as much: measured 4.4e-16 (2 ulp); 1e-15 is 4.5 ulp, relative only (an absolute term, like
    # np.isclose's default atol = 1e-8, would allow 2e-7 of Δ = 0.06).
    assert _rel(binary, decimal) < 1e-15
