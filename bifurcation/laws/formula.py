r"""Friction laws written as formulas in x, parsed with a whitelist (never ``eval``).

``parse_formula("1/(1 + x)")`` returns a :class:`~bifurcation.laws.FrictionLaw`. A formula uses numbers,
the variable ``x``, the constants ``pi`` and ``e``, ``+ - * / ^`` (or ``**``), parentheses and the
functions of ``_FUNCTIONS``; ``piecewise(E0, b1, E1, b2, E2, ...)`` at the top level means
Φ = E0 on [0, b1), E1 on [b1, b2), ... with constant breakpoints 0 < b1 < b2 < ....

The engine divides the drop g(x) = 1 − Φ(x) by ν (down to 1e-15), so g needs full *relative* precision
wherever it is small. Writing 1 − Φ(x) directly cancels: its relative error is ε Φ/g, about ε/x at small
x. A Taylor polynomial of g below some x_s removes the cancellation only below x_s and leaves ε/x_s just
above it (1e-14 for x_s = 0.01); pushing x_s to where the cancellation is harmless (g ≈ 1/2) would need
over a hundred terms for a law with a pole at x = −1. Instead every subexpression f is carried in
*defect form*, its value f(b) at the left end b of the piece (an exact constant, computed in mpmath) plus
its change δf(x) = f(x) − f(b), with rules that never subtract nearly equal numbers, e.g.

.. math::
    \delta e^{a} = e^{a(b)}\,\operatorname{expm1}(\delta a), \quad
    \delta \log a = \operatorname{log1p}(\delta a / a(b)), \quad
    \delta \frac{p}{q} = \frac{\delta p - (p/q)(b)\,\delta q}{q},

and g = [1 − Φ(b)] − δΦ on each piece. δf has relative error O(ε) for every x (each term is
O(δx)), so g does too, down to x = 0 and up to any x. The same rules give the mpmath version at the
caller's precision.

The rules need every subexpression to be analytic at the left end of its piece (sqrt(x), x^2.5,
log(x) are not at x = 0, and heyoka's Taylor recurrences would start from NaN there); such formulas
are refused, as are those that fail Eq. (3) of Vasconcelos, PRL 76, 4865 (1996), or that are
discontinuous (both checked by ``FrictionLaw``), or that are not real and finite at sample points
from 1e-6 to 1e4, or anywhere on 0 ≤ x ≤ 1e5 (interval arithmetic over the whole range, ``_intervals``).
"""

from __future__ import annotations

import ast
import functools
import math
from dataclasses import dataclass
from typing import Callable

import mpmath

from ..errors import InputError
from ._base import CONTINUITY_RTOL, FrictionLaw, Piece

__all__ = ["parse_formula"]

_FUNCTIONS = ("exp", "log", "sqrt", "sin", "cos", "tan", "sinh", "cosh", "tanh", "atan", "expm1", "log1p")
_CONSTANTS = ("pi", "e")
_MAX_CHARS = 500
_MAX_DEPTH = 50
#: Digits of the constants handed to heyoka (real128 keeps ~34) and of the values used for decisions.
_DPS = 60
_DIGITS = 40
#: A value at the left end of a piece smaller than this counts as zero (sqrt(0), division by 0, Φ(0) = 1).
_ZERO = mpmath.mpf("1e-40")
#: Integer powers up to this size are expanded exactly (x^2 has no Taylor recurrence trouble at x = 0).
_MAX_INT_POWER = 1024
#: mpmath refuses exp of arguments beyond 2^_MAX_EXP_BITS: towers like exp(exp(exp(x))) would not
#: fit in memory (exp of a large negative argument underflows to 0 instead).
_MAX_EXP_BITS = 4096
#: Points where the law must be real and finite (beyond them the engine is not expected to go).
_SAMPLES = tuple(10.0 ** (k / 4) for k in range(-24, 17))

_FIX = ("write Φ as a formula in x, e.g. 'exp(-x)', '1/(1+x)' or 'piecewise(1 - x, 1, 0)'; functions: "
        + ", ".join(_FUNCTIONS) + "; constants: pi, e; operators: + - * / ^")
