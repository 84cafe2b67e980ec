"""Friction laws given as formulas: the whitelist parser, the drop's precision, the refusals.

References are closed forms evaluated independently here in mpmath at dps 50 (or numpy's expm1), the
built-in laws of ``bifurcation.laws.builtin``, and Eq. (12) of Vasconcelos, PRL 76, 4865 (1996).
"""

import heyoka as hy
import mpmath
import numpy as np
import pytest

import bifurcation.engine as engine
from bifurcation.errors import InputError
from bifurcation.laws import resolve_law
from bifurcation.laws.builtin import carlson_langer, exponential, piecewise_linear
from bifurcation.laws.formula import parse_formula

X = hy.make_vars("x")
#: Sample points of the brief, spanning the near-zero region (where 1 − Φ cancels) and large x.
POINTS = [1e-12, 1e-6, 1e-3, 0.1, 1.0, 10.0]
#: A wider grid: from deep underflow territory to well past the slip velocities the engine reaches.
GRID = [0.0, 1e-300, 1e-15] + [10.0 ** (k / 4) for k in range(-40, 9)]
#: Relative tolerance of a double-precision drop: 1e-15 ≈ 4.5 ulp (ε = 2.2e-16), room for the few
#: roundings of the defect form. Measured: parsed and built-in drops are identical (0); against the
#: closed forms ≤ 3.7 ulp (8.1e-16) over GRID.
ULP4 = 1e-15


def double(value):
    return hy.expression(float(value))


def quad(value):
    return hy.expression(hy.real128(str(value)))


def evaluate(law, xs, num=double, fp_type=None):
    """g(x) of ``law`` at ``xs`` through heyoka compiled functions (one per piece), as the engine sees it."""
    xs = np.asarray(xs, dtype=float)
    out = np.empty(len(xs), dtype=object if fp_type is not None else float)
    for k, piece in enumerate(law.pieces):
        mask = np.array([law.piece_index(v) == k for v in xs])
        if not mask.any():
            continue
        options = {} if fp_type is None else {"fp_type": fp_type}
        cf = hy.cfunc([piece.drop(X, num)], vars=[X], **options)
        inputs = xs[mask] if fp_type is None else np.array([fp_type(v) for v in xs[mask]])
        out[mask] = cf(inputs.reshape(1, -1))[0]
    return out


def relative_error(value, reference) -> float:
    with mpmath.workdps(50):
        return float(abs(mpmath.mpf(str(value)) - reference) / abs(reference))


# -- closed forms, independent of the module; evaluated with enough digits to survive their own
# -- cancellation (dps 60 + log10(1/x)), then compared at dps 50 -----------------------------------------
CLOSED_FORMS = {
    # Carlson–Langer, Eq. (19): g = x/(1 + x)
    "1/(1+x)": lambda x: x / (1 + x),
    # exponential law (builtin.exponential): g = −expm1(−x)
    "exp(-x)": lambda x: -mpmath.expm1(-x),
    "1/(1+x/2)^2": lambda x: 1 - 1 / (1 + x / 2) ** 2,
    "1/sqrt(1+2*x)": lambda x: 1 - 1 / mpmath.sqrt(1 + 2 * x),
    "cos(x) - sin(x)": lambda x: 1 - mpmath.cos(x) + mpmath.sin(x),
    "atan(1 - 2*x) + 1 - pi/4": lambda x: mpmath.pi / 4 - mpmath.atan(1 - 2 * x),
    "2/(1 + exp(2*x))": lambda x: mpmath.tanh(x),
    "(1 + x/7)^-7": lambda x: 1 - (1 + x / 7) ** -7,
    "1 - log1p(x)": lambda x: mpmath.log1p(x),
    "1 - tanh(x)": lambda x: mpmath.tanh(x),
    "1/(1+x) + (exp(x) - 1 - x)*0.3": lambda x: x / (1 + x) - (mpmath.expm1(x) - x) * mpmath.mpf("0.3"),
}


def reference_drop(text, x):
    x = mpmath.mpf(x)
    with mpmath.workdps(60 + max(0, int(-mpmath.log10(x))) if x > 0 else 60):
        value = CLOSED_FORMS[text](x)
    with mpmath.workdps(50):
        return +value


# -- agreement with the built-in laws -----------------------------------------------------------------
def test_carlson_langer_matches_builtin():
    parsed, builtin = parse_formula("1/(1+x)"), carlson_langer()
    assert len(parsed.pieces) == 1  # no near-zero split: the drop is exact in defect form everywhere
    got, expected = evaluate(parsed, POINTS), evaluate(builtin, POINTS)
    np.testing.assert_allclose(got, expected, rtol=ULP4, atol=0)
    for x, value in zip(POINTS, got):
        assert relative_error(value, reference_drop("1/(1+x)", x)) <= ULP4


