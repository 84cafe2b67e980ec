"""A friction law's drop g = 1 − Φ as a *tape* for compiled code (the compiled chain engine).

The drop of every law is rebuilt from its formula text (the named laws have one too: ``law.formula``)
with the defect-form rules of ``bifurcation.laws`` (``_defect``: no cancellation at small x, the same
rules heyoka's expressions come from), but recorded as a straight-line program of register operations
instead of a heyoka expression: ``(opcode, a, b)`` with a constant per entry. ``_compiled.tape_eval``
runs it in numba. Nothing is evaluated from user text: the formula is parsed by the laws' whitelist
parser, and the tape holds only opcodes and numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath
import numpy as np

__all__ = ["LawTape", "law_tape", "OPS"]

# opcodes (``_compiled.tape_eval`` implements each)
X, CONST, ADD, SUB, MUL, DIV, NEG = range(7)
FUNCS = ("exp", "log", "sqrt", "sin", "cos", "tan", "sinh", "cosh", "tanh", "atan", "expm1", "log1p", "atan2")
OPS = {name: 7 + i for i, name in enumerate(FUNCS)}


class _Recorder:
    def __init__(self) -> None:
        self.code: list[tuple[int, int, int]] = []
        self.consts: list[float] = []

    def emit(self, op: int, a: int = -1, b: int = -1, c: float = 0.0) -> "_Node":
        self.code.append((op, a, b))
        self.consts.append(c)
        return _Node(self, len(self.code) - 1)

    def lift(self, other) -> "_Node":
        if isinstance(other, _Node):
            return other
        return self.emit(CONST, c=float(other))


class _Node:
    """One register of the tape; arithmetic records operations."""

    def __init__(self, rec: _Recorder, reg: int) -> None:
        self.rec, self.reg = rec, reg

    def _bin(self, op, other, swap=False):
        o = self.rec.lift(other)
        a, b = (o.reg, self.reg) if swap else (self.reg, o.reg)
        return self.rec.emit(op, a, b)

    def __add__(self, o): return self._bin(ADD, o)
    def __radd__(self, o): return self._bin(ADD, o, True)
    def __sub__(self, o): return self._bin(SUB, o)
    def __rsub__(self, o): return self._bin(SUB, o, True)
    def __mul__(self, o): return self._bin(MUL, o)
    def __rmul__(self, o): return self._bin(MUL, o, True)
    def __truediv__(self, o): return self._bin(DIV, o)
    def __rtruediv__(self, o): return self._bin(DIV, o, True)
    def __neg__(self): return self.rec.emit(NEG, self.reg)


class _TapeOps:
    """The backend protocol of ``laws._defect`` (``x``, ``const``, ``fn``) recording a tape."""

    def __init__(self, rec: _Recorder) -> None:
        self.rec = rec
        self.x = rec.emit(X)

    def const(self, value):
        from ...laws._parse import _DPS

        with mpmath.workdps(_DPS):
            return self.rec.emit(CONST, c=float(value() if callable(value) else mpmath.mpf(value)))

    def fn(self, name: str):
        op = OPS[name]

        def call(*args):
            regs = [self.rec.lift(a).reg for a in args] + [-1]
            return self.rec.emit(op, regs[0], regs[1])

        return call


@dataclass(frozen=True)
class LawTape:
    """Per piece k: tape entries [start[k], start[k + 1]) whose last register is g on that piece."""

    code: np.ndarray        # int64 (entries, 3)
    consts: np.ndarray      # float64 (entries,)
    start: np.ndarray       # int64 (pieces + 1,)
    lower: np.ndarray       # float64 (pieces,): left end of each piece in x
    upper: np.ndarray       # float64 (pieces,): right end (inf for the last)
    g_break: np.ndarray     # float64 (pieces − 1,): g at each breakpoint (both pieces agree)
    carlson_langer: bool    # g = x/(1 + x): evaluated directly (the benchmark law; no tape loop)

    @property
    def registers(self) -> int:
        return int(np.max(np.diff(self.start))) if self.start.size > 1 else 1


def law_tape(law) -> LawTape:
    """The tape of ``law`` (a ``FrictionLaw``), built from its formula by the laws' own rules."""
    from ...laws._evaluate import _at
    from ...laws._parse import _parse
    from ...laws.formula import _drop_builder, _offset

    text = law.formula
    pieces, breaks, _ = _parse(text)
    bases = [(exact, mpmath.mpf(float(exact))) for exact in breaks]
    builds = [_drop_builder(pieces[0], mpmath.mpf(0), lambda: 1 - _at(pieces[0], 0), text)]
    for previous, phi, (exact, rounded) in zip(pieces, pieces[1:], bases):
        offset = _offset(phi, (previous, builds[-1]), exact, rounded, text)
        builds.append(_drop_builder(phi, rounded, offset, text))
    code, consts, start = [], [], [0]
    for build in builds:
        rec = _Recorder()
        out = build(_TapeOps(rec))
        if out is None or not isinstance(out, _Node):   # a constant piece
            rec.emit(CONST, c=0.0 if out is None else float(out))
        elif out.reg != len(rec.code) - 1:               # the result must be the last register
            rec.emit(ADD, out.reg, rec.emit(CONST, c=0.0).reg)
        code += rec.code
        consts += rec.consts
        start.append(len(code))
    lower = np.array([0.0] + [float(r) for _, r in bases])
    upper = np.append(lower[1:], np.inf)
    with mpmath.workdps(40):
        g_break = np.array([float(law.pieces[i + 1].drop_mp(mpmath.mpf(b))) for i, b in enumerate(law.breakpoints)])
    return LawTape(np.array(code, dtype=np.int64).reshape(-1, 3), np.array(consts, dtype=np.float64),
                   np.array(start, dtype=np.int64), lower, upper, g_break,
                   law.name == "carlson-langer")
