"""The single and damped block against a second independent reference, at parameters no other test uses.

Reference: tests/_xref_block.py (no code of the package, nor of tests/_indep_single.py): mpmath.odefun
(mpmath's own Taylor integrator, 30 digits) in U, U̇ for analytic laws, the exact solution of each
linear piece for piecewise-linear laws (40 digits). The two methods agree to ≤ 6e-31 where they solve
the same equation (test_the_two_methods_agree).

Points: ν = 1e-12 (tiny), 1e-7 and 0.3 (large), ν_f = 0.07, 0.31, 0.49, 0.51, 0.93; ten laws (the three
built-in ones and seven formulas: rational, fading, non-monotone curvature, a square root, two and
three piecewise-linear pieces); the damped block at γ = 0.3, 1.7, 4.0. Measured when written (this
machine, AVX2; all 150 + 60 points, both precisions):
* double, ν_f ≠ 0.51: ≤ 3.1e-15 relative in Δ (exp(−x)(1+x²), ν = 1e-12, ν_f = 0.07), ≤ 4.4e-15 in
  max U̇, ≤ 2.3e-16 in the stop time and t1;
* double, ν_f = 0.51 (creep, ill-conditioned: κ = |d ln Δ/d ln ν_f| ≈ 400, tests/test_precision.py):
  ≤ 2.0e-14 in Δ and max U̇ (exponential, ν = 1e-12), ≤ 1.3e-15 in the times;
* quad: ≤ 1.5e-16 everywhere (a real128 result rounded to a double: within one ulp).

Tolerances: the project's target (tests/test_precision.py) is max(1e-14, κε) in double; κε at
ν_f = 0.51 is 403 · 2.2e-16 = 9e-14 there. Quad: 2.3e-16 (one ulp either way of a correctly rounded
double).
"""

from __future__ import annotations

import math

import pytest
from mpmath import mpf

import bifurcation as bf
from bifurcation.engine.solve import solve
from bifurcation.models import get_model

import _xref_block as ref
from _indep_sample import sample

FIELDS = ("delta", "stop_time", "creep_time", "max_velocity")
KAPPA_EPS_051 = 403 * 2.220446049250313e-16     # tests/test_precision.py: κ(Δ) = 403 at ν_f = 0.51


def _tolerance(nu_f, precision):
    if precision == "quad":
        return 2.3e-16
    return KAPPA_EPS_051 if 0.5 < nu_f < 0.52 else 1e-14


def _expected_status(r, nu, nu_f, critical=0.5):
    if nu * r["stop_time"] - r["delta"] + 1 < -1:   # the spring beats static friction after the stop
        return "no-stick"
    return "creep" if (nu_f > critical and r["creep_time"] is None) else "stick-slip"


def _compare(got, r, tol, where):
    for k in FIELDS:
        value = float(got[k])
        if r[k] is None:                          # U̇ never reached ν_f: NaN by definition
            assert math.isnan(value), (where, k, value)
            continue
        rel = abs(mpf(value) - r[k]) / abs(r[k])
        assert rel <= tol, (where, k, value, float(r[k]), float(rel))


def _check_slip(law, nu, nu_f, precision):
    r = ref.cycle(law, nu, nu_f, dps=30)
    p = bf.slip(law, nu=nu, nu_f=nu_f, precision=precision)
    assert p.status_names()[()] == _expected_status(r, nu, nu_f)
    _compare({k: getattr(p, k) for k in FIELDS}, r, _tolerance(nu_f, precision), (law, nu, nu_f, precision))


def _check_damped(law, gamma, nu_f, nu):
    r = ref.cycle(law, nu, nu_f, gamma, dps=30)
    out = solve(get_model("damped-block"), law, {"gamma": [gamma], "nu_f": [nu_f], "nu": [nu]})
    status = str(bf.Status(int(out["status"].ravel()[0])))
    assert status == _expected_status(r, nu, nu_f, critical=1 / (2 + gamma)), (law, gamma, nu_f, nu, status)
    _compare({k: out[k].ravel()[0] for k in FIELDS}, r, 1e-14, (law, gamma, nu_f, nu))


