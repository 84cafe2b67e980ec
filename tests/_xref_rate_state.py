"""A second independent reference for the rate-and-state slider (no code of the package or of
tests/_indep_rate_state.py), in the physical variables V, θ_i (and, with mass M, the net force F):

    μ = μ0 + a ln(V/V*) + Σ b_i ln(V* θ_i/(c_i Dc_i)),   c = 1 (aging, slip), 2 (PRZ)
    θ̇: aging 1 − Vθ/Dc;  slip −(Vθ/Dc) ln(Vθ/Dc);  PRZ 1 − (Vθ/(2Dc))²     (docs/rate-state.md)
    quasi-static  k(V_lp − V) − ηV̇ = dμ/dt   →   V̇ = [k(V_lp − V) − Σ b_i θ̇_i/θ_i] / (a/V + η)
    inertial      M V̇ = F,   Ḟ = k(V_lp − V) − ηV̇ − dμ/dt = k(V_lp − V) − (η + a/V) F/M − Σ b_i θ̇_i/θ_i

* ``hopf``: the Hopf point as the real root (k, ω) of det(J(k) − iω I) = 0 (real and imaginary parts,
  mpmath.findroot in two unknowns), J the Jacobian at the steady state V = V_lp, θ_i = c_i Dc_i/V_lp,
  F = 0, differentiated by mpmath.diff (J is affine in k: J(0) and J(1) suffice); no closed form, no
  eigenvalue routine.
* ``series``: μ, V, θ at given times after a load-point velocity step, by mpmath.odefun.
"""

from __future__ import annotations

from mpmath import mp, mpf, mpc, exp, log, diff, findroot, matrix, det, eye, odefun

C = {"aging": 1, "slip": 1, "prz": 2}


def _theta_dot(law, v, th, dc):
    if law == "aging":
        return 1 - v * th / dc
    if law == "slip":
        r = v * th / dc
        return -r * log(r)
    if law == "prz":
        return 1 - (v * th / (2 * dc)) ** 2
    raise ValueError(law)


def rhs(laws, a, bs, dcs, k, v_lp, mass=None, eta=0):
    """f(y) with y = [V, θ_1, ..., (F)]."""
    n = len(laws)

    def f(y):
        v, ths = y[0], y[1:1 + n]
        tds = [_theta_dot(law, v, th, dc) for law, th, dc in zip(laws, ths, dcs)]
        state = sum(b * td / th for b, td, th in zip(bs, tds, ths))
        if mass is None:
            vd = (k * (v_lp - v) - state) / (a / v + eta)
            return [vd] + tds
        force = y[1 + n]
        vd = force / mass
        return [vd] + tds + [k * (v_lp - v) - (eta + a / v) * vd - state]

    return f


def _jacobian(f, y0):
    m = len(y0)
    J = matrix(m, m)
    for j in range(m):
        def fj(x, j=j):
            y = list(y0)
            y[j] = x
            return f(y)
        col = [diff(lambda x, i=i: fj(x)[i], y0[j]) for i in range(m)]
        for i in range(m):
            J[i, j] = col[i]
    return J


def hopf(laws, a, bs, dcs, v_lp, mass=None, eta=0, *, guess, dps=40):
    """(k_c, ω_c) with det(J(k_c) − iω_c I) = 0, from ``guess`` = (k, ω)."""
    with mp.workdps(dps):
        a, v_lp, eta = mpf(a), mpf(v_lp), mpf(eta)
        bs, dcs = [mpf(b) for b in bs], [mpf(d) for d in dcs]
        mass = None if mass is None else mpf(mass)
        y0 = [v_lp] + [C[law] * dc / v_lp for law, dc in zip(laws, dcs)] + ([] if mass is None else [mpf(0)])

        # J is affine in k (k multiplies V_lp − V, which vanishes at the steady state, nowhere else)
        J0 = _jacobian(rhs(laws, a, bs, dcs, 0, v_lp, mass, eta), y0)
        J1 = _jacobian(rhs(laws, a, bs, dcs, 1, v_lp, mass, eta), y0) - J0
        eye_m = eye(len(y0))

        def eqs(k, w):
            d = det(J0 + k * J1 - mpc(0, w) * eye_m)
            return [d.real, d.imag]

        k, w = findroot(eqs, (mpf(guess[0]), mpf(guess[1])))
        return k, abs(w)