_FIX_PIECEWISE = "write piecewise(E0, b1, E1, b2, E2, ...) with numeric breakpoints 0 < b1 < b2 < ..."
_FIX_DOMAIN = "give a law that is smooth and finite at x = 0 and at each breakpoint"


# -- the parsed tree ------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Num:
    text: str  # decimal literal, kept as text so each precision rounds it once


@dataclass(frozen=True)
class _Name:
    name: str  # "x", "pi" or "e"


@dataclass(frozen=True)
class _Neg:
    arg: object


@dataclass(frozen=True)
class _Bin:
    op: str  # + - * / **
    left: object
    right: object


@dataclass(frozen=True)
class _Call:
    func: str
    arg: object


_PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "**": 4}


def _show(node, parent: int = 0) -> str:
    """The formula text of ``node`` (``^`` for powers), parenthesised only where needed."""
    if isinstance(node, _Num):
        return node.text
    if isinstance(node, _Name):
        return node.name
    if isinstance(node, _Call):
        return f"{node.func}({_show(node.arg)})"
    if isinstance(node, _Neg):
        text, own = "-" + _show(node.arg, 3), 3
    else:
        own = _PRECEDENCE[node.op]
        # a - (b - c), a / (b * c), (a ^ b) ^ c need their parentheses; a ^ b ^ c does not.
        left = _show(node.left, own + (node.op == "**"))
        right = _show(node.right, own + (node.op in "-/"))
        op = "^" if node.op == "**" else node.op
        text = f"{left}{op}{right}" if op in "^*/" else f"{left} {op} {right}"
    return f"({text})" if own < parent else text


@functools.lru_cache(maxsize=4096)
def _has_x(node) -> bool:
    if isinstance(node, _Name):
        return node.name == "x"
    if isinstance(node, _Num):
        return False
    if isinstance(node, (_Neg, _Call)):
        return _has_x(node.arg)
    return _has_x(node.left) or _has_x(node.right)


# -- text → tree (the whitelist) --------------------------------------------------------------------
def _refuse(text: object, problem: str, fix: str = _FIX) -> InputError:
    return InputError("law", text, problem, fix)


def _syntax_tree(text: str) -> tuple[ast.expr, str]:
    """Parse ``text`` into a Python expression tree (nothing is run), after the size checks."""
    if len(text) > _MAX_CHARS:
        raise _refuse(text[:40] + "...", f"is {len(text)} characters long; the limit is {_MAX_CHARS}")
    stripped = text.strip()  # a leading space would be an "unexpected indent"
    if not stripped:
        raise _refuse(text, "is empty")
    source = stripped.replace("\u2212", "-").replace("^", "**")
    try:
        tree = ast.parse(source, mode="eval")
    except SyntaxError as exc:
        raise _refuse(text, _syntax_problem(stripped, exc, len(text) - len(text.lstrip()))) from None
    except (ValueError, RecursionError, MemoryError) as exc:
        raise _refuse(text, f"cannot be parsed ({exc})") from None
    depth = _depth(tree)
    if depth > _MAX_DEPTH:
        raise _refuse(text, f"is nested {depth} levels deep; the limit is {_MAX_DEPTH}")
    return tree.body, source


def _syntax_problem(text: str, exc: SyntaxError, indent: int) -> str:
    """Where the syntax error is, as a column of the user's text (``^`` became two characters)."""
    lines = text.splitlines() or [""]
    lineno = min(max(exc.lineno or 1, 1), len(lines))
    line, offset = lines[lineno - 1], exc.offset or 0
    column, shifted = None, 0
    for i, char in enumerate(line):
        if shifted < offset <= shifted + (2 if char == "^" else 1):
            column = i + 1 + (indent if lineno == 1 else 0)
            break
        shifted += 2 if char == "^" else 1
    where = "at the end" if column is None else f"at column {column}"
    if len(lines) > 1:
        where += f" of line {lineno}"
    return f"syntax error {where} ({exc.msg})"


