"""Independent mpmath reference for one slip cycle of the single block (tests/test_indep_single.py).

Equation (docs/physics.md; Vasconcelos, PRL 76, 4865 (1996), Eq. 5 measured from the start of a slip):
    Ü = νt − U + 1 − Φ(U̇/ν_f),   U(0) = U̇(0) = 0,
until U̇ returns to 0. Integrated in the physical variables U, U̇ (the engine integrates the scaled
W = U/ν: a different formulation), at 50 digits with an absolute tolerance of 1e-46, by
tests/_indep_taylor.py. The piecewise-linear law's kink at x = 1 is an event: each smooth piece is
integrated separately. Also a closed form for the piecewise-linear law (linear pieces, solved
exactly in mpmath) as a second method.
"""

from __future__ import annotations

from mpmath import mp, mpf

import _indep_taylor as tt


def _law_pieces(law):
    """1 − Φ(x) as node expressions, one per smooth piece, and the breakpoints in x."""
    if law == "carlson-langer":
        return [lambda x: x / (1 + x)], []
    if law == "exponential":
        return [lambda x: -tt.expm1(-x)], []
    if law == "piecewise-linear":
        return [lambda x: x, lambda x: tt.Const(1) + 0 * x], [mpf(1)]
    if law == "quadratic-cl":  # user formula 1/(1+x/2)^2: 1 − Φ = (x + x²/4)/(1 + x/2)²
        return [lambda x: (x + x * x / 4) / ((1 + x / 2) * (1 + x / 2))], []
    raise ValueError(law)


def _fade_cap(vs, nu_f, h, dps):
    """Shorten a step so that the friction of e^{−x} cannot come back unseen within it.

    The series of 1 − e^{−x(t)} beyond its constant is proportional to e^{−x0}: at large x (x ~ 1/ν_f) it
    does not limit the step, which then crossed the friction's return near the stop (docs/engine.md,
    "Friction that fades"): without this cap, at ν = 1e-6, ν_f = 1e-4 this reference gave
    Δ = 2.0000031280449, 6.5e-9 above tests/_indep3_block.py and the engine (2.0000031215258). As
    tests/_indep3_block.py does: above x_neg, where e^{−x} is 10 decades below the working precision, a
    step may not take x below x_neg; below it, x may change by at most 1 per step (e^{−x} by a factor e).
    """
    x_neg = (dps + 10) * mp.log(10)
    xs = [c / nu_f for c in vs]
    if xs[0] > x_neg:
        d = list(xs)
        d[0] -= x_neg
        r = tt.first_root(d, h)
        return r if r is not None and r > 0 else h
    return min(h, 1 / max(abs(xs[1]), mpf(10) ** -30))


def single_cycle(law, nu, nu_f, dps=50, order=40, tol=None):
    """Δ, stop time, t1 (first U̇ = ν_f, None if never), max U̇ of one cycle, as mpf."""
    with mp.workdps(dps):
        tol = mpf(10) ** (-(dps - 4)) if tol is None else mpf(tol)
        nu, nu_f = mpf(nu), mpf(nu_f)
        pieces, breaks = _law_pieces(law)
        systems = []
        for g in pieces:
            def rhs(t, x, g=g):
                return [x[1], nu * t - x[0] + g(x[1] / nu_f)]

            def ev(t, x):
                # stop, ν_f crossing (t1 and the kink), velocity maximum
                return [x[1] / nu_f, x[1] / nu_f - 1, rhs(t, x)[1]]

            systems.append(tt.System(2, rhs, ev))
        piece = 0
        t, st = mpf(0), [mpf(0), mpf(0)]
        t1, vmax = None, mpf(0)
        first = True
        for _ in range(100000):
            sysm = systems[piece]
            xs, gs, _o = sysm.series(t, st, order)
            h = tt.step_size(xs, order, tol)
            if law == "exponential":
                h = _fade_cap(xs[1], nu_f, h, dps)
            # event candidates in (0, h]
            hits = []
            r = tt.first_root(gs[0], h, skip0=first)
            if r is not None:
                hits.append((r, "stop"))
            r = tt.first_root(gs[1], h, skip0=(abs(gs[1][0]) < tol))
            if r is not None:
                hits.append((r, "nuf"))
            r = tt.first_root(gs[2], h, skip0=first or abs(gs[2][0]) < tol)
            if r is not None and gs[2][0] > 0:
                hits.append((r, "max"))
            first = False
            if hits:
                r, kind = min(hits, key=lambda p: p[0])
            else:
                r, kind = h, None
            st = [tt.peval(c, r) for c in xs]
            t = t + r
            if kind == "max":
                vmax = max(vmax, st[1])
                # step just past the maximum so it is not found again
            elif kind == "nuf":
                if t1 is None:
                    t1 = t
                if breaks:
                    piece = 1 if tt.peval(tt.pderiv(gs[1]), r) > 0 else 0
            elif kind == "stop":
                return {"delta": st[0], "stop_time": t, "creep_time": t1,
                        "max_velocity": max(vmax, mpf(0))}
        raise RuntimeError("no stop")


