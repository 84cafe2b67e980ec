"""The named friction laws.

Each law gives the drop g(x) = 1 − Φ(x) in a form free of cancellation at small x (see ``_base``).
Adding a law means adding one function here and one line to ``BUILTIN``.
"""

from __future__ import annotations

import mpmath

from ._base import FrictionLaw, Piece

__all__ = ["BUILTIN", "carlson_langer", "exponential", "piecewise_linear"]


def piecewise_linear() -> FrictionLaw:
    r"""Piecewise-linear law, Eq. (12) of Vasconcelos, PRL 76, 4865 (1996) (his Ref. [7]).

    .. math:: \Phi(x) = 1 - x \ (0 \le x \le 1), \qquad \Phi(x) = 0 \ (x \ge 1).

    The only law with a closed-form ν → 0 slip, Eq. (18). Two pieces, switched at x = 1.
    """
    return FrictionLaw(
        name="piecewise-linear",
        pieces=(
            Piece(0.0, lambda x, num: x, lambda x: x, "1 - x"),
            Piece(1.0, lambda x, num: num(1) + 0.0 * x, lambda x: mpmath.mpf(1), "0"),
        ),
        formula="piecewise(1 - x, 1, 0)",
        equation="Φ(x) = 1 − x for 0 ≤ x ≤ 1, 0 for x ≥ 1  [Eq. (12)]",
        source="Vasconcelos, PRL 76, 4865 (1996), Eq. (12)",
        description="the paper's piecewise-linear law; kink at x = 1, frictionless above",
    )


def carlson_langer() -> FrictionLaw:
    r"""Carlson–Langer law, Eq. (19) of Vasconcelos (1996); Carlson & Langer, PRL 62, 2632 (1989).

    .. math:: \Phi(x) = \frac{1}{1 + x}, \qquad g(x) = 1 - \Phi(x) = \frac{x}{1 + x}.
    """
    return FrictionLaw(
        name="carlson-langer",
        pieces=(Piece(0.0, lambda x, num: x / (num(1) + x), lambda x: x / (1 + x), "1/(1 + x)"),),
        formula="1/(1 + x)",
        equation="Φ(x) = 1/(1 + x)  [Eq. (19)]",
        source="Vasconcelos, PRL 76, 4865 (1996), Eq. (19); Carlson & Langer, PRL 62, 2632 (1989)",
        description="smooth, slowly weakening (Φ ~ 1/x at large x)",
    )


def _neg_expm1_neg(x, num):
    """−expm1(−x) as a heyoka expression (heyoka imported here: naming a law must not load it)."""
    import heyoka

    return -heyoka.expm1(-x)


def exponential() -> FrictionLaw:
    r"""Exponential velocity weakening (our addition; not in the paper).

    .. math:: \Phi(x) = e^{-x}, \qquad g(x) = -\operatorname{expm1}(-x).

    Smooth like Eq. (19) but weakening to zero friction quickly like Eq. (12): a law between the two.
    """
    return FrictionLaw(
        name="exponential",
        pieces=(Piece(0.0, _neg_expm1_neg, lambda x: -mpmath.expm1(-x), "exp(-x)"),),
        formula="exp(-x)",
        equation="Φ(x) = exp(−x)",
        source="this project (smooth law between Eqs. (12) and (19))",
        description="smooth, weakening to zero friction exponentially fast",
    )


#: name → factory; the order is the order ``bifurcation laws`` lists them in.
BUILTIN = {
    "piecewise-linear": piecewise_linear,
    "carlson-langer": carlson_langer,
    "exponential": exponential,
}