def _depth(tree: ast.AST) -> int:
    """Nesting depth of a syntax tree, without recursion."""
    deepest, stack = 0, [(tree, 1)]
    while stack:
        node, level = stack.pop()
        deepest = max(deepest, level)
        stack.extend((child, level + 1) for child in ast.iter_child_nodes(node))
    return deepest


_REFUSED_SYNTAX = {
    ast.Attribute: "attribute access ('.') is not allowed",
    ast.Subscript: "indexing ('[...]') is not allowed",
    ast.Lambda: "lambda is not allowed",
    ast.Compare: "comparisons are not allowed",
    ast.BoolOp: "'and'/'or' are not allowed",
    ast.IfExp: "conditional expressions ('if ... else') are not allowed; use piecewise(E0, b1, E1)",
    ast.JoinedStr: "strings are not allowed",
}
_BINARY = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_OTHER_OPERATORS = {ast.Mod: "%", ast.FloorDiv: "//", ast.MatMult: "@", ast.BitXor: "^ (bitwise)",
                    ast.BitAnd: "&", ast.BitOr: "|", ast.LShift: "<<", ast.RShift: ">>",
                    ast.Not: "not", ast.Invert: "~"}


def _convert(node: ast.expr, source: str, text: str):
    """The whitelisted tree of a Python expression; anything else is refused."""
    if isinstance(node, ast.Constant):
        return _number(node, source, text)
    if isinstance(node, ast.Name):
        if node.id == "x" or node.id in _CONSTANTS:
            return _Name(node.id)
        if node.id in _FUNCTIONS or node.id == "piecewise":
            raise _refuse(text, f"'{node.id}' is a function; call it as {node.id}(...)")
        raise _refuse(text, f"unknown name '{node.id}'; the variable is x")
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        return _Bin(_BINARY[type(node.op)], _convert(node.left, source, text),
                    _convert(node.right, source, text))
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        arg = _convert(node.operand, source, text)
        return _Neg(arg) if isinstance(node.op, ast.USub) else arg
    if isinstance(node, ast.Call):
        return _call(node, source, text)
    if isinstance(node, (ast.BinOp, ast.UnaryOp)):
        symbol = _OTHER_OPERATORS.get(type(node.op), type(node.op).__name__)
        raise _refuse(text, f"operator '{symbol}' is not allowed; use + - * / ^")
    for kind, problem in _REFUSED_SYNTAX.items():
        if isinstance(node, kind):
            raise _refuse(text, problem)
    raise _refuse(text, f"{type(node).__name__.lower()} expressions are not allowed")


def _call(node: ast.Call, source: str, text: str):
    if not isinstance(node.func, ast.Name):
        raise _refuse(text, "only calls of the listed functions by name are allowed")
    name = node.func.id
    if name == "piecewise":
        raise _refuse(text, "piecewise(...) is only allowed as the whole formula", _FIX_PIECEWISE)
    if name not in _FUNCTIONS:
        raise _refuse(text, f"unknown function '{name}'")
    if node.keywords:
        raise _refuse(text, f"keyword arguments are not allowed (in {name}(...))")
    if len(node.args) != 1 or isinstance(node.args[0], ast.Starred):
        raise _refuse(text, f"{name} takes one argument, got {len(node.args)}")
    return _Call(name, _convert(node.args[0], source, text))


def _number(node: ast.Constant, source: str, text: str) -> _Num:
    """A numeric literal, kept as its decimal text; refused unless it is a finite double."""
    value = node.value
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        what = "complex numbers are" if isinstance(value, complex) else f"{value!r} is"
        raise _refuse(text, f"{what} not allowed; only real numbers")
    if isinstance(value, int):
        literal = str(value)
    else:
        literal = (ast.get_source_segment(source, node) or repr(value)).replace("_", "")
    try:
        as_double = float(literal)
    except OverflowError:
        as_double = math.inf
    if not math.isfinite(as_double):
        raise _refuse(text, f"number {literal[:30]} is too large for double precision")
    if as_double == 0.0 and mpmath.mpf(literal) != 0:
        raise _refuse(text, f"number {literal} underflows double precision")
    return _Num(literal)


