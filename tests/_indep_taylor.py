"""An independent Taylor-series ODE integrator in mpmath, for the test_indep_* references.

Written from the textbook recurrences (automatic differentiation of power series: Moore 1966;
Jorba & Zou, Experiment. Math. 14, 99 (2005), for the step size) without any code or module of
the `bifurcation` package, so that the references it produces are independent of the engine.

A system is built once by calling the user's right-hand side on symbolic nodes; the nodes form a
tape that, per step, computes the Taylor coefficients of every intermediate one order at a time
(x_{n+1} = f(x)_n / (n + 1)). Event functions are nodes too; their roots are found on the step's
polynomial (sign changes on a fine sample, plus a check of every interior minimum of |g| so that a
touching root is not missed), refined by bisection and Newton to the working precision.
"""

from __future__ import annotations

from mpmath import mp, mpf


class Node:
    __slots__ = ("c", "idx")

    def __init__(self):
        self.c = []

    # arithmetic builds the tape -------------------------------------------------
    def __add__(self, o):
        return Add(self, _lift(o))

    __radd__ = __add__

    def __sub__(self, o):
        return Sub(self, _lift(o))

    def __rsub__(self, o):
        return Sub(_lift(o), self)

    def __mul__(self, o):
        if not isinstance(o, Node):
            return Scale(self, mpf(o))
        return Mul(self, o)

    def __rmul__(self, o):
        return self.__mul__(o)

    def __truediv__(self, o):
        if not isinstance(o, Node):
            return Scale(self, 1 / mpf(o))
        return Div(self, o)

    def __rtruediv__(self, o):
        return Div(_lift(o), self)

    def __neg__(self):
        return Scale(self, mpf(-1))


def _lift(o):
    return o if isinstance(o, Node) else Const(o)


class Const(Node):
    def __init__(self, v):
        super().__init__()
        self.v = mpf(v)
        self.args = ()

    def coef(self, n):
        return self.v if n == 0 else mpf(0)


class Var(Node):
    """A state variable (its coefficients are written by the integrator)."""

    def __init__(self, i):
        super().__init__()
        self.i = i
        self.args = ()


class Time(Node):
    def __init__(self):
        super().__init__()
        self.args = ()
        self.t0 = mpf(0)

    def coef(self, n):
        return self.t0 if n == 0 else (mpf(1) if n == 1 else mpf(0))


class Add(Node):
    def __init__(self, a, b):
        super().__init__()
        self.args = (a, b)

    def coef(self, n):
        return self.args[0].c[n] + self.args[1].c[n]


class Sub(Node):
    def __init__(self, a, b):
        super().__init__()
        self.args = (a, b)

    def coef(self, n):
        return self.args[0].c[n] - self.args[1].c[n]


class Scale(Node):
    def __init__(self, a, s):
        super().__init__()
        self.args = (a,)
        self.s = s

    def coef(self, n):
        return self.s * self.args[0].c[n]


class Mul(Node):
    def __init__(self, a, b):
        super().__init__()
        self.args = (a, b)

    def coef(self, n):
        a, b = self.args[0].c, self.args[1].c
        return mp.fsum(a[k] * b[n - k] for k in range(n + 1))


class Div(Node):
    def __init__(self, a, b):
        super().__init__()
        self.args = (a, b)

    def coef(self, n):
        a, b, q = self.args[0].c, self.args[1].c, self.c
        s = a[n] - mp.fsum(b[k] * q[n - k] for k in range(1, n + 1))
        return s / b[0]


class Exp(Node):
    def __init__(self, a, minus_one=False):
        super().__init__()
        self.args = (a,)
        self.m1 = minus_one  # expm1: the same series but c_0 = exp(a_0) − 1 without cancellation

    def coef(self, n):
        a = self.args[0].c
        if n == 0:
            return mp.expm1(a[0]) if self.m1 else mp.exp(a[0])
        e = self.c
        e0 = e[0] + 1 if self.m1 else e[0]
        return mp.fsum(k * a[k] * (e[n - k] if n - k else e0) for k in range(1, n + 1)) / n