def piecewise_linear_closed_form(nu, nu_f, dps=40):
    """Second method for the piecewise-linear law: each piece is a linear ODE solved exactly.

    Piece x < 1:  Ü − 2αU̇ + U = νt (α = 1/(2ν_f)), U = νt + 2αν + A e^{λ+ t} + B e^{λ− t};
    piece x ≥ 1:  Ü + U = νt + 1,                   U = νt + 1 + C cos t + D sin t.
    Crossings of U̇ = ν_f and the stop U̇ = 0 by sampling the closed form and bisection.
    Returns Δ, stop time, t1 (or None), max U̇.
    """
    with mp.workdps(dps):
        nu, nu_f = mpf(nu), mpf(nu_f)
        al = 1 / (2 * nu_f)
        disc = mp.sqrt(mp.mpc(al * al - 1))
        lp, lm = al + disc, al - disc

        def piece0(t0, u0, v0):
            # U(t0 + s) = ν(t0 + s) + 2αν + A e^{λ+ s} + B e^{λ− s}
            r0 = u0 - nu * t0 - 2 * al * nu
            r1 = v0 - nu
            b = (r1 - lp * r0) / (lm - lp)
            a = r0 - b
            u = lambda s: (nu * (t0 + s) + 2 * al * nu + a * mp.exp(lp * s) + b * mp.exp(lm * s)).real
            v = lambda s: (nu + a * lp * mp.exp(lp * s) + b * lm * mp.exp(lm * s)).real
            return u, v

        def piece1(t0, u0, v0):
            c = u0 - nu * t0 - 1
            d = v0 - nu
            u = lambda s: nu * (t0 + s) + 1 + c * mp.cos(s) + d * mp.sin(s)
            v = lambda s: nu - c * mp.sin(s) + d * mp.cos(s)
            return u, v

        def first_zero(f, s0, ds, smax):
            s = s0
            fa = f(s)
            while s < smax:
                fb = f(s + ds)
                if (fa > 0) != (fb > 0):
                    a, b = s, s + ds
                    for _ in range(mp.prec + 10):
                        m = (a + b) / 2
                        if (f(m) > 0) == (fa > 0):
                            a = m
                        else:
                            b = m
                    return (a + b) / 2
                s, fa = s + ds, fb
            return None

        t, u0, v0, t1, vmax, piece = mpf(0), mpf(0), mpf(0), None, mpf(0), 0
        ds = mpf(1) / 64
        for _ in range(1000):
            u, v = (piece0 if piece == 0 else piece1)(t, u0, v0)
            # scan U̇ for the first of: a crossing of ν_f, a return to 0
            s, va = ds / 1000, v(ds / 1000)
            while True:
                vb = v(s + ds)
                if vb <= 0 or (va > nu_f) != (vb > nu_f):
                    break
                s, va = s + ds, vb
            s_stop = first_zero(v, s, ds, s + ds) if vb <= 0 else None
            s_cross = first_zero(lambda q: v(q) - nu_f, s, ds, s + ds)
            if s_stop is not None and s_cross is not None and s_stop < s_cross:
                s_cross = None
            if s_cross is not None:
                s_stop = None
            # velocity maximum in this piece: U̇' = 0 (bracketed by sampling U̇ before the end)
            s_end = s_cross if s_cross is not None else s_stop
            grid = [s_end * k / 256 for k in range(257)]
            vmax = max([vmax] + [v(s) for s in grid])
            if piece == 1 or s_cross is None:
                acc = lambda s: mp.diff(v, s)
                sm = first_zero(acc, ds / 1000, ds, s_end)
                if sm is not None:
                    vmax = max(vmax, v(sm))
            if s_cross is not None:
                t1 = t + s_cross if t1 is None else t1
                t, u0, v0 = t + s_cross, u(s_cross), nu_f
                piece = 1 - piece
                continue
            return {"delta": u(s_stop), "stop_time": t + s_stop, "creep_time": t1, "max_velocity": vmax}
        raise RuntimeError("no stop")


def limit_delta0(law, nu_f, eps=mpf(10) ** -22, dps=50, order=40):
    """Δ0 = lim_{ν→0} Δ for ν_f < 1/2: the ν = 0 orbit leaving U = U̇ = 0 along the fast eigenvector.

    Started at U = ε, U̇ = λ+ ε (λ+ = α + ω, α = 1/(2ν_f), ω = √(α² − 1)); the start's offset from the
    unstable manifold is O(ε²) and its slow-mode part decays relative to the fast one, so with
    ε = 1e-22 the error in Δ0 is ~1e-22 relative (checked by halving ε in the test).
    Returns Δ0 = U at the first return of U̇ to 0 (the fixed point is at U = 0), and max U̇.
    """
    with mp.workdps(dps):
        tol = mpf(10) ** (-(dps - 4))
        nu_f = mpf(nu_f)
        al = 1 / (2 * nu_f)
        lp = al + mp.sqrt(al * al - 1)
        pieces, _breaks = _law_pieces(law)
        systems = []
        for g in pieces:
            def rhs(t, x, g=g):
                return [x[1], -x[0] + g(x[1] / nu_f)]

            systems.append(tt.System(2, rhs, lambda t, x, rhs=rhs: [x[1] / nu_f, x[1] / nu_f - 1,
                                                                     rhs(t, x)[1]]))
        piece, t, st, vmax = 0, mpf(0), [mpf(eps), lp * mpf(eps)], mpf(0)
        skip = set()
        for _ in range(100000):
            xs, gs, _o = systems[piece].series(t, st, order)
            h = tt.step_size(xs, order, mpf(tol) * max(abs(st[0]), mpf(eps)))
            hits = []
            for gi in range(3):
                r = tt.first_root(gs[gi], h, skip0=gi in skip)
                if r is not None:
                    hits.append((r, gi))
            skip = set()
            r, gi = min(hits) if hits else (h, None)
            st = [tt.peval(c, r) for c in xs]
            t += r
            if gi is not None:
                skip.add(gi)
            if gi == 0:
                return {"delta0": st[0], "max_velocity0": vmax}
            if gi == 1 and len(pieces) > 1:
                piece = 1 if tt.peval(tt.pderiv(gs[1]), r) > 0 else 0
            if gi == 2:
                vmax = max(vmax, st[1])
        raise RuntimeError("no stop")
