"""A third independent reference for one slip cycle of the single block (tests/test_indep3_block.py).

Written without reading the package's engine, nor using tests/_indep_taylor.py or mpmath.odefun (the
two earlier references): its own Taylor-series recurrences in mpmath for

    U' = V,   V' = νt − U + g(V/ν_f),   g = 1 − Φ,   U(0) = V(0) = 0,

(docs/physics.md; Vasconcelos, PRL 76, 4865 (1996), Eq. 5), integrated in the physical variables
with order-P steps whose size follows the last two coefficients, and every event (the stop V = 0, the
first V = ν_f, each velocity maximum, each crossing of the piecewise-linear kink) found by sampling
the step's polynomial and bisecting it to full working precision. The kink of Φ at x = 1 switches the
piece exactly at the crossing: each piece is smooth.

Laws: carlson-langer g = x/(1+x), exponential g = 1 − e^{−x}, piecewise-linear g = min(x, 1),
"1/(1+x+x^2)" g = (x + x²)/(1 + x + x²).
"""

from __future__ import annotations

from mpmath import mp, mpf


class _Law:
    """Incremental Taylor coefficients of g(x(t)): ``next(xs)`` returns g_k from x_0..x_k."""

    def __init__(self, law, piece):
        self.law, self.piece = law, piece
        self.g, self.aux, self.aux2 = [], [], []

    def next(self, xs):
        k = len(xs) - 1
        law = self.law
        if law == "piecewise-linear":
            v = xs[k] if self.piece == 0 else (mpf(1) if k == 0 else mpf(0))
        elif law == "carlson-langer":      # g = x/d, d = 1 + x
            d = [1 + xs[0]] + xs[1:]
            v = (xs[k] - sum(d[j] * self.g[k - j] for j in range(1, k + 1))) / d[0]
        elif law == "exponential":         # e = exp(−x), g = 1 − e
            if k == 0:
                e = mp.exp(-xs[0])
                v = -mp.expm1(-xs[0])
            else:
                e = -sum(j * xs[j] * self.aux[k - j] for j in range(1, k + 1)) / k
                v = -e
            self.aux.append(e)
        elif law == "1/(1+x+x^2)":         # g = n/d, n = x + x², d = 1 + n
            sq = sum(xs[j] * xs[k - j] for j in range(k + 1))
            n = xs[k] + sq
            self.aux.append(n)
            d0 = 1 + self.aux[0]
            v = (n - sum(self.aux[j] * self.g[k - j] for j in range(1, k + 1))) / d0
        else:
            raise ValueError(law)
        self.g.append(v)
        return v


def _series(law, piece, nu, nu_f, t0, u0, v0, order):
    us, vs, xs = [u0], [v0], []
    lw = _Law(law, piece)
    for k in range(order):
        xs.append(vs[k] / nu_f)
        g = lw.next(xs)
        f = (nu * t0 if k == 0 else (nu if k == 1 else 0)) - us[k] + g
        us.append(vs[k] / (k + 1))
        vs.append(f / (k + 1))
    return us, vs


def _ev(c, s):
    r = mpf(0)
    for a in reversed(c):
        r = r * s + a
    return r


def _first_root(c, h, lo_frac, samples=24):
    """Smallest root of the polynomial c in (lo_frac·h, h] by sampling and bisection, or None."""
    a = h * lo_frac
    fa = _ev(c, a)
    for i in range(1, samples + 1):
        b = h * i / samples
        if b <= a:
            continue
        fb = _ev(c, b)
        if fa == 0:
            return a
        if (fa > 0) != (fb > 0):
            lo, hi = a, b
            for _ in range(mp.prec + 4):
                m = (lo + hi) / 2
                fm = _ev(c, m)
                if (fm > 0) == (fa > 0):
                    lo = m
                else:
                    hi = m
            return (lo + hi) / 2
        a, fa = b, fb
    return None


def _fade_cap(vs, nu_f, h, dps):
    """Shorten a step so that the friction of e^{−x} cannot come back unseen within it.

    The series of e^{−x(t)} is proportional to e^{−x0}: at large x its coefficients do not limit the
    step, which could then cross the whole return of the friction near the stop (the blind spot of
    docs/engine.md, "Friction that fades"; an earlier version of this reference had it: Δ 3.3e-9 too
    large at ν = 1e-6, ν_f = 1e-4, i.e. ≈ (π²/12)ν_f²/2). Above X_NEG, where e^{−x} is below the
    working precision by 10 more decades, a step may not go below X_NEG; below it, x may change by at
    most 1 per step (the friction by at most a factor e)."""
    x_neg = (dps + 10) * mp.log(10)
    xs = [c / nu_f for c in vs]
    x0 = xs[0]
    if x0 > x_neg:
        d = list(xs)
        d[0] -= x_neg
        r = _first_root(d, h, mpf(0))
        return r if r is not None and r > 0 else h
    rate = max(abs(xs[1]), mpf(10) ** -30)
    return min(h, 1 / rate)


def cycle(law, nu, nu_f, dps=45, order=32, max_steps=200000):
    """Δ, stop time, t1 (None if V never reaches ν_f), max V and steps of one cycle, as mpf."""
    with mp.workdps(dps):
        nu, nu_f = mpf(nu), mpf(nu_f)
        eps = mpf(10) ** (-(dps - 3))
        t, u, v = mpf(0), mpf(0), mpf(0)
        piece, t1, vmax, last, crossings = 0, None, mpf(0), None, 0
        for step in range(max_steps):
            us, vs = _series(law, piece, nu, nu_f, t, u, v, order)
            # absolute tolerance on the scale of the state (ν while the block creeps)
            tol = eps * max(abs(u), abs(v), nu)
            hs = []
            for k in (order - 1, order):
                m = max(abs(us[k]), abs(vs[k]))
                if m > 0:
                    hs.append((tol / m) ** (mpf(1) / k))
            h = min(hs) * mpf("0.5") if hs else mpf(1)
            if law == "exponential":
                h = _fade_cap(vs, nu_f, h, dps)
            acc = [(k + 1) * vs[k + 1] for k in range(order)]   # V' series
            dv = list(vs)
            dv[0] -= nu_f
            # a function that starts on its own root (t = 0, or the event just found) is searched from
            # 1e-9 of the step on: its next root is a separate event, never that close
            lo = {k: (mpf(10) ** -9 if (step == 0 or last == k) else mpf(0)) for k in ("stop", "nuf", "max")}
            cands = []
            for kind, c in (("stop", vs), ("nuf", dv), ("max", acc)):
                start = lo[kind]
                while True:
                    r = _first_root(c, h, start)
                    if r is None or r <= 0:
                        break
                    if kind == "max" and not _ev(acc, r * (1 - mpf(10) ** -6)) > 0:
                        start = r / h * (1 + mpf(10) ** -6)      # a minimum of V: look past it
                        continue
                    cands.append((r, kind))
                    break
            if cands:
                s, kind = min(cands, key=lambda p: p[0])
            else:
                s, kind = h, None
            u, v, t = _ev(us, s), _ev(vs, s), t + s
            last = kind
            if kind == "stop":
                return {"delta": u, "stop_time": t, "creep_time": t1, "max_velocity": vmax, "steps": step,
                        "crossings": crossings}
            if kind == "max":
                vmax = max(vmax, v)
            elif kind == "nuf":
                up = _ev(acc, s) > 0
                crossings += 1
                if up and t1 is None:
                    t1 = t
                if law == "piecewise-linear":
                    piece = 1 if up else 0
                    v = nu_f         # on the kink exactly
        raise RuntimeError("no stop within max_steps")