def _parse(text: str) -> tuple[list, list, list[str]]:
    """Pieces (trees of Φ), breakpoints (dps-60 values) and piece texts of a formula."""
    body, source = _syntax_tree(text)
    is_piecewise = (isinstance(body, ast.Call) and isinstance(body.func, ast.Name)
                    and body.func.id == "piecewise")
    if not is_piecewise:
        return [_convert(body, source, text)], [], [_segment(source, body)]
    if body.keywords:
        raise _refuse(text, "piecewise takes no keyword arguments", _FIX_PIECEWISE)
    args = body.args
    if len(args) < 3 or len(args) % 2 == 0 or any(isinstance(a, ast.Starred) for a in args):
        raise _refuse(text, f"piecewise needs an odd number (at least 3) of arguments "
                            f"E0, b1, E1, ..., got {len(args)}", _FIX_PIECEWISE)
    pieces = [_convert(a, source, text) for a in args[0::2]]
    breaks = [_breakpoint(_convert(a, source, text), text) for a in args[1::2]]
    for left, right in zip(breaks, breaks[1:]):
        if not right > left:
            raise _refuse(text, f"breakpoints must increase, got {mpmath.nstr(left, 10)} then "
                                f"{mpmath.nstr(right, 10)}", _FIX_PIECEWISE)
    return pieces, breaks, [_segment(source, a) for a in args[0::2]]


def _breakpoint(node, text: str):
    if _has_x(node):
        raise _refuse(text, f"breakpoint '{_show(node)}' depends on x; it must be a number",
                      _FIX_PIECEWISE)
    value = _value_at_base(node, mpmath.mpf(0), text)
    if not (value > 0 and value < 1e300):
        raise _refuse(text, f"breakpoint {_show(node)} must be > 0 and finite", _FIX_PIECEWISE)
    return value


def _segment(source: str, node: ast.expr) -> str:
    """The user's text of a piece, with ``^`` for powers and single spaces."""
    return " ".join((ast.get_source_segment(source, node) or "").replace("**", "^").split())


# -- direct evaluation in mpmath ---------------------------------------------------------------------
def _too_big_for_exp(arg) -> bool:
    return isinstance(arg, mpmath.mpf) and mpmath.isfinite(arg) and mpmath.mag(arg) > _MAX_EXP_BITS


def _mp_exp_like(name: str) -> Callable:
    """mpmath's ``name`` that gives up (or underflows) instead of building an exponent of huge size."""
    function = getattr(mpmath, name)
    underflow = {"exp": 0, "expm1": -1}.get(name)

    def guarded(arg):
        if _too_big_for_exp(arg):
            if arg < 0 and underflow is not None:
                return mpmath.mpf(underflow)
            raise OverflowError(f"{name} of a number of magnitude 2^{mpmath.mag(arg)} overflows")
        return function(arg)

    return guarded


def _mp_pow(base, power):
    """base^power; a large integer power goes through exp/log (mpmath would build the exact integer)."""
    if base == 0 and power > 0:
        return mpmath.mpf(0)
    if base == 0 or power == 0 or (abs(power) <= _MAX_INT_POWER and power == int(power)):
        return base ** power
    exponent = power * mpmath.log(abs(base))
    if _too_big_for_exp(exponent) and exponent > 0:
        raise OverflowError("power overflows")
    if base > 0:
        return _MP["exp"](exponent)
    if power != int(power):
        return base ** power  # complex: refused by the caller as not real
    sign = -1 if power % 2 else 1  # a negative base to a large integer power
    return sign * _MP["exp"](exponent)


_MP = {name: getattr(mpmath, name) for name in _FUNCTIONS}
_MP.update({name: _mp_exp_like(name) for name in ("exp", "expm1", "sinh", "cosh")})
_MP["atan2"] = mpmath.atan2