class Log(Node):
    def __init__(self, a):
        super().__init__()
        self.args = (a,)

    def coef(self, n):
        a, l = self.args[0].c, self.c
        if n == 0:
            return mp.log(a[0])
        s = a[n] - mp.fsum(k * l[k] * a[n - k] for k in range(1, n)) / n
        return s / a[0]


def exp(a):
    return Exp(a)


def expm1(a):
    return Exp(a, minus_one=True)


def log(a):
    return Log(a)


def _topo(outputs):
    order, seen = [], set()

    def visit(n):
        if id(n) in seen:
            return
        seen.add(id(n))
        for a in n.args:
            visit(a)
        order.append(n)

    for o in outputs:
        visit(o)
    return order


class System:
    """x' = rhs(t, x); `events` are node-valued functions of (t, x) whose zeros are located."""

    def __init__(self, dim, rhs, events=(), outputs=()):
        self.t = Time()
        self.x = [Var(i) for i in range(dim)]
        self.f = [_lift(e) for e in rhs(self.t, self.x)]
        self.g = [_lift(e) for e in (events(self.t, self.x) if events else [])]
        self.o = [_lift(e) for e in (outputs(self.t, self.x) if outputs else [])]
        self.tape = [n for n in _topo(self.f + self.g + self.o) if not isinstance(n, Var)]

    def series(self, t0, x0, order):
        """Taylor coefficients (in the step's local time) of the state, events and outputs."""
        self.t.t0 = mpf(t0)
        for v, x in zip(self.x, x0):
            v.c = [mpf(x)]
        for n in self.tape:
            n.c = []
        for k in range(order + 1):
            for n in self.tape:
                n.c.append(n.coef(k))
            if k < order:
                for v, f in zip(self.x, self.f):
                    v.c.append(f.c[k] / (k + 1))
        return ([v.c for v in self.x], [g.c for g in self.g], [o.c for o in self.o])


def peval(c, h):
    s = mpf(0)
    for a in reversed(c):
        s = s * h + a
    return s


def pderiv(c):
    return [k * c[k] for k in range(1, len(c))]


def step_size(xs, order, tol):
    """Jorba–Zou: the last two terms of the series below tol relative to the state's size."""
    scale = max([mpf(1)] + [abs(c[0]) for c in xs])
    rho = mp.inf
    for c in xs:
        for n in (order - 1, order):
            if c[n] != 0:
                rho = min(rho, (tol * scale / abs(c[n])) ** (mpf(1) / n))
    return rho


def first_root(c, h, samples=48, skip0=False):
    """First zero of the polynomial c in (0, h] (a sign change, or an interior minimum of |p|
    that touches 0 to the working precision); None if none."""
    d = pderiv(c)
    ts = [h * k / samples for k in range(samples + 1)]
    vs = [peval(c, t) for t in ts]
    ds = [peval(d, t) for t in ts]
    # the rounding of p on [0, h]: a touching root is one that |p| reaches to within it
    eps = mpf(10) ** (-mp.dps + 5) * peval([abs(a) for a in c], h)
    for k in range(samples):
        a, b = ts[k], ts[k + 1]
        va, vb = vs[k], vs[k + 1]
        if k == 0 and skip0:
            va = peval(c, a + (b - a) * mpf(10) ** (-mp.dps // 3))
        if va == 0 and not (k == 0 and skip0) and k > 0:
            return a
        if (va > 0) != (vb > 0) and vb != 0:
            return _bisect(c, d, a, b)
        if vb == 0:
            return b
        # a touching root (same sign at both ends, |p| dips to a minimum in between)
        da, db = ds[k], ds[k + 1]
        dips = (va > 0 and da < 0 < db) or (va < 0 and da > 0 > db)
        if dips and not (k == 0 and skip0):
            tm = _bisect(d, pderiv(d), a, b)
            vm = peval(c, tm)
            if (vm > 0) != (va > 0):
                return _bisect(c, d, a, tm)
            if abs(vm) <= eps:
                return tm
    return None


def _bisect(c, d, a, b):
    fa = peval(c, a)
    for _ in range(400):
        m = (a + b) / 2
        fm = peval(c, m)
        if fm == 0:
            return m
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
        if b - a <= abs(b) * mpf(2) ** (-mp.prec + 4) + mpf(10) ** (-2 * mp.dps):
            break
    return (a + b) / 2
