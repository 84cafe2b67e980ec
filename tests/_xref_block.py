"""A second independent reference for one slip cycle of the (damped) single block.

Written apart from tests/_indep_single.py and the package (no code of either): the equation of
docs/physics.md / docs/models.md in the physical variables,

    Ü = νt − U + g(U̇/ν_f) − γU̇,   g = 1 − Φ,   U(0) = U̇(0) = 0,

until U̇ returns to 0, by two methods:

* ``smooth_cycle``: mpmath.odefun (mpmath's own adaptive Taylor integrator) for analytic laws, with g
  written by hand without cancellation (x/(1+x), −expm1(−x), ...) so that its relative error is O(ε)
  at the tiny x of the start (x ~ ν t²/ν_f). Events are sign changes of U̇, U̇ − ν_f and Ü on a grid
  of ``h`` refined by mpmath.findroot (Anderson–Björk) on odefun's dense output.
* ``linear_cycle``: laws whose g is linear on each piece (the piecewise-linear law, Eq. 12 of
  Vasconcelos, PRL 76, 4865 (1996), and user piecewise formulas), solved exactly: on a piece
  g = p + q x, Ü + cU̇ + U = νt + p with c = γ − q/ν_f, so U = νt + p − cν + A e^{λ1 t} + B e^{λ2 t}.

The two agree to ≤ 1e-28 on the piecewise-linear law's smooth first piece (test_xref_block.py).
"""

from __future__ import annotations

from mpmath import mp, mpf, mpc, exp, expm1, sqrt, odefun, findroot, re as mre

# g = 1 − Φ for analytic laws, written without cancellation (exact identities, checked at the bottom)
SMOOTH = {
    "carlson-langer": lambda x: x / (1 + x),
    "exponential": lambda x: -expm1(-x),
    "1/(1+x+x^2)": lambda x: (x + x * x) / (1 + x + x * x),
    "exp(-x-x^2)": lambda x: -expm1(-x - x * x),
    "exp(-x)*(1+x*x)": lambda x: -expm1(-x) - x * x * exp(-x),
    "(1+x)*exp(-2*x)": lambda x: -expm1(-2 * x) - x * exp(-2 * x),
    "1/sqrt(1+2*x)": lambda x: 2 * x / (sqrt(1 + 2 * x) * (1 + sqrt(1 + 2 * x))),
    "_linear": lambda x: x,      # Φ = 1 − x everywhere: not a law, a cross-check of the two methods
}
# laws linear in x on each piece: [(x_left, p, q)], g = p + q x on [x_left, next x_left)
LINEAR = {
    "piecewise-linear": [(0, 0, 1), (1, 1, 0)],
    "piecewise(1 - x, 1, 0)": [(0, 0, 1), (1, 1, 0)],
    # Φ = 1 − x on [0, 1/2), 1/2 − (x − 1/2)/5 on [1/2, 2), 1/5 above: g = x, 2/5 + x/5, 4/5
    "piecewise(1 - x, 0.5, 0.5 - (x - 0.5)/5, 2, 0.2)": [(0, 0, 1), (mpf(1) / 2, mpf(2) / 5, mpf(1) / 5),
                                                        (2, mpf(4) / 5, 0)],
}


def _bracket_root(f, a, b):
    """The root of f in the bracket [a, b] (a sign change there)."""
    fa, fb = f(a), f(b)
    if fb == 0:
        return b
    if fa == 0:
        return a
    try:
        return findroot(f, (a, b), solver="anderson")
    except (ZeroDivisionError, ValueError):     # a flat secant: fall back on bisection
        return findroot(f, (a, b), solver="bisect")


