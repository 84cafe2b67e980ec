"""Formula laws, step 2: a parsed tree evaluated directly in mpmath (at the left ends of pieces).

Exponentials and powers that would build numbers of absurd size give up instead (``OverflowError``).
"""

from __future__ import annotations

import functools
from typing import Callable

import mpmath

from ._parse import (
    _Call, _DPS, _FIX_DOMAIN, _FUNCTIONS, _MAX_EXP_BITS, _MAX_INT_POWER, _Name, _Neg, _Num, _refuse, _show)

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