def _direct(node, x):
    """``node`` at x in mpmath at the current precision, as written (used at the left ends only)."""
    if isinstance(node, _Num):
        return mpmath.mpf(node.text)
    if isinstance(node, _Name):
        return x if node.name == "x" else (+mpmath.pi if node.name == "pi" else +mpmath.e)
    if isinstance(node, _Neg):
        return -_direct(node.arg, x)
    if isinstance(node, _Call):
        return _real(node, _MP[node.func](_direct(node.arg, x)))
    left, right = _direct(node.left, x), _direct(node.right, x)
    if node.op == "+":
        return left + right
    if node.op == "-":
        return left - right
    if node.op == "*":
        return left * right
    if node.op == "/":
        return left / right
    return _real(node, _mp_pow(left, right))


def _real(node, value):
    if not isinstance(value, mpmath.mpf):
        raise ValueError(f"{_show(node)} is not real")
    return value


@functools.lru_cache(maxsize=8192)
def _direct_cached(node, x, prec: int):
    with mpmath.workprec(prec):
        return _direct(node, x)


def _at(node, x):
    """``node`` at x with 20 guard bits over the current precision, memoised."""
    return _direct_cached(node, mpmath.mpf(x), mpmath.mp.prec + 20)


def _value_at_base(node, base, text: str):
    """``node`` at the left end ``base`` of its piece at dps 60; refused unless real and finite."""
    where = f"x = {float(base):.15g}"
    try:
        with mpmath.workdps(_DPS):
            value = _at(node, base)
    except (ValueError, TypeError, ZeroDivisionError, OverflowError) as exc:
        reason = str(exc) or type(exc).__name__.replace("ZeroDivisionError", "division by zero")
        raise _refuse(text, f"'{_show(node)}' cannot be evaluated at {where} ({reason})",
                      _FIX_DOMAIN) from None
    if not isinstance(value, mpmath.mpf):
        raise _refuse(text, f"'{_show(node)}' is not real at {where}", _FIX_DOMAIN)
    if not mpmath.isfinite(value):
        raise _refuse(text, f"'{_show(node)}' is not finite at {where}", _FIX_DOMAIN)
    if abs(value) > mpmath.mpf("1e300"):
        raise _refuse(text, f"'{_show(node)}' is {mpmath.nstr(value, 3)} at {where}, too large for "
                            "double precision", _FIX_DOMAIN)
    return value


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


# -- pieces and the law ------------------------------------------------------------------------------
def _drop_builder(phi, base, offset: Callable, text: str) -> Callable:
    """``build(ops)`` → g = offset − δΦ on the piece of ``phi`` with left end ``base``.

    ``offset()`` is g at the left end in mpmath at the current precision: 1 − Φ(0) for the first piece
    (dropped when it vanishes to 40 digits, as Eq. (3) requires), the previous piece's drop at a
    breakpoint where the law is continuous (see ``_offset``).
    """
    with mpmath.workdps(_DPS):
        # Refuses a piece not real and finite at its left end (the dry build in _make_piece catches the
        # rest, but does not evaluate a piece without x).
        _value_at_base(phi, base, text)
        keep_offset = abs(offset()) > _ZERO

    def build(ops):
        delta = _Defect(ops, base, text).d(phi)
        constant = ops.const(offset) if keep_offset or delta is None else None
        if delta is None:
            return constant
        return -delta if constant is None else constant - delta

    return build


def _offset(phi, previous, exact, rounded, text: str) -> Callable:
    """g at the left end of the piece ``phi`` that starts at the breakpoint ``exact``.

    The engine switches at the breakpoint rounded to a double; a law continuous at 0.1 jumps by
    ~1e-17 at the rounded point and would be refused. So where the law is continuous at the exact
    breakpoint, the piece starts from the previous piece's drop at the rounded one, exactly; a law that
    really jumps keeps its own value and is refused by ``FrictionLaw``.
    """
    left, right = _value_at_base(previous[0], exact, text), _value_at_base(phi, exact, text)
    if abs(left - right) <= CONTINUITY_RTOL * max(1, abs(right)):
        build = previous[1]
        return lambda: build(_MpmathOps(rounded))
    return lambda: 1 - _at(phi, rounded)