# -- fast: exact linear pieces (≤ 0.4 s of mpmath each; a formula would add its compile, ~5 s) -------------
THREE_PIECES = "piecewise(1 - x, 0.5, 0.5 - (x - 0.5)/5, 2, 0.2)"


@pytest.mark.parametrize("law,nu,nu_f", [("piecewise-linear", 0.3, 0.31), ("piecewise-linear", 1e-12, 0.07)])
def test_linear_pieces_exact(law, nu, nu_f):
    _check_slip(law, nu, nu_f, "double")


def test_damped_block_linear_pieces_exact():
    """γ = 1.7: the creep threshold moves to ν_f* = 1/3.7; ν_f = 0.2 sticks and slips below it."""
    _check_damped("piecewise-linear", 1.7, 0.2, 1e-9)


# -- slow: every law, tiny and large ν ------------------------------------------------------------------
LAWS = ["carlson-langer", "exponential", "piecewise-linear", THREE_PIECES, "1/(1+x+x^2)", "exp(-x-x^2)",
        "exp(-x)*(1+x*x)", "(1+x)*exp(-2*x)", "1/sqrt(1+2*x)", "piecewise(1 - x, 1, 0)"]
POINTS = [(law, nu, nu_f) for law in LAWS for nu in (1e-12, 0.3) for nu_f in (0.07, 0.31, 0.49, 0.51, 0.93)]


@pytest.mark.slow
@pytest.mark.parametrize("law,nu,nu_f", sample(POINTS, 25))   # 4 of 100; BIFURCATION_INDEP=all: every one
@pytest.mark.parametrize("precision", ["double", "quad"])
def test_slip_against_odefun(law, nu, nu_f, precision):
    _check_slip(law, nu, nu_f, precision)


@pytest.mark.slow
@pytest.mark.parametrize("law,gamma,nu_f,nu", sample([
    ("carlson-langer", 0.3, 0.31, 1e-9), ("carlson-langer", 0.3, 0.49, 1e-9),    # 0.49 creeps: ν_f* = 1/2.3
    ("exponential", 1.7, 0.2, 1e-6), ("1/(1+x+x^2)", 1.7, 0.31, 1e-6), ("carlson-langer", 0.3, 0.93, 0.01)], 2))
def test_damped_block_against_odefun(law, gamma, nu_f, nu):
    _check_damped(law, gamma, nu_f, nu)


@pytest.mark.slow
def test_damped_block_that_never_stops_says_so():
    """γ = 4, ν = 0.3, ν_f = 0.15: the damped block settles into steady sliding (U̇ → ν), so there is no
    cycle to report. The exact pieces find no stop up to t = 60; the engine must say no-stop (at its
    t_max = 1e5), not return a number."""
    with pytest.raises(RuntimeError, match="no stop"):
        ref.linear_cycle("piecewise-linear", 0.3, 0.15, 4.0, dps=30, t_max=60)
    out = solve(get_model("damped-block"), "piecewise-linear", {"gamma": [4.0], "nu_f": [0.15], "nu": [0.3]})
    assert str(bf.Status(int(out["status"].ravel()[0]))) == "no-stop"
    assert math.isnan(float(out["delta"].ravel()[0]))


@pytest.mark.slow
def test_the_two_methods_agree():
    """odefun and the exact pieces on Φ = 1 − x (no kink): measured ≤ 6e-31 (dps 30)."""
    ref.LINEAR["_linear"] = [(0, 0, 1)]
    try:
        for nu, nu_f, gamma in [(1e-3, 0.93, 0), (0.3, 0.7, 0.2), (1e-12, 0.93, 0)]:
            a = ref.smooth_cycle("_linear", nu, nu_f, gamma, dps=30)
            b = ref.linear_cycle("_linear", nu, nu_f, gamma, dps=30)
            for k in FIELDS:
                if b[k] is None:
                    assert a[k] is None
                else:
                    assert abs(a[k] - b[k]) <= mpf(10) ** -28 * abs(b[k]), k
    finally:
        del ref.LINEAR["_linear"]


