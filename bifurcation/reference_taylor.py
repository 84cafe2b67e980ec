"""An independent high-precision Taylor integrator for one slip cycle of smooth and piecewise laws.

Nothing here uses heyoka, the engine or the law parser: each law is written again by hand in mpmath
(``REFERENCE_LAWS``) as a rule that turns the Taylor series of x(t) into the Taylor series of Φ(x(t)).
It is the yardstick of ``tests/test_fading.py`` for friction that fades faster than any power at high
x (docs/engine.md, "Friction that fades").

Equation (docs/engine.md): the unscaled cycle from rest at the static threshold,

    Ü = νt − U + 1 − Φ(U̇/ν_f),   U(0) = U̇(0) = 0,

until U̇ first returns to 0 (Δ = U there), and the ν → 0 limit, Ü = −U + 1 − Φ(U̇/ν_f), started on
the fast eigen-solution U = a·e^{λt}, λ = α + sqrt(α² − 1), α = 1/(2ν_f), at amplitude a = 1e-45 (the
neglected curvature is O(a) relative), until U̇ returns to 0 (Δ0 = U there).

How it differs from the engine, so that it cannot share its blind spot:

* Φ's series is computed from Φ itself (``exp`` of the exponent's series, quotients, products), never
  as 1 − g, so its coefficients keep full *relative* precision however small Φ is (mpmath numbers
  have an unbounded exponent: e^{−20000} is a number, not zero).
* Step control: the last two coefficients of U and U̇ against 10^−(dps+5) of the state, *and*, on
  pieces that fade exponentially (whose Taylor coefficients are all ∝ Φ, so that a tiny Φ hides
  them from that control), a cap: Φ may grow by at most e^``_MAX_LOG_CHANGE`` over a step, counted
  from 10^−(dps+10) when it starts below that level. A step that starts where friction is
  negligible thus ends before friction becomes visible, and no step lets Φ grow by more than e²
  (its order-``_ORDER`` polynomial then represents Φ to ≪ 10^−dps relative).
* Breakpoints, the stop: located on the step's polynomial by scanning 16 points and bisection to
  working precision; the step is cut there.

Cost: ~0.02 s per step at dps 50; a cycle is a few hundred to a few thousand steps. Too slow for the
test suite, so ``tests/data/fading_reference.json`` holds values produced once by
``tests/make_fading_reference.py``.
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath

__all__ = ["REFERENCE_LAWS", "ReferenceLaw", "taylor_cycle", "taylor_limit"]

_ORDER = 36
_MAX_LOG_CHANGE = 2
_SCAN = 16


# -- series arithmetic (coefficients c_k = y^(k)/k!), one coefficient at a time ---------------------
class _Node:
    """A series whose coefficient k needs the coefficients ≤ k of its inputs only (cached)."""

    def __init__(self, *args) -> None:
        self.args, self.c = args, []

    def __call__(self, k: int):
        while len(self.c) <= k:
            self.c.append(self._next(len(self.c)))
        return self.c[k]


class _X(_Node):
    def __init__(self, x: list) -> None:
        super().__init__()
        self.x = x

    def _next(self, k):
        return self.x[k]


class _Const(_Node):
    def _next(self, k):
        return mpmath.mpf(self.args[0]) if k == 0 else mpmath.mpf(0)


class _Add(_Node):
    def _next(self, k):
        a, b, sign = self.args
        return a(k) + sign * b(k)


class _Mul(_Node):
    def _next(self, k):
        a, b = self.args
        return mpmath.fsum(a(i) * b(k - i) for i in range(k + 1))


class _Div(_Node):
    def _next(self, k):
        a, b = self.args
        return (a(k) - mpmath.fsum(self.c[j] * b(k - j) for j in range(k))) / b(0)


class _Exp(_Node):
    def _next(self, k):
        (s,) = self.args
        if k == 0:
            return mpmath.exp(s(0))
        return mpmath.fsum(j * s(j) * self.c[k - j] for j in range(1, k + 1)) / k


def _poly(coefficients, x):
    """Σ c_m x^m as a node (Horner form)."""
    out = _Const(coefficients[-1])
    for c in reversed(coefficients[:-1]):
        out = _Add(_Mul(out, x), _Const(c), 1)
    return out


@dataclass(frozen=True)
class ReferenceLaw:
    """Φ as (breakpoints, pieces); each piece gives Φ(x) and the node of Φ(x(t)) from the node x(t)."""

    text: str                 # the formula the engine is given for the same law
    breakpoints: tuple        # increasing x values > 0 (as decimal strings)
    phi: tuple                # Φ(x) per piece, mpmath
    series: tuple             # series(x_node) -> Φ node, per piece
    capped: tuple             # per piece: Φ fades exponentially (its coefficients ∝ Φ), cap its growth

    def piece(self, x) -> int:
        return sum(1 for b in self.breakpoints if x >= mpmath.mpf(b))


def _exp_poly(coefficients):
    """Φ = exp(−Σ c_m x^m) as (value, series)."""
    cs = [mpmath.mpf(c) for c in coefficients]

    def value(x):
        return mpmath.exp(-mpmath.fsum(c * x**m for m, c in enumerate(cs)))

    return value, lambda x: _Exp(_poly([-c for c in cs], x))


def _smooth(text, value, series, capped=True):
    return ReferenceLaw(text, (), (value,), (series,), (capped,))


def _exp_over_one_plus_x():
    """Φ = e^{−x/2}/(1 + x/2) (Φ'(0) = −1, Eq. 3)."""
    e_value, e_series = _exp_poly([0, "0.5"])
    return (lambda x: e_value(x) / (1 + x / 2)), lambda x: _Div(e_series(x), _poly([1, "0.5"], x))


def _carlson_langer():
    return (lambda x: 1 / (1 + x)), lambda x: _Div(_Const(1), _Add(_Const(1), x, 1))


def _linear_then_exp():
    """Φ = 1 − x on [0, 1/2), (1/2)·e^{1 − 2x} above: continuous, Φ'(0) = −1, fades like e^{−2x}."""
    e_value, e_series = _exp_poly([-1, 2])
    return ReferenceLaw("piecewise(1 - x, 0.5, 0.5*exp(1 - 2*x))", ("0.5",),
                        (lambda x: 1 - x, lambda x: e_value(x) / 2),
                        (lambda x: _Add(_Const(1), x, -1), lambda x: _Mul(_Const("0.5"), e_series(x))), (False, True))


def _algebraic_square():
    """Φ = 1/(1 + x/2)² (Φ'(0) = −1; algebraic, fades like 4/x²)."""
    half_x = lambda x: _Add(_Const(1), _Mul(_Const("0.5"), x), 1)  # noqa: E731
    return (lambda x: 1 / (1 + x / 2) ** 2), lambda x: _Div(_Const(1), _Mul(half_x(x), half_x(x)))


def _three_pieces():
    """Φ = 1 − x on [0, 1/2), 3/4 − x/2 on [1/2, 3/2), 0 above: two breakpoints, continuous, crossed
    up and down in one cycle (the slope halves at the first, friction vanishes at the second)."""
    return ReferenceLaw("piecewise(1 - x, 0.5, 0.75 - x/2, 1.5, 0)", ("0.5", "1.5"),
                        (lambda x: 1 - x, lambda x: mpmath.mpf("0.75") - x / 2, lambda x: mpmath.mpf(0)),
                        (lambda x: _Add(_Const(1), x, -1), lambda x: _Add(_Const("0.75"), _Mul(_Const("0.5"), x), -1),
                         lambda x: _Const(0)), (False, False, False))


def _piecewise_linear():
    """Eq. (12): Φ = 1 − x on [0, 1), 0 above (a cross-check against ``reference.piecewise_linear_exact``)."""
    return ReferenceLaw("piecewise(1 - x, 1, 0)", ("1",), (lambda x: 1 - x, lambda x: mpmath.mpf(0)),
                        (lambda x: _Add(_Const(1), x, -1), lambda x: _Const(0)), (False, False))


#: The laws, keyed by the formula the engine is given. Written here by hand, independently of
#: ``bifurcation.laws`` ("exp(-x)" is the engine's "exponential", "1/(1 + x)" its "carlson-langer").
REFERENCE_LAWS = {
    "exp(-x)": _smooth("exp(-x)", *_exp_poly([0, 1])),
    "exp(-x - x^2)": _smooth("exp(-x - x^2)", *_exp_poly([0, 1, 1])),
    "exp(-x - x^3)": _smooth("exp(-x - x^3)", *_exp_poly([0, 1, 0, 1])),
    "exp(-x/2)/(1 + x/2)": _smooth("exp(-x/2)/(1 + x/2)", *_exp_over_one_plus_x()),
    "1/(1 + x)": _smooth("1/(1 + x)", *_carlson_langer(), capped=False),
    "piecewise(1 - x, 0.5, 0.5*exp(1 - 2*x))": _linear_then_exp(),
    "piecewise(1 - x, 1, 0)": _piecewise_linear(),
    "exp(-x - x^2/2)": _smooth("exp(-x - x^2/2)", *_exp_poly([0, 1, "0.5"])),
    "1/(1 + x/2)^2": _smooth("1/(1 + x/2)^2", *_algebraic_square(), capped=False),
    "piecewise(1 - x, 0.5, 0.75 - x/2, 1.5, 0)": _three_pieces(),
}


# -- the integrator ---------------------------------------------------------------------------------
def _step_series(law: ReferenceLaw, piece: int, nu, nu_f, t0, u0, v0, forcing: bool):
    """Coefficients of U, U̇ and Φ at t0 to order _ORDER (O(N²) per step)."""
    u, v, x = [u0], [v0], [v0 / nu_f]
    phi = law.series[piece](_X(x))
    for k in range(_ORDER):
        # U̇' = νt − U + 1 − Φ; the constant 1 − Φ_0 is formed at extra precision (it cancels at small x).
        if k == 0:
            with mpmath.extradps(60):
                rhs = (nu * t0 if forcing else 0) - u[0] + (1 - law.phi[piece](x[0]))
        else:
            rhs = (nu if forcing and k == 1 else 0) - u[k] - phi(k)
        u.append(v[k] / (k + 1))
        v.append(rhs / (k + 1))
        x.append(v[k + 1] / nu_f)
    return u, v, x


def _horner(c, s):
    out = mpmath.mpf(0)
    for a in reversed(c):
        out = out * s + a
    return out


def _root(f, lo, hi):
    """A root of f in [lo, hi] with f(lo), f(hi) of opposite sign, by bisection to working precision."""
    flo = f(lo)
    for _ in range(mpmath.mp.prec + 10):
        mid = (lo + hi) / 2
        if mid in (lo, hi):
            break
        fm = f(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return lo


def _log_phi(law, piece, x):
    value = law.phi[piece](x)
    return mpmath.log(value) if value > 0 else -mpmath.inf


def _integrate(law: ReferenceLaw, nu, nu_f, u, v, forcing: bool, dps: int, t_max, max_steps):
    tol = mpmath.mpf(10) ** (-dps - 5)
    negligible = mpmath.mpf(10) ** (-dps - 10)
    floor = mpmath.mpf(10) ** (-2 * dps)
    t, moving, steps = mpmath.mpf(0), v > 0, 0
    piece = law.piece(v / nu_f)
    while t < t_max and steps < max_steps:
        steps += 1
        cu, cv, cx = _step_series(law, piece, nu, nu_f, t, u, v, forcing)
        scale = max(abs(u), abs(v), floor)
        h = mpmath.inf
        for c in (cu, cv):
            for n in (_ORDER - 1, _ORDER):
                if c[n] != 0:
                    h = min(h, (tol * scale / abs(c[n])) ** (mpmath.mpf(1) / n))
        h = min(h, mpmath.mpf(1)) / 2

        # Friction cap: Φ grows by at most e^_MAX_LOG_CHANGE over a step, counted from the negligible
        # level 10^−(dps+10) when it starts below it (a decrease of Φ is seen by the step control).
        floor_log = max(_log_phi(law, piece, cx[0]), mpmath.log(negligible))

        def too_far(s):
            # Samples past the stop count as x = 0 and past a breakpoint use that piece's Φ: a step
            # that would overshoot the whole deceleration must be seen as the largest growth of all.
            for j in range(1, 9):
                xs = max(_horner(cx, s * j / 8), 0)
                p = law.piece(xs)
                if law.phi[p](xs) > negligible and _log_phi(law, p, xs) - floor_log > _MAX_LOG_CHANGE:
                    return True
            return False

        if law.capped[piece] and too_far(h):
            lo, hi = mpmath.mpf(0), h
            for _ in range(14):
                mid = (lo + hi) / 2
                lo, hi = (mid, hi) if not too_far(mid) else (lo, mid)
            h = lo

        # Events on the step's polynomial: the stop (U̇ = 0 downward), breakpoint crossings.
        grid = [h * j / _SCAN for j in range(_SCAN + 1)]
        vs = [_horner(cv, s) for s in grid]
        cut, event = h, None
        for j in range(1, _SCAN + 1):
            if moving and vs[j - 1] > 0 >= vs[j]:
                cut, event = _root(lambda s: _horner(cv, s), grid[j - 1], grid[j]), "stop"
                break
        stop_cut = cut
        for b in law.breakpoints:
            target = mpmath.mpf(b) * nu_f
            for j in range(1, _SCAN + 1):
                if grid[j - 1] >= stop_cut:
                    break
                # the interval that holds the stop ends there: a crossing of the breakpoint before the
                # stop in that same interval (V falls from above b·ν_f through 0 within 1/_SCAN of a
                # step, as on a friction-free piece at small ν_f) must be seen, not stepped over
                end = min(grid[j], stop_cut)
                v_end = vs[j] if end == grid[j] else _horner(cv, end)
                if (vs[j - 1] - target) * (v_end - target) < 0:
                    s = _root(lambda s: _horner(cv, s) - target, grid[j - 1], end)
                    if s < cut:
                        cut, event = s, ("switch", b, v_end > target)
                    break
        if event == "stop":
            return t + cut, _horner(cu, cut), steps
        u, v, t = _horner(cu, cut), _horner(cv, cut), t + cut
        if v > 0:
            moving = True
        if event is not None:
            b, up = event[1], event[2]
            v = mpmath.mpf(b) * nu_f  # exactly on the breakpoint
            piece = law.piece(mpmath.mpf(b)) if up else law.piece(mpmath.mpf(b)) - 1
    raise ArithmeticError(f"no stop before t = {mpmath.nstr(t, 6)} / {steps} steps")


def _law(law) -> ReferenceLaw:
    return law if isinstance(law, ReferenceLaw) else REFERENCE_LAWS[law]


def taylor_cycle(law, nu, nu_f, dps: int = 50, t_max=1000, max_steps=100_000) -> dict:
    """Δ and the stop time of one finite-ν cycle (floats ν, ν_f taken as their exact binary values).

    Returns ``{"delta": U(stop), "stop_time": stop, "steps": n}`` as mpmath numbers at ``dps``.
    """
    with mpmath.workdps(dps + 10):
        nu, nu_f = mpmath.mpf(nu), mpmath.mpf(nu_f)
        zero = mpmath.mpf(0)
        stop, delta, steps = _integrate(_law(law), nu, nu_f, zero, zero, True, dps, t_max, max_steps)
        return {"delta": delta, "stop_time": stop, "steps": steps}


def taylor_limit(law, nu_f, dps: int = 50, amplitude="1e-45", max_steps=100_000) -> dict:
    """Δ0 of the ν → 0 limit orbit (ν_f ≤ 1/2): the ν = 0 flow from the fast eigen-solution.

    The start (a, λa) lies on the linearisation's fast solution; the true orbit differs by O(a²),
    a = ``amplitude``, i.e. 1e-45 relative in Δ0 for the default.
    """
    with mpmath.workdps(dps + 10):
        nu_f = mpmath.mpf(nu_f)
        alpha = 1 / (2 * nu_f)
        lam = alpha + mpmath.sqrt(alpha * alpha - 1)
        a = mpmath.mpf(amplitude)
        stop, delta, steps = _integrate(_law(law), mpmath.mpf(0), nu_f, a, lam * a, False, dps,
                                        mpmath.mpf(1000), max_steps)
        return {"delta0": delta, "stop_time": stop, "steps": steps}
