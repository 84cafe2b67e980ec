r"""Interval arithmetic over the whole range of x: a formula law has no pole and no undefined point there.

Sampling misses poles between samples (``1 - tan(x)`` passed: tan has a pole at π/2, between the
samples 1.33 and 1.78). Here each piece of Φ is evaluated in interval arithmetic on subintervals that
cover its whole domain [b_k, b_{k+1}] (the last piece up to ``X_MAX``): every operation returns an
interval that *contains* every value of the subexpression on the subinterval (mpmath at 100 bits,
each endpoint widened outward by 2^-90 relative). If no operation meets a forbidden argument —
a divisor interval containing 0, a log / log1p / sqrt / non-integer power argument reaching where it is
undefined, a tan argument containing π/2 + kπ — Φ is finite and real on the whole subinterval: that is
the proof. Otherwise the subinterval is bisected; an interval narrower than 10^-12 relative that
still meets one holds a pole or an undefined point (interval bounds are tight on narrow intervals), and
the law is refused naming it.

Range. x = U̇/ν_f. While the block slips, Ü = −U + νt + g(x) with g = 1 − Φ ≤ 1 for every friction
law with Φ ≥ 0; multiplying by U̇ > 0 and integrating from rest gives U̇ ≤ 1 + ν·t_slip ≤ 1 + π for ν ≤ 1
and a slip of at most half a period, so x ≤ 4.2/ν_f ≤ 4.2e4 at the smallest ν_f = 1e-4
(``bifurcation.bounds``). ``X_MAX`` = 1e5 covers that with room. Overflow of huge but finite values
(exp(x) at large x) is not a pole and is not refused here.
"""

from __future__ import annotations

import mpmath

__all__ = ["X_MAX", "check_intervals"]

X_MAX = 1e5
_PREC = 100
_WIDEN = mpmath.mpf(2) ** -90
_NARROW = mpmath.mpf("1e-12")
#: Interval evaluations per law before giving up (a pole is cornered in ~2 × 45 bisections).
_BUDGET = 20_000
#: exp of more than this counts as +inf (finite, just beyond any number an engine can hold).
_EXP_LIMIT = mpmath.mpf(10) ** 9


class _Bad(Exception):
    """A forbidden argument met on an interval (maybe a pole, maybe overestimation: bisect)."""


def _out(lo, hi):
    """``[lo, hi]`` widened outward (an infinite end stays as it is: inf − inf would be NaN)."""
    if mpmath.isfinite(lo):
        lo = lo - abs(lo) * _WIDEN
    if mpmath.isfinite(hi):
        hi = hi + abs(hi) * _WIDEN
    return (lo, hi)


def _mono(f, a):
    lo, hi = a
    return _out(f(lo), f(hi))


def _exp(v):
    return mpmath.inf if v > _EXP_LIMIT else (mpmath.mpf(0) if v < -_EXP_LIMIT else mpmath.exp(v))


def _contains(a, value) -> bool:
    return a[0] <= value <= a[1]


def _mul(a, b):
    products = [a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1]]
    products = [p if p == p else mpmath.mpf(0) for p in products]   # 0 · inf: the finite operand is 0
    return _out(min(products), max(products))


def _div(a, b, what: str):
    if _contains(b, 0):
        raise _Bad(f"division by {what} = 0")
    return _mul(a, _out(1 / b[1], 1 / b[0]))


def _periodic_hits(a, phase, period) -> bool:
    """Whether [a] contains phase + k·period for some integer k."""
    return mpmath.ceil((a[0] - phase) / period) <= mpmath.floor((a[1] - phase) / period)


def _sin(a):
    pi = mpmath.pi
    if a[1] - a[0] >= 2 * pi:
        return (mpmath.mpf(-1), mpmath.mpf(1))
    lo, hi = sorted((mpmath.sin(a[0]), mpmath.sin(a[1])))
    if _periodic_hits(a, pi / 2, 2 * pi):
        hi = mpmath.mpf(1)
    if _periodic_hits(a, 3 * pi / 2, 2 * pi):
        lo = mpmath.mpf(-1)
    return _out(lo, hi)


def _cosh(a):
    lo, hi = sorted((abs(a[0]), abs(a[1])))
    if _contains(a, 0):
        lo = mpmath.mpf(0)
    return _out(mpmath.cosh(min(lo, _EXP_LIMIT)), mpmath.cosh(min(hi, _EXP_LIMIT)))