@pytest.mark.slow
@pytest.mark.parametrize("law,nu_f", sample([(law, nu_f) for law in ["exponential", "1/(1+x+x^2)", "exp(-x)*(1+x*x)",
                                                                      "1/sqrt(1+2*x)", "(1+x)*exp(-2*x)"]
                                             for nu_f in (0.07, 0.31, 0.49)], 8))
def test_limit_against_odefun(law, nu_f):
    """bf.limit's Δ0 and max U̇ against the ν = 0 orbit started ε along the fast eigenvector.

    The start error is O(ε^{2−λ−/λ+}): ε = 1e-18 and 1e-22 changed Δ0 by ≤ 1.6e-33 at ν_f = 0.07, 0.31
    and 1.8e-23 at 0.49 (carlson-langer, measured when written); ε = 1e-22 here. Measured (double): Δ0
    ≤ 3.0e-16 for ν_f ≤ 0.31, 4.0e-16 (Δ0) and 4.8e-16 (max U̇) for 1/(1+x+x²) at 0.49, where the limit
    orbit's conditioning grows towards 1/2 (docs/engine.md, "Precision": double and real128 limits agree to ≤ 5e-15 at 1/2);
    quad ≤ 1e-16. Held to 1e-15.
    """
    b = ref.limit_delta0(law, nu_f, eps=mpf("1e-22"), dps=28)
    lim = bf.limit(law, nu_f=nu_f)
    assert abs(mpf(float(lim.delta0)) - b["delta0"]) / b["delta0"] <= 1e-15
    assert abs(mpf(float(lim.max_velocity0)) - b["max_velocity0"]) / b["max_velocity0"] <= 1e-15


@pytest.mark.slow
@pytest.mark.parametrize("law", ["carlson-langer", "exponential", "1/(1+x+x^2)"])
def test_precision_just_above_one_half_off_the_grid(law):
    """docs/engine.md, "Precision": off tests/test_precision.py's grid, ν_f just above 1/2 (0.502, 0.505, 0.52),
    double Δ within max(1e-14, κε), κ = |d ln Δ/d ln ν_f| from two quad runs (ν_f and ν_f(1 + 1e-9),
    given as decimals, so read exactly in real128). Reference: quad, which agrees with the mpmath
    references above to ≤ 1.5e-16. Measured when written (AVX2): error/bound ≤ 0.72 over 225 points."""
    from decimal import Decimal

    nus = ["1e-9", "1e-12", "1e-13"]
    for nu_f in ["0.502", "0.505", "0.52"]:
        q = bf.slip(law, nu=nus, nu_f=nu_f, precision="quad").delta
        bumped = bf.slip(law, nu=nus, nu_f=str(Decimal(nu_f) * (1 + Decimal("1e-9"))), precision="quad").delta
        kappa = abs(bumped / q - 1) / 1e-9
        d = bf.slip(law, nu=[float(x) for x in nus], nu_f=float(nu_f), batch=1).delta
        err = abs(d / q - 1)
        bound = [max(1e-14, k * 2.220446049250313e-16) for k in kappa]
        assert all(e <= b for e, b in zip(err, bound)), (law, nu_f, err, kappa)


@pytest.mark.slow
@pytest.mark.parametrize("law,nu,nu_f", sample([("exp(-x-x^2)", 0.3, 0.07), ("exp(-x-x^2)", 1e-6, 0.02),
                                                ("exp(-x-x^2)", 1e-6, 0.01)], 2))
def test_fading_friction_small_nu_f(law, nu, nu_f):
    """A Gaussian fade: Φ = e^{−x−x²} is below 1e-300 for most of the slip (x = U̇/ν_f up to 50–100)
    and comes back within Δx ≈ 0.1 before the stop, the case the engine's rungs are for (docs/engine.md, "Friction
    that fades"). The reference restarts odefun at every h where Φ is invisible to it (tests/_xref_block.py;
    without that it stepped over the return, 3.7e-4 off at ν_f = 0.01, where the engine, scipy DOP853 with
    max_step 0.01 and the restarted reference agree). Measured: ≤ 3e-16 (24 s, 77 s, 224 s)."""
    _check_slip(law, nu, nu_f, "double")