def series(laws, a, bs, dcs, k, v_steps, at, times, mass=None, eta=0, *, mu0=mpf("0.6"), v_ref=1, dps=30):
    """μ, V, θ at ``times`` from steady sliding at v_steps[0]; the load velocity becomes v_steps[i]
    at at[i − 1]. Returns a list of (μ, V, [θ_i])."""
    with mp.workdps(dps):
        a, eta, k, v_ref, mu0 = mpf(a), mpf(eta), mpf(k), mpf(v_ref), mpf(mu0)
        bs, dcs = [mpf(b) for b in bs], [mpf(d) for d in dcs]
        mass = None if mass is None else mpf(mass)
        v0 = mpf(v_steps[0])
        y = [v0] + [C[law] * dc / v0 for law, dc in zip(laws, dcs)] + ([] if mass is None else [mpf(0)])
        edges = [mpf(0)] + [mpf(x) for x in at] + [mp.inf]
        out = []
        for i, vl in enumerate(v_steps):
            f = rhs(laws, a, bs, dcs, k, mpf(vl), mass, eta)
            F = odefun(lambda t, yy, f=f: f(yy), edges[i], y)
            for t in times:
                t = mpf(t)
                if edges[i] <= t < edges[i + 1] or (i == len(v_steps) - 1 and t >= edges[i]):
                    yt = F(t)
                    v, ths = yt[0], yt[1:1 + len(laws)]
                    mu = mu0 + a * log(v / v_ref) + sum(b * log(v_ref * th / (C[law] * dc))
                                                        for b, th, law, dc in zip(bs, ths, laws, dcs))
                    out.append((mu, v, list(ths)))
            if edges[i + 1] != mp.inf:
                y = F(edges[i + 1])
        return out


def _crossings(F, f, t0, h, t_end, want_up_v, v_lp):
    """Scan F on [t0, t_end] by h: the first upward V = V_lp crossing after t0 + h, and the extrema of V
    (V̇ = f(y)[0] changing sign) before it."""
    from mpmath import findroot as _fr
    ta, ya = t0, F(t0)
    da = f(ya)[0]
    extrema = []
    while ta < t_end:
        tb = ta + h
        yb = F(tb)
        db = f(yb)[0]
        if (da > 0) != (db > 0):
            tm = _fr(lambda s: f(F(s))[0], (ta, tb), solver="anderson")
            extrema.append(F(tm)[0])
        if ya[0] < v_lp <= yb[0] and tb > t0 + 2 * h:
            tc = _fr(lambda s: F(s)[0] - v_lp, (ta, tb), solver="anderson")
            return tc, F(tc), extrema
        ta, ya, da = tb, yb, db
    raise RuntimeError("no return to the section")


def cycle(law, a, b, dc, k, v_lp, eta=0, *, theta_guess, h=mpf("0.05"), dps=25, t_end=200):
    """The attracting cycle of the quasi-static slider (one state variable) by secant shooting on the
    section V = V_lp (upward): dict(period, ln_v_max, ln_v_min, closure)."""
    with mp.workdps(dps):
        a, b, dc, k, v_lp, eta = (mpf(x) for x in (a, b, dc, k, v_lp, eta))
        f = rhs([law], a, [b], [dc], k, v_lp, None, eta)

        def ret(theta):
            F = odefun(lambda t, y: f(y), 0, [v_lp, theta])
            tc, yc, ext = _crossings(F, f, mpf(0), h, t_end, True, v_lp)
            return tc, yc[1], ext

        x0, x1 = mpf(theta_guess), mpf(theta_guess) * (1 + mpf(10) ** -4)
        r0 = ret(x0)[1] - x0
        for _ in range(30):
            r1 = ret(x1)[1] - x1
            if abs(r1) < mpf(10) ** (-dps + 5) * x1:
                break
            x0, x1, r0 = x1, x1 - r1 * (x1 - x0) / (r1 - r0), r1
        period, theta_back, ext = ret(x1)
        return dict(period=period, ln_v_max=log(max(ext)), ln_v_min=log(min(ext)),
                    closure=abs(theta_back - x1) / x1)


