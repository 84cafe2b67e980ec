"""A small Taylor-series ODE integrator in mpmath (helper indep4's own; no code of the package).

Automatic differentiation on truncated power series: an expression is a DAG of ``S`` nodes whose k-th
coefficient is computed on demand from the children's coefficients 0..k (the classic recurrences for
products, quotients, exp and log), cached per step. ``step`` builds the series of every state variable
to order P (x_{k+1} = f_k/(k+1)), takes the step h = ρ·ε^{1/P} (ρ the radius estimated from the last two
coefficients of each variable, relative to max(1, |x_0|); ε = 10^{4 − dps}), and returns the series so
that the caller can locate events on them (``first_root``).
"""

from __future__ import annotations

from mpmath import mp, mpf


class S:
    """A truncated power series, lazily computed coefficient by coefficient."""

    __slots__ = ("op", "a", "b", "c")

    def __init__(self, op, a=None, b=None, c=None):
        self.op, self.a, self.b, self.c = op, a, b, c if c is not None else []

    def __getitem__(self, k):
        c = self.c
        while len(c) <= k:
            c.append(self._coef(len(c)))
        return c[k]

    def _coef(self, k):
        op, a, b = self.op, self.a, self.b
        if op == "const":
            return a if k == 0 else mpf(0)
        if op == "var":
            raise IndexError("state coefficient not yet known")
        if op == "add":
            return a[k] + b[k]
        if op == "sub":
            return a[k] - b[k]
        if op == "scal":
            return a * b[k]
        if op == "mul":
            return mp.fsum(a[i] * b[k - i] for i in range(k + 1))
        if op == "div":
            q = self.c
            return (a[k] - mp.fsum(b[i] * q[k - i] for i in range(1, k + 1))) / b[0]
        if op == "exp":
            e = self.c
            if k == 0:
                return mp.exp(a[0])
            return mp.fsum(i * a[i] * e[k - i] for i in range(1, k + 1)) / k
        if op == "log":
            g = self.c
            if k == 0:
                return mp.log(a[0])
            return (a[k] - mp.fsum(i * g[i] * a[k - i] for i in range(1, k)) / k) / a[0]
        raise ValueError(op)

    @staticmethod
    def of(x):
        return x if isinstance(x, S) else S("const", mpf(x))

    def __add__(self, o):
        return S("add", self, S.of(o))

    __radd__ = __add__

    def __sub__(self, o):
        return S("sub", self, S.of(o))

    def __rsub__(self, o):
        return S("sub", S.of(o), self)

    def __neg__(self):
        return S("scal", mpf(-1), self)

    def __mul__(self, o):
        if not isinstance(o, S):
            return S("scal", mpf(o), self)
        return S("mul", self, o)

    __rmul__ = __mul__

    def __truediv__(self, o):
        if not isinstance(o, S):
            return S("scal", 1 / mpf(o), self)
        return S("div", self, o)

    def __rtruediv__(self, o):
        return S("div", S.of(o), self)


def sexp(x):
    return S("exp", x)


def slog(x):
    return S("log", x)


def horner(c, r):
    acc = mpf(0)
    for a in reversed(c):
        acc = acc * r + a
    return acc


def deriv(c):
    return [i * c[i] for i in range(1, len(c))]


def step(rhs, x0, t0, order):
    """Taylor series of the solution of x' = rhs(t, x) at (t0, x0): (list of coefficient lists, h, rhs
    series nodes). ``rhs(t, xs)`` gets S nodes and returns a list of S nodes (or constants)."""
    n = len(x0)
    xs = [S("var", c=[mpf(v)]) for v in x0]
    t = S("var", c=[mpf(t0), mpf(1)])
    f = [S.of(q) for q in rhs(t, xs)]
    for k in range(order):
        fk = [q[k] for q in f]
        for i in range(n):
            xs[i].c.append(fk[i] / (k + 1))
        t.c.append(mpf(0))
    eps = mpf(10) ** (4 - mp.dps)
    rho = None
    for x in xs:
        scale = max(1, abs(x.c[0]))
        for kk in (order - 1, order):
            if x.c[kk] != 0:
                r = (scale / abs(x.c[kk])) ** (mpf(1) / kk)
                rho = r if rho is None else min(rho, r)
    h = (rho if rho is not None else mpf(1)) * eps ** (mpf(1) / order)
    return [x.c for x in xs], h, f


def first_root(c, h, skip0=False, samples=24):
    """First sign change of the polynomial c in (0, h], refined by safeguarded Newton (None if none seen
    on the samples). ``skip0``: c(0) is a root just handled; the sign is taken from the first sample."""
    f0 = horner(c, mpf(0))
    if f0 != 0 and not skip0:
        # no root on [0, h] if |c_0| exceeds every other term's largest size there
        hk, bound = mpf(1), mpf(0)
        for a in c[1:]:
            hk *= h
            bound += abs(a) * hk
        if bound < abs(f0):
            return None
    prev_r, prev_f = mpf(0), (None if skip0 or f0 == 0 else f0)
    for s in range(1, samples + 1):
        r = h * s / samples
        fr = horner(c, r)
        if prev_f is None:
            if fr != 0:
                prev_r, prev_f = r, fr
            continue
        if fr == 0:
            return r
        if (fr > 0) != (prev_f > 0):
            return refine(c, prev_r, r, prev_f)
        prev_r, prev_f = r, fr
    return None


def refine(c, a, b, fa):
    dc = deriv(c)
    x = (a + b) / 2
    for _ in range(400):
        fx = horner(c, x)
        if fx == 0:
            return x
        if (fx > 0) == (fa > 0):
            a, fa = x, fx
        else:
            b = x
        d = horner(dc, x)
        xn = x - fx / d if d != 0 else (a + b) / 2
        if not (a < xn < b):
            xn = (a + b) / 2
        if abs(xn - x) <= abs(x) * mpf(10) ** (2 - mp.dps) or b - a <= abs(b) * mpf(10) ** (1 - mp.dps):
            return xn
        x = xn
    return x
