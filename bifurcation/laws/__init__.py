"""Friction laws: a registry of named laws and user formulas.

``resolve_law("carlson-langer")`` returns a named law; ``resolve_law("exp(-x)")`` parses a formula in
x with a whitelist (never ``eval``). Laws are resolved by their text, so a grid ships only strings to
its workers and each worker builds (and caches) the law itself.
"""

from __future__ import annotations

import functools
import re

from ..errors import InputError
from ._base import FrictionLaw, Piece
from .builtin import BUILTIN

__all__ = ["FrictionLaw", "Piece", "law_names", "resolve_law"]

_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_-]*$")


def law_names() -> list[str]:
    """Names of the built-in laws."""
    return list(BUILTIN)


@functools.lru_cache(maxsize=64)
def _resolve_text(text: str) -> FrictionLaw:
    if text in BUILTIN:
        return BUILTIN[text]()
    from .formula import parse_formula

    if _NAME.match(text) and text != "x":  # a bare name, not a formula in x
        raise InputError("law", text, "is not a known law",
                         f"use one of {', '.join(BUILTIN)} or a formula in x such as 'exp(-x)'")
    return parse_formula(text)


def resolve_law(law: str | FrictionLaw) -> FrictionLaw:
    """The law named or written by ``law`` (a name of ``law_names()`` or a formula in x)."""
    if isinstance(law, FrictionLaw):
        return law
    if not isinstance(law, str) or not law.strip():
        raise InputError("law", law, "is not a law name or formula",
                         f"use one of {', '.join(BUILTIN)} or a formula in x such as 'exp(-x)'")
    return _resolve_text(law.strip())