def rs_chain_first_event(law, x0, y0, *, a, b, dc, k, ell, v_lp, eta, v_th, periodic, dps=25, h=None,
                         t_end=1000):
    """The first event of the quasi-dynamic rate-state chain (docs/rs-chain.md, M = 0, η > 0) from
    ln V_j = x0[j], ln θ_j = y0[j] (doubles, as the engine starts): per block
    (a/V_j + η) V̇_j = k(V_lp − V_j) + ℓ²k(V_{j+1} − 2V_j + V_{j−1}) − b θ̇_j/θ_j, integrated by odefun
    in (V, θ, P) with P = Σ δ_j. dict(t_start, hypocentre, n_blocks, potency, duration, max_velocity)."""
    with mp.workdps(dps):
        n = len(x0)
        a, b, dc, k, l2, v_lp, eta, v_th = (mpf(x) for x in (a, b, dc, k, mpf(ell) ** 2, v_lp, eta, v_th))
        h = mpf(h) if h is not None else mpf("0.01")

        def nbr(v, j, d):
            i = j + d
            if 0 <= i < n:
                return v[i]
            return v[i % n] if periodic else v[j]

        def f(y):
            v, th = y[:n], y[n:2 * n]
            out_v, out_t = [], []
            for j in range(n):
                td = _theta_dot(law, v[j], th[j], dc)
                lap = nbr(v, j, 1) - 2 * v[j] + nbr(v, j, -1)
                out_v.append((k * (v_lp - v[j]) + l2 * k * lap - b * td / th[j]) / (a / v[j] + eta))
                out_t.append(td)
            return out_v + out_t + [sum(v)]

        y = [exp(mpf(x)) for x in x0] + [exp(mpf(x)) for x in y0] + [mpf(0)]
        F = odefun(lambda t, yy: f(yy), 0, y)
        ta, ya = mpf(0), y
        above, t_start, hyp, members, vmax, p0 = set(), None, None, set(), mpf(0), None
        acc_a = f(ya)[:n]
        while ta < t_end:
            tb = ta + h
            yb = F(tb)
            acc_b = f(yb)[:n]
            events = []
            for j in range(n):
                if (ya[j] < v_th) != (yb[j] < v_th):
                    tc = findroot(lambda s, j=j: F(s)[j] - v_th, (ta, tb), solver="anderson")
                    events.append((tc, j, yb[j] >= v_th))
                if acc_a[j] > 0 >= acc_b[j]:
                    tm = findroot(lambda s, j=j: f(F(s))[j], (ta, tb), solver="anderson")
                    vm = F(tm)[j]
                    if vm > v_th:
                        vmax = max(vmax, vm)
            for tc, j, up in sorted(events):
                if up:
                    if not above and t_start is None:
                        t_start, hyp, p0 = tc, j, F(tc)[2 * n]
                    above.add(j)
                    members.add(j)
                else:
                    above.discard(j)
                    if not above and t_start is not None:
                        return dict(t_start=t_start, hypocentre=hyp, n_blocks=len(members),
                                    potency=F(tc)[2 * n] - p0, duration=tc - t_start, max_velocity=vmax)
            ta, ya, acc_a = tb, yb, acc_b
        raise RuntimeError("no event before t_end")
