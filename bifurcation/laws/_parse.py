"""Formula laws, step 1: text → tree, with a whitelist (never ``eval``), and the tree → text.

The grammar and the refusals are described in ``bifurcation.laws.formula``.
"""

from __future__ import annotations

import ast
import functools
import math
from dataclasses import dataclass

import mpmath

from ..errors import InputError

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
    if "#" in source:   # Python's comment: the rest was ignored yet kept in the law's name (issue 21 walk)
        raise _refuse(text, "holds '#', which is not part of a formula", _FIX)
    if not source.isascii():   # Python reads identifiers NFKC-folded: 'ℯxp(-x)' ran as exp(-x) (issue 21 walk 3)
        column, char = next((i + 1, c) for i, c in enumerate(stripped) if not c.isascii() and c != "\u2212")
        raise _refuse(text, f"holds {char!r} (U+{ord(char):04X}) at column {column}, which is not ASCII",
                      "write the formula in ASCII letters and digits; " + _FIX)
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
    from ._evaluate import _value_at_base   # evaluation builds on the tree: imported when used
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



def _normal(node):
    """``node`` with every number written one way (``2``, ``2.0`` and ``2e0`` alike)."""
    if isinstance(node, _Num):
        with mpmath.workdps(_DPS):
            return _Num(mpmath.nstr(mpmath.mpf(node.text), _DIGITS, min_fixed=-math.inf, max_fixed=math.inf))
    if isinstance(node, _Name):
        return node
    if isinstance(node, (_Neg, _Call)):
        return type(node)(*([node.func] if isinstance(node, _Call) else []), _normal(node.arg))
    return _Bin(node.op, _normal(node.left), _normal(node.right))