def test_exponential_matches_closed_form():
    parsed = parse_formula("exp(-x)")
    got = evaluate(parsed, POINTS)
    # closed form g = −expm1(−x) (numpy) and the built-in exponential law
    np.testing.assert_allclose(got, -np.expm1(-np.array(POINTS)), rtol=ULP4, atol=0)
    np.testing.assert_allclose(got, evaluate(exponential(), POINTS), rtol=ULP4, atol=0)


def test_parsed_laws_give_the_builtin_slips():
    """The engine sees the same drop: Δ equal to the built-in laws' (ν = 1e-9, ν_f = 0.3)."""
    for name, text in [("carlson-langer", "1/(1+x)"), ("piecewise-linear", "piecewise(1 - x, 1, 0)")]:
        parsed = engine.slip(parse_formula(text), nu=[1e-9], nu_f=[0.3])
        builtin = engine.slip(name, nu=[1e-9], nu_f=[0.3])
        # Measured identical: the drops agree bit for bit, so the integrations do; ULP4 would still
        # admit an equal drop written with its roundings in another order.
        np.testing.assert_allclose(np.asarray(parsed.delta, float), np.asarray(builtin.delta, float),
                                   rtol=ULP4)


# -- relative precision of the drop ------------------------------------------------------------------
def test_naive_drop_cancels_at_tiny_x():
    # Why the defect form (test_full_relative_precision_everywhere covers x = 1e-15 in GRID): the naive
    # 1 − 1/(1 + 1e-15) is off by ~10 % in double.
    x = 1e-15
    assert relative_error(1 - 1 / (1 + x), reference_drop("1/(1+x)", x)) > 1e-2


@pytest.mark.parametrize("text", sorted(CLOSED_FORMS))
def test_full_relative_precision_everywhere(text):
    """A few ulps at every x: no hole above a near-zero region (where 1 − Φ would cost ε/x)."""
    values = evaluate(parse_formula(text), GRID)
    assert GRID[0] == 0.0 and values[0] == 0.0  # Eq. (3): g(0) = 0 exactly
    worst = max(relative_error(v, reference_drop(text, x)) for x, v in zip(GRID[1:], values[1:]))
    assert worst <= ULP4, (text, worst)


def test_drop_mp_full_precision():
    for text in ("1/(1+x)", "1/sqrt(1+2*x)", "atan(1 - 2*x) + 1 - pi/4"):
        law = parse_formula(text)
        with mpmath.workdps(50):
            for x in (mpmath.mpf("1e-40"), mpmath.mpf("1e-8"), mpmath.mpf(3)):
                # drop_mp works at the caller's dps 50, so a few units of 1e-50 (measured ≤ 2.7e-51);
                # 1e-45 allows the defect form's roundings and still needs 45 correct digits.
                assert abs(law.drop_mp(x) / reference_drop(text, x) - 1) < mpmath.mpf("1e-45"), text


def test_taylor_coefficients_of_exp():
    # g = −expm1(−x) = Σ (−1)^(k+1) x^k / k!  (k ≥ 1)
    coefficients = parse_formula("exp(-x)").drop_taylor(10)
    for k, c in enumerate(coefficients):
        exact = 0 if k == 0 else (-1) ** (k + 1) / mpmath.factorial(k)
        # drop_taylor works at dps 60 (measured exact here); the manifold series that uses the
        # coefficients truncates its tail at 1e-40 relative (engine/manifold.py), so they must beat that.
        assert abs(c - exact) < mpmath.mpf("1e-40")


def test_real128_constants():
    if not hasattr(hy, "real128"):
        pytest.skip("this heyoka build has no real128")
    for text in ("1/(1+x)", "exp(-x)", "1/sqrt(1+2*x)", "atan(1 - 2*x) + 1 - pi/4"):
        law = parse_formula(text)
        try:
            values = evaluate(law, [1e-15, 0.1, 3.0], num=quad, fp_type=hy.real128)
        except (TypeError, ValueError) as exc:  # pragma: no cover - depends on the heyoka build
            pytest.skip(f"cfunc does not take fp_type=real128 here ({exc})")
        for x, value in zip([1e-15, 0.1, 3.0], values):
            # real128 has 113 bits (ε = 1.9e-34); constants reach it with 40 digits
            assert relative_error(value, reference_drop(text, x)) <= 1e-33, (text, x)