def smooth_cycle(law, nu, nu_f, gamma=0, *, dps=30, h=None, t_max=400):
    """dict(delta, stop_time, creep_time (None if U̇ < ν_f throughout), max_velocity) as mpf."""
    with mp.workdps(dps):
        nu, nu_f, gamma = mpf(nu), mpf(nu_f), mpf(gamma)
        g = SMOOTH[law]

        def acc(t, y):
            return nu * t - y[0] + g(y[1] / nu_f) - gamma * y[1]

        F = odefun(lambda t, y: [y[1], acc(t, y)], 0, [mpf(0), mpf(0)])
        h = mpf(h) if h is not None else min(mpf(1) / 20, nu_f / 4)
        invisible = mpf(10) ** (5 - dps)
        t, y = mpf(0), [mpf(0), mpf(0)]
        creep_time, vmax = None, mpf(0)
        prev_a = None
        while t < t_max:
            if 1 - g(y[1] / nu_f) < invisible:
                # odefun sizes a step from its series' last coefficient at the step's start: where a
                # fading friction (e^{−x−x²} at x ≫ 1) is below the working precision it cannot see
                # the friction coming back and steps over its return (measured: 3.7e-4 off in the stop
                # time at ν = 1e-6, ν_f = 0.01; scipy DOP853 with max_step 0.01 and the engine agree to
                # 1e-9 on the right value). Restarting at every h there bounds the step: within h,
                # x = U̇/ν_f moves by ≤ h|Ü|/ν_f ≈ 1/4, too little for friction to grow from below
                # 10^−(dps−5) to matter. Costly (~300 s at ν_f = 0.004), so only where Φ is invisible.
                F = odefun(lambda tt, yy: [yy[1], acc(tt, yy)], t, y)
            t1 = t + h
            y1 = F(t1)
            a1 = acc(t1, y1)
            if creep_time is None and y[1] < nu_f <= y1[1]:
                creep_time = _bracket_root(lambda s: F(s)[1] - nu_f, t, t1)
            if prev_a is not None and prev_a > 0 >= a1:   # a velocity maximum
                tm = _bracket_root(lambda s: acc(s, F(s)), t, t1)
                vmax = max(vmax, F(tm)[1])
            if y1[1] <= 0:                                  # the stop
                ts = _bracket_root(lambda s: F(s)[1], t, t1)
                return dict(delta=F(ts)[0], stop_time=ts, creep_time=creep_time, max_velocity=vmax)
            t, y, prev_a = t1, y1, a1
        raise RuntimeError("no stop before t_max")