def _call(name: str, a, show):
    if name == "exp":
        return _out(_exp(a[0]), _exp(a[1]))
    if name == "expm1":
        return _out(_exp(a[0]) - 1, _exp(a[1]) - 1)
    if name == "log":
        if a[0] <= 0:
            raise _Bad(f"log of {show} ≤ 0")
        return _mono(mpmath.log, a)
    if name == "log1p":
        if a[0] <= -1:
            raise _Bad(f"log1p of {show} ≤ -1")
        return _mono(mpmath.log1p, a)
    if name == "sqrt":
        if a[0] < 0:
            raise _Bad(f"sqrt of {show} < 0")
        return _mono(mpmath.sqrt, a)
    if name == "sin":
        return _sin(a)
    if name == "cos":
        return _sin((a[0] + mpmath.pi / 2, a[1] + mpmath.pi / 2))
    if name == "tan":
        if a[1] - a[0] >= mpmath.pi or _periodic_hits(a, mpmath.pi / 2, mpmath.pi):
            raise _Bad(f"tan at {show} = π/2 + kπ")
        return _mono(mpmath.tan, a)
    if name == "sinh":
        return _mono(lambda v: mpmath.sinh(max(min(v, _EXP_LIMIT), -_EXP_LIMIT)), a)
    if name == "cosh":
        return _cosh(a)
    if name in ("tanh", "atan"):
        return _mono(getattr(mpmath, name), a)
    raise _Bad(f"unknown function {name}")   # the parser's whitelist makes this unreachable


def _int_pow(a, n: int, show):
    if n < 0:
        return _div((mpmath.mpf(1), mpmath.mpf(1)), _int_pow(a, -n, show), f"{show}^{-n}")
    lo, hi = a[0] ** n, a[1] ** n
    if n % 2 == 0:
        lo, hi = sorted((lo, hi))
        if _contains(a, 0):
            lo = mpmath.mpf(0)
    return _out(lo, hi)


def _pow(node, base, power, show):
    from ._parse import _has_x

    constant = not _has_x(node.right)
    if constant and power[0] == power[1] == int(power[0]) and abs(power[0]) <= 1024:
        return _int_pow(base, int(power[0]), show(node.left))
    if base[0] < 0 or (base[0] == 0 and (power[0] <= 0 or not constant)):
        raise _Bad(f"power of {show(node.left)} ≤ 0")
    if constant:   # b^p is monotone in b and in p separately: its bounds are at the corners
        corners = [mpmath.mpf(0) if b == 0 else _exp(p * mpmath.log(b)) for b in base for p in power]
        return _out(min(corners), max(corners))
    exponent = _mul(_mono(mpmath.log, base), power)
    return _out(_exp(exponent[0]), _exp(exponent[1]))


def _evaluate(node, x):
    from ._parse import _Call, _Name, _Neg, _Num, _show

    if isinstance(node, _Num):
        value = mpmath.mpf(node.text)
        return (value, value)
    if isinstance(node, _Name):
        if node.name == "x":
            return x
        value = +mpmath.pi if node.name == "pi" else +mpmath.e
        return _out(value, value)
    if isinstance(node, _Neg):
        lo, hi = _evaluate(node.arg, x)
        return (-hi, -lo)
    if isinstance(node, _Call):
        return _call(node.func, _evaluate(node.arg, x), _show(node.arg))
    left, right = _evaluate(node.left, x), _evaluate(node.right, x)
    if node.op == "+":
        return _out(left[0] + right[0], left[1] + right[1])
    if node.op == "-":
        return _out(left[0] - right[1], left[1] - right[0])
    if node.op == "*":
        return _mul(left, right)
    if node.op == "/":
        return _div(left, right, _show(node.right))
    return _pow(node, left, right, _show)


def _cover(lo: float, hi: float) -> list[tuple]:
    """Subintervals of [lo, hi] doubling in length (x spans decades)."""
    start = max(lo, 1e-8)
    edges = [mpmath.mpf(lo)] if lo < start else []
    edge = mpmath.mpf(start)
    while edge < hi:
        edges.append(edge)
        edge *= 2
    edges.append(mpmath.mpf(hi))
    return list(zip(edges, edges[1:]))


def check_intervals(pieces, lowers, text: str) -> None:
    """Refuse (``InputError``) a law one of whose ``pieces`` has a pole or an undefined point on its domain.

    ``pieces`` are the parsed trees of Φ, ``lowers`` their left ends (0 first); the last piece runs to
    ``X_MAX``.
    """
    from ._parse import _refuse

    uppers = [*lowers[1:], X_MAX]
    budget = _BUDGET
    with mpmath.workprec(_PREC):
        for piece, lo, hi in zip(pieces, lowers, uppers):
            stack = _cover(lo, hi)[::-1]
            while stack:
                a, b = stack.pop()
                budget -= 1
                try:
                    _evaluate(piece, (a, b))
                    continue
                except _Bad as exc:
                    problem = str(exc)
                middle = (a + b) / 2
                if b - a <= _NARROW * max(abs(middle), 1) or budget <= 0:
                    where = mpmath.nstr(middle, 12)
                    reason = "(a pole or an undefined point)" if budget > 0 else \
                        "(could not be excluded within the evaluation budget)"
                    raise _refuse(text, f"Φ is not finite and real near x = {where}: {problem} {reason}",
                                  f"give a law defined and finite for all 0 ≤ x ≤ {X_MAX:g} (the range "
                                  f"the engine can reach; check denominators, tan, log, sqrt and powers)")
                stack += [(middle, b), (a, middle)]
