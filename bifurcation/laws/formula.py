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

import functools
import math
from typing import Callable

import mpmath

from ._base import CONTINUITY_RTOL, FrictionLaw, Piece
from ._parse import (
    _DIGITS, _DPS, _FIX_DOMAIN, _FIX_PIECEWISE, _SAMPLES, _ZERO, _normal, _parse, _refuse, _show)
from ._evaluate import _at, _value_at_base
from ._defect import _Defect, _HeyokaOps, _MpmathOps

__all__ = ["formula_key", "parse_formula"]


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


@functools.lru_cache(maxsize=256)
def formula_key(text: str) -> str:
    """The parsed expression of a formula as one canonical text: two formulas with the same key are
    the same law (``1/(1+x/2)**2``, ``1/(1 + x/2)^2`` and ``1/(1+x/2.0)^2`` share one). Raises
    ``InputError`` for text that is not a formula."""
    pieces, breaks, _ = _parse(text)
    shown = [_show(_normal(p)) for p in pieces]
    if not breaks:
        return shown[0]
    parts = [shown[0]]
    for b, piece in zip(breaks, shown[1:]):
        parts += [mpmath.nstr(b, _DIGITS), piece]
    return "piecewise(" + ", ".join(parts) + ")"


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
