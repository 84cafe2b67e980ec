"""Formula laws, step 3: the expression builder, δf = f(x) − f(b) without cancellation, for heyoka
and for mpmath from one set of rules (the defect form of ``bifurcation.laws.formula``).
"""

from __future__ import annotations

from typing import Callable

import mpmath

from ._parse import (
    _Bin, _Call, _DIGITS, _DPS, _FIX_DOMAIN, _MAX_INT_POWER, _Name, _Neg, _Num, _ZERO, _has_x, _refuse,
    _show)
from ._evaluate import _MP, _at, _value_at_base

# -- the defect form: f(x) − f(b) without cancellation ---------------------------------------------------
class _HeyokaOps:
    """heyoka expressions; constants through ``num`` as 40-digit decimal strings."""

    def __init__(self, x, num) -> None:
        import heyoka

        self.x, self._num, self._hy = x, num, heyoka

    def const(self, value):
        with mpmath.workdps(_DPS):
            return self._num(mpmath.nstr(value() if callable(value) else value, _DIGITS))

    def fn(self, name: str) -> Callable:
        return getattr(self._hy, name)


class _MpmathOps:
    """mpmath numbers at the caller's precision."""

    def __init__(self, x) -> None:
        self.x = mpmath.mpf(x)

    def const(self, value):
        with mpmath.extraprec(20):
            return +(value() if callable(value) else mpmath.mpf(value))

    def fn(self, name: str) -> Callable:
        return _MP[name]