# -- piecewise laws -----------------------------------------------------------------------------------
def test_piecewise_linear_is_eq12():
    law = parse_formula("piecewise(1 - x, 1, 0)")
    assert law.breakpoints == (1.0,)
    assert [p.text for p in law.pieces] == ["1 - x", "0"]
    points = [0.0, 1e-15, 0.25, 0.999, 1.0, 1.5, 100.0]
    # Eq. (12): Φ = 1 − x on [0, 1], 0 above, so g = min(x, 1); and the built-in law
    np.testing.assert_array_equal(evaluate(law, points), np.minimum(points, 1.0))
    np.testing.assert_array_equal(evaluate(law, points), evaluate(piecewise_linear(), points))
    assert law.phi(0.25) == 0.75 and law.phi(2.0) == 0.0


def test_piecewise_with_inexact_breakpoint_is_continuous():
    # meets at the decimal 0.1; the engine switches at the double nearest 0.1
    law = parse_formula("piecewise(1 - x, 0.1, 0.9 - (x - 0.1)/2, 0.5, 0.7*exp(-(x - 0.5)/0.7))")
    assert law.breakpoints == (0.1, 0.5)
    with mpmath.workdps(40):
        for left, right, b in [(0, 1, 0.1), (1, 2, 0.5)]:
            assert law.pieces[left].drop_mp(b) == law.pieces[right].drop_mp(b)
        # 1 − Φ at 0.3 = 0.1 + 0.2/2 (the middle piece), but the piece starts at the double nearest
        # 0.1, 5.6e-18 above it: g(0.3) = 0.15 + fl(0.1)/2 is 2.8e-18 above 0.2 (measured). 1e-17
        # allows that rounding (at most ulp(0.1)/4 = 3.5e-18) and nothing more.
        assert abs(law.drop_mp(mpmath.mpf("0.3")) - mpmath.mpf("0.2")) < 1e-17


# -- metadata and the registry ------------------------------------------------------------------------
def test_metadata():
    law = parse_formula(" 1 / (1 + x/2)^2 ")
    assert law.name == "1/(1+x/2)^2"
    assert law.formula == " 1 / (1 + x/2)^2 "
    assert law.equation == "Φ(x) = 1 / (1 + x/2)^2"
    assert law.source == "user formula"


def test_resolve_law_formula():
    law = resolve_law("exp(-x/2)*0+1/(1+x)")
    assert law.name == "exp(-x/2)*0+1/(1+x)"
    np.testing.assert_allclose(evaluate(law, POINTS), evaluate(carlson_langer(), POINTS), rtol=ULP4)


def test_unicode_minus_and_constants():
    law = parse_formula("exp(−x) + 0*e*pi")
    assert law.name == "exp(-x)+0*e*pi"
    np.testing.assert_allclose(evaluate(law, POINTS), -np.expm1(-np.array(POINTS)), rtol=ULP4)