def _piece_solution(nu, nu_f, gamma, p, q, t0, u0, v0):
    """U(t), U̇(t), Ü(t) on one linear piece from (t0, u0, v0), exact (complex roots allowed)."""
    c = gamma - q / nu_f
    disc = c * c - 4
    if abs(disc) < mpf(10) ** (-mp.dps // 2):
        raise ValueError("repeated root: choose parameters off c = ±2")
    r = sqrt(mpc(disc))
    l1, l2 = (-c + r) / 2, (-c - r) / 2
    # U = νt + p − cν + A e^{l1 (t−t0)} + B e^{l2 (t−t0)}
    w0 = u0 - (nu * t0 + p - c * nu)
    w1 = v0 - nu
    A = (w1 - l2 * w0) / (l1 - l2)
    B = w0 - A

    def at(t):
        s = t - t0
        e1, e2 = exp(l1 * s), exp(l2 * s)
        u = nu * t + p - c * nu + mre(A * e1 + B * e2)
        v = nu + mre(A * l1 * e1 + B * l2 * e2)
        a = mre(A * l1 * l1 * e1 + B * l2 * l2 * e2)
        return u, v, a

    return at


def linear_cycle(law, nu, nu_f, gamma=0, *, dps=40, h=None, t_max=400):
    """As smooth_cycle, for a law linear on each piece: the exact solution of each piece."""
    with mp.workdps(dps):
        nu, nu_f, gamma = mpf(nu), mpf(nu_f), mpf(gamma)
        pieces = [(mpf(a), mpf(p), mpf(q)) for a, p, q in LINEAR[law]]
        edges = [a * nu_f for a, _, _ in pieces[1:]]     # breakpoints in U̇

        h = mpf(h) if h is not None else min(mpf(1) / 50, nu_f / 8)
        t, u, v = mpf(0), mpf(0), mpf(0)
        k = 0
        creep_time, vmax = None, mpf(0)
        sol = _piece_solution(nu, nu_f, gamma, pieces[k][1], pieces[k][2], t, u, v)
        prev_a = None
        while t < t_max:
            t1 = t + h
            u1, v1, a1 = sol(t1)
            lo = edges[k - 1] if k > 0 else None
            hi = edges[k] if k < len(edges) else None
            # the earliest event in (t, t1]: leaving the piece, the stop, a maximum
            cands = []
            if hi is not None and v1 >= hi:
                cands.append((_bracket_root(lambda s: sol(s)[1] - hi, t, t1), "up"))
            if lo is not None and v1 <= lo:
                cands.append((_bracket_root(lambda s: sol(s)[1] - lo, t, t1), "down"))
            if v1 <= 0 and t > 0:
                cands.append((_bracket_root(lambda s: sol(s)[1], t, t1), "stop"))
            if prev_a is not None and prev_a > 0 >= a1:
                tm = _bracket_root(lambda s: sol(s)[2], t, t1)
                vmax = max(vmax, sol(tm)[1])
            te, kind = min(cands, key=lambda c: c[0]) if cands else (t1, None)
            if creep_time is None and nu_f not in edges and v < nu_f <= sol(te)[1]:
                creep_time = _bracket_root(lambda s: sol(s)[1] - nu_f, t, te)
            if kind is not None:
                ue, ve, ae = sol(te)
                if kind == "stop":
                    return dict(delta=ue, stop_time=te, creep_time=creep_time, max_velocity=vmax)
                if kind == "up" and creep_time is None and edges[k] == nu_f:
                    creep_time = te
                k += 1 if kind == "up" else -1
                ve = edges[k - 1] if kind == "up" else edges[k]   # exactly on the breakpoint
                sol = _piece_solution(nu, nu_f, gamma, pieces[k][1], pieces[k][2], te, ue, ve)
                t, v, prev_a = te, ve, None
                continue
            t, v, prev_a = t1, v1, a1
        raise RuntimeError("no stop before t_max")


def cycle(law, nu, nu_f, gamma=0, **kw):
    return (linear_cycle if law in LINEAR else smooth_cycle)(law, nu, nu_f, gamma, **kw)


def fast_eigen(nu_f, gamma=0):
    """λ+ of the ν = 0 linearisation Ü = −U + (1/ν_f − γ) U̇ (real for ν_f ≤ 1/(2 + γ))."""
    c = 1 / mpf(nu_f) - gamma
    return (c + sqrt(c * c - 4)) / 2


def limit_delta0(law, nu_f, *, eps=mpf("1e-18"), dps=34):
    """Δ0 of the ν = 0 orbit leaving U = U̇ = 0 along the fast eigenvector (ν_f < 1/2).

    Started at ε(1, λ+) plus the second-order term of the unstable manifold is not needed: a start
    off the manifold by O(ε²) transverse grows with the slow rate λ−, reaching ε^{2 − λ−/λ+} ≪ ε by
    the time the fast part is O(1); two ε (1e-18, 1e-22) bound this (the caller compares them).
    Analytic laws only (odefun).
    """
    with mp.workdps(dps):
        nu_f, eps = mpf(nu_f), mpf(eps)
        g = SMOOTH[law]
        lp = fast_eigen(nu_f)

        def acc(y):
            return -y[0] + g(y[1] / nu_f)

        F = odefun(lambda t, y: [y[1], acc(y)], 0, [eps, eps * lp])
        h = nu_f / 4
        t, prev_a, vmax = mpf(0), acc([eps, eps * lp]), mpf(0)
        while t < 2000:
            t1 = t + h
            y1 = F(t1)
            a1 = acc(y1)
            if prev_a > 0 >= a1:
                tm = _bracket_root(lambda s: acc(F(s)), t, t1)
                vmax = max(vmax, F(tm)[1])
            if y1[1] <= 0:
                ts = _bracket_root(lambda s: F(s)[1], t, t1)
                return dict(delta0=F(ts)[0], max_velocity0=vmax)
            t, prev_a = t1, a1
        raise RuntimeError("no stop")