def _make_piece(phi, base, offset: Callable, text: str, piece_text: str) -> tuple[Piece, Callable]:
    build = _drop_builder(phi, base, offset, text)
    # Build once now, so that refusals happen at parse time and not inside the engine.
    build(_HeyokaOps(_dry_variable(), _checked_double(text)))

    def drop(x, num):
        return build(_HeyokaOps(x, num))

    def drop_mp(x):
        return build(_MpmathOps(x))

    return Piece(float(base), drop, drop_mp, piece_text), build


def _dry_variable():
    import heyoka

    return heyoka.make_vars("x")


def _checked_double(text: str) -> Callable:
    import heyoka

    def num(decimal: str):
        value = float(decimal)
        if not math.isfinite(value):
            raise _refuse(text, f"needs the constant {decimal[:20]}, which overflows double precision",
                          _FIX_DOMAIN)
        return heyoka.expression(value)

    return num


def _check_samples(law: FrictionLaw, text: str) -> None:
    """Refuse a law that is not real and finite at the sample points (and each breakpoint)."""
    points = sorted({0.0, *_SAMPLES, *law.breakpoints})
    with mpmath.workdps(30):
        for x in points:
            try:
                value = law.drop_mp(x)
                ok = isinstance(value, mpmath.mpf) and mpmath.isfinite(value)
            except (ValueError, ZeroDivisionError, OverflowError, TypeError):
                ok = False
            if not ok:
                raise _refuse(text, f"Φ is not real and finite at x = {x:g}",
                              "give a law defined for all x ≥ 0 (check denominators and the "
                              "arguments of sqrt, log and powers)")


def parse_formula(text: str) -> FrictionLaw:
    """The friction law Φ(x) written by ``text``.

    Parameters
    ----------
    text : str
        A formula in x, e.g. ``"exp(-x)"``, ``"1/(1+x/2)^2"``, or ``"piecewise(1 - x, 1, 0)"`` for
        Φ = 1 − x on [0, 1) and 0 above (Eq. (12) of Vasconcelos, PRL 76, 4865 (1996)).

    Returns
    -------
    FrictionLaw
        Named by the formula without spaces; its drops are built in defect form (module docstring),
        with full relative precision at every x.

    Raises
    ------
    InputError
        For text outside the whitelist, a syntax error, a law that is not smooth and finite at x = 0 or
        at a breakpoint, not real and finite at a sample point up to x = 1e4, or that violates Eq. (3)
        (Φ(0) = 1, Φ'(0) = −1) or continuity.
    """
    if not isinstance(text, str):
        raise _refuse(text, "is not a formula text")
    pieces, breaks, piece_texts = _parse(text)
    bases = [(exact, mpmath.mpf(float(exact))) for exact in breaks]
    lowers = [0.0] + [float(rounded) for _, rounded in bases]
    if any(b <= a for a, b in zip(lowers, lowers[1:])):
        raise _refuse(text, "breakpoints coincide in double precision", _FIX_PIECEWISE)
    built = [_make_piece(pieces[0], mpmath.mpf(0), lambda: 1 - _at(pieces[0], 0), text, piece_texts[0])]
    for previous, phi, (exact, rounded), piece_text in zip(pieces, pieces[1:], bases, piece_texts[1:]):
        offset = _offset(phi, (previous, built[-1][1]), exact, rounded, text)
        built.append(_make_piece(phi, rounded, offset, text, piece_text))
    law = FrictionLaw(
        name="".join(text.replace("\u2212", "-").split()),
        pieces=tuple(piece for piece, _ in built),
        formula=text,
        equation=f"Φ(x) = {text.strip()}",
        source="user formula",
        description="parsed from a formula; drop in defect form (full relative precision)",
    )
    _check_samples(law, text)
    from ._intervals import check_intervals

    check_intervals(pieces, lowers, text)   # no pole between the samples either
    return law