# -- refusals -----------------------------------------------------------------------------------------
REFUSED = [
    ("__import__('os')", ["unknown function '__import__'"]),
    # a call that would have side effects is refused before anything is evaluated
    ("exec('import os') + 1 - x", ["unknown function 'exec'"]),
    ("x.__class__", ["attribute"]),
    ("open('f')", ["unknown function 'open'"]),
    ("y+1", ["unknown name 'y'", "the variable is x"]),
    ("foo(x)", ["unknown function 'foo'", "functions: exp, log"]),
    ("1/(1+x)^2", ["Φ'(0) = -2", "Eq. 3"]),
    ("1-2*x", ["Φ'(0) = -2", "Eq. 3"]),
    ("exp(-x)*(1+x)", ["Φ'(0) = 0.0;", "Eq. 3"]),   # slope exactly 0: shown as 0, not a -5.6e-45 residue
    ("2-x", ["Φ(0) = 2", "Eq. 3"]),
    ("log(x)", ["'log(x)' is not finite at x = 0"]),
    ("1/x", ["'1/x'", "x = 0", "division by zero"]),
    ("sqrt(x)", ["'sqrt(x)' is not analytic at x = 0"]),
    ("1 - x + x^2.5", ["'x^2.5' is not analytic at x = 0"]),
    ("1 + log(1 - x)", ["not real and finite at x = 1"]),
    ("piecewise(1-x, 1, 0.5)", ["discontinuous at x = 1.0", "jumps from 0.0 to 0.5"]),
    ("piecewise(1-x)", ["odd number", "got 1"]),
    ("piecewise(1-x, 1)", ["odd number", "got 2"]),
    ("piecewise(1-x, 1, 0, 2)", ["odd number", "got 4"]),
    ("piecewise(1-x, -1, 0)", ["breakpoint -1 must be > 0"]),
    ("piecewise(1-x, 0.5, 0.5, 0.25, 0.75)", ["breakpoints must increase", "0.5 then 0.25"]),
    ("piecewise(1-x, x, 0)", ["breakpoint 'x' depends on x"]),
    ("exp(piecewise(1-x, 1, 0))", ["piecewise(...) is only allowed as the whole formula"]),
    ("1 +", ["syntax error at the end"]),
    ("1 ^^ x", ["syntax error at column 4"]),
    ("", ["is empty"]),
    ("x if x<1 else 0", ["conditional expressions", "piecewise"]),
    ("x" * 10_000, ["10000 characters", "limit is 500"]),
    ("-" * 60 + "x", ["nested", "limit is 50"]),
    ("1e400*x", ["number 1e400 is too large for double precision"]),
    ("x % 2", ["operator '%' is not allowed"]),
    ("x[0]", ["indexing"]),
    ("lambda: x", ["lambda is not allowed"]),
    ("x < 1", ["comparisons are not allowed"]),
    ("'1 - x'", ["not allowed; only real numbers"]),
    ("exp(x=1)", ["keyword arguments"]),
    ("exp(x, 2)", ["exp takes one argument, got 2"]),
    ("x**(9**9**9)", ["too large for double precision"]),
    # poles between the sample points, found by interval arithmetic over 0 ≤ x ≤ 1e5 (laws._intervals);
    # the places are closed forms: π/2; the root (1 + √1.8)/0.4 of 1 + x − 0.2x²; 0.5 + π/2
    ("1 - tan(x)", ["near x = 1.5707963268", "tan at x"]),
    ("1/(1 + x - 0.2*x^2)", ["near x = 5.85410196625", "division by 1 + x - 0.2*x^2 = 0"]),
    ("piecewise(1 - x, 0.5, 0.5 + 0.001*tan(x - 0.5))", ["near x = 2.070796326", "tan"]),
    # undefined on (1.99, 2.01) only, between the samples 1.78 and 3.16 (0 * NaN is NaN in the engine)
    ("1/(1+x) + 0*sqrt((x - 2)^2 - 0.0001)", ["near x = 1.99", "sqrt of (x - 2)^2 - 0.0001 < 0"]),
]


@pytest.mark.parametrize("text,words", REFUSED, ids=[t[:30] for t, _ in REFUSED])
def test_refused(text, words):
    with pytest.raises(InputError) as info:
        parse_formula(text)
    error = info.value
    assert error.argument == "law"
    message = str(error)
    assert "\n" not in message
    for word in words:
        assert word in message, (word, message)


def test_refusal_tells_how_to_write_a_law():
    with pytest.raises(InputError) as info:
        parse_formula("foo(x)")
    assert "write Φ as a formula in x, e.g. 'exp(-x)'" in info.value.fix


def test_refused_through_resolve_law():
    with pytest.raises(InputError, match=r"Φ'\(0\) = -2"):
        resolve_law("1/(1+x)^2")


@pytest.mark.parametrize("pole", [0.0123456789, 0.987654321, 3.14159, 47.5, 1234.5678, 98765.4321])
def test_a_pole_anywhere_in_range_is_found_where_it_is(pole):
    # Φ = 1/(1+x) + 0·x/(x − c) is Carlson–Langer with a pole at x = c (a closed form): the engine would
    # meet 0·inf = NaN there. Samples miss it unless c is one of them; interval arithmetic must corner it:
    # its narrowest interval is 1e-12 · max(x, 1) wide, and the message prints 12 significant digits.
    with pytest.raises(InputError, match=r"near x = ") as info:
        parse_formula(f"1/(1+x) + 0*x/(x - {pole!r})")
    where = float(str(info.value).split("near x = ")[1].split(":")[0])
    assert abs(where - pole) <= 1e-12 * max(pole, 1) + 1e-11 * pole


@pytest.mark.parametrize("text", ["1/(1+x)", "exp(-x)", "1/(1 + x + 0.1*sin(x)^2)", "1/(1+x)^0.5/(1+x)^0.5",
                                  "1/(1 + x + x^2/(1 + x^2))", "piecewise(1 - x, 1, 0)"])
def test_laws_finite_everywhere_pass_the_interval_check(text):
    parse_formula(text)   # no pole, no undefined point on 0 ≤ x ≤ 1e5: must not be refused