class _Defect:
    """Builds δf = f(x) − f(b) for the nodes of one piece with left end ``base``, in one backend.

    Decisions (is f(b) zero, is the power an integer) use dps-60 values, so every backend builds the
    same formula; ``_value_at_base`` refuses subexpressions that are not real and finite at b.
    """

    def __init__(self, ops, base, text: str) -> None:
        self.ops, self.base, self.text = ops, mpmath.mpf(base), text
        self._memo: dict = {}
        self.dx = ops.x if base == 0 else ops.x - ops.const(self.base)

    # small helpers -----------------------------------------------------------------------------
    def hp(self, node):
        """``node`` at the left end, dps 60 (for decisions)."""
        return _value_at_base(node, self.base, self.text)

    def k(self, node):
        """``node`` at the left end as a backend constant."""
        self.hp(node)
        return self.ops.const(lambda: _at(node, self.base))

    def kf(self, function: Callable):
        """A constant computed from the values at the left end."""
        return self.ops.const(function)

    def value(self, node):
        """f(x) = f(b) + δf (just δf when f(b) = 0, the constant when δf = 0)."""
        delta = self.d(node)
        if delta is None:
            return self.k(node)
        return delta if self.hp(node) == 0 else self.k(node) + delta

    def refuse(self, node, problem: str, why: str):
        where = f"x = {float(self.base):.15g}"
        raise _refuse(self.text, f"'{_show(node)}' {problem} at {where} ({why})", _FIX_DOMAIN)

    # the rules -------------------------------------------------------------------------------------
    def d(self, node):
        """δf of ``node``, or None when it does not depend on x."""
        if not _has_x(node):
            return None
        if node not in self._memo:
            self.hp(node)
            if isinstance(node, _Name):
                result = self.dx
            elif isinstance(node, _Neg):
                result = -self.d(node.arg)
            elif isinstance(node, _Call):
                result = getattr(self, "_" + node.func)(node, node.arg, self.d(node.arg))
            else:
                result = {"+": self._add, "-": self._sub, "*": self._mul, "/": self._div,
                          "**": self._pow}[node.op](node, node.left, node.right)
            self._memo[node] = result
        return self._memo[node]

    def _add(self, node, left, right):
        dl, dr = self.d(left), self.d(right)
        return dl if dr is None else dr if dl is None else dl + dr

    def _sub(self, node, left, right):
        dl, dr = self.d(left), self.d(right)
        return dl if dr is None else -dr if dl is None else dl - dr

    def _mul(self, node, left, right):
        # (l0 + δl)(r0 + δr) − l0 r0 = l0 δr + r0 δl + δl δr
        dl, dr = self.d(left), self.d(right)
        terms = []
        if dr is not None and self.hp(left) != 0:
            terms.append(self.k(left) * dr)
        if dl is not None and self.hp(right) != 0:
            terms.append(self.k(right) * dl)
        if dl is not None and dr is not None:
            terms.append(dl * dr)
        return _sum(terms)

    def _div(self, node, top, bottom):
        # l/r − q0 = (δl − q0 δr)/r with q0 = l0/r0
        if abs(self.hp(bottom)) <= _ZERO:
            self.refuse(node, "is not finite", f"its denominator '{_show(bottom)}' is 0 there")
        dt, db = self.d(top), self.d(bottom)
        if db is None:
            return dt / self.k(bottom)
        shifted = -(self.k(node) * db) if self.hp(node) != 0 else None
        numerator = _sum([t for t in (dt, shifted) if t is not None])
        return numerator / self.value(bottom) if numerator is not None else None

    def _pow(self, node, base, power):
        exponent = None if _has_x(power) else self.hp(power)
        if exponent is not None and abs(exponent) <= _MAX_INT_POWER and exponent == int(exponent):
            return self._int_pow(node, base, int(exponent))
        if self.hp(base) <= _ZERO:
            sign = "0" if abs(self.hp(base)) <= _ZERO else "negative"
            self.refuse(node, "is not analytic" if sign == "0" else "is not real",
                        f"its base '{_show(base)}' is {sign} there and the power is not an integer")
        return self.d(_Call("exp", _Bin("*", power, _Call("log", base))))

    def _int_pow(self, node, base, n: int):
        if n == 0 or self.d(base) is None:
            return None
        if n < 0:
            if abs(self.hp(base)) <= _ZERO:
                self.refuse(node, "is not finite", f"its base '{_show(base)}' is 0 there")
            # a^−m − a0^−m = −(a^m − a0^m)/(a^m a0^m)
            positive = _Bin("**", base, _Num(str(-n)))
            return -self.d(positive) / (self.k(positive) * _power(self.value(base), -n))
        delta = self.d(base)
        if self.hp(base) == 0:
            return _power(delta, n)
        # a^n − a0^n = δa (a^{n−1} + a0 a^{n−2} + ... + a0^{n−1}), the sum in Horner form
        whole, horner = self.value(base), None
        for k in range(1, n):
            coefficient = self.kf(lambda k=k: _at(base, self.base) ** k)
            horner = whole + coefficient if horner is None else horner * whole + coefficient
        return delta if horner is None else delta * horner

    def _exp(self, node, arg, delta):
        expm1 = self.ops.fn("expm1")(delta)
        return expm1 if self.hp(arg) == 0 else self.kf(lambda: mpmath.exp(_at(arg, self.base))) * expm1

    _expm1 = _exp  # δ expm1(a) = δ exp(a)

    def _log(self, node, arg, delta):
        if self.hp(arg) <= _ZERO:
            self.refuse(node, "is not finite or not real", f"its argument '{_show(arg)}' is not > 0")
        return self.ops.fn("log1p")(delta / self.k(arg))

    def _log1p(self, node, arg, delta):
        if self.hp(arg) <= -1 + _ZERO:
            self.refuse(node, "is not finite or not real", f"its argument '{_show(arg)}' is not > -1")
        if self.hp(arg) == 0:
            return self.ops.fn("log1p")(delta)
        return self.ops.fn("log1p")(delta / self.kf(lambda: 1 + _at(arg, self.base)))

    def _sqrt(self, node, arg, delta):
        if self.hp(arg) <= _ZERO:
            sign = "0" if abs(self.hp(arg)) <= _ZERO else "negative"
            self.refuse(node, "is not analytic" if sign == "0" else "is not real",
                        f"its argument '{_show(arg)}' is {sign} there")
        return delta / (self.k(node) + self.ops.fn("sqrt")(self.value(arg)))

    def _sum_to_product(self, node, arg, delta):
        """δ of sin, cos, sinh, cosh as a product (``_SUM_TO_PRODUCT``); sin, sinh of δa when a0 = 0."""
        if node.func in ("sin", "sinh") and self.hp(arg) == 0:
            return self.ops.fn(node.func)(delta)
        factor, of_middle, of_half = _SUM_TO_PRODUCT[node.func]
        half = delta * self.kf(lambda: mpmath.mpf(1) / 2)
        middle = half if self.hp(arg) == 0 else self.k(arg) + half
        scaled = self.kf(lambda: mpmath.mpf(factor)) * self.ops.fn(of_middle)(middle)
        return scaled * self.ops.fn(of_half)(half)  # (k·a)·b: rounding depends on the order

    _sin = _cos = _sinh = _cosh = _sum_to_product

    def _tan(self, node, arg, delta):
        # tan a − tan a0 = sin(δa)/(cos a cos a0)
        if self.hp(arg) == 0:
            return self.ops.fn("tan")(delta)
        if abs(mpmath.cos(self.hp(arg))) <= _ZERO:
            self.refuse(node, "is not finite", f"cos({_show(arg)}) is 0 there")
        cos0 = self.kf(lambda: mpmath.cos(_at(arg, self.base)))
        return self.ops.fn("sin")(delta) / (cos0 * self.ops.fn("cos")(self.value(arg)))

    def _tanh(self, node, arg, delta):
        if self.hp(arg) == 0:
            return self.ops.fn("tanh")(delta)
        cosh0 = self.kf(lambda: mpmath.cosh(_at(arg, self.base)))
        return self.ops.fn("sinh")(delta) / (cosh0 * self.ops.fn("cosh")(self.value(arg)))

    def _atan(self, node, arg, delta):
        # atan a − atan a0 = atan2(δa, 1 + a0 a), on the right branch for every a
        if self.hp(arg) == 0:
            return self.ops.fn("atan")(delta)
        cosine = self.kf(lambda: mpmath.mpf(1)) + self.k(arg) * self.value(arg)
        return self.ops.fn("atan2")(delta, cosine)


#: f(a) − f(a0) = factor · of_middle(a0 + δa/2) · of_half(δa/2) for these f (sums to products),
#: e.g. sin a − sin a0 = 2 cos(a0 + δa/2) sin(δa/2): no cancellation at small δa.
_SUM_TO_PRODUCT = {"sin": (2, "cos", "sin"), "cos": (-2, "sin", "sin"),
                   "sinh": (2, "cosh", "sinh"), "cosh": (2, "sinh", "sinh")}


def _sum(terms: list):
    if not terms:
        return None
    total = terms[0]
    for term in terms[1:]:
        total = total + term
    return total


def _power(base, n: int):
    """base^n for an integer n ≥ 1 by repeated squaring (no pow, which heyoka cannot start at 0)."""
    result, square = None, base
    while n:
        if n & 1:
            result = square if result is None else result * square
        n >>= 1
        if n:
            square = square * square
    return result
