"""Independent mpmath shooting for slowly attracting cycles of the rate-and-state slider (multipliers
0.95–0.9999, next to a Hopf point), with and without mass and radiation damping (tests/test_rscycle.py,
tests/data/make_rscycle_sweep.py).

Written without the package. With mass it extends tests/_indep3_rate_state.py (its own Taylor
recurrences in (V, θ, F = M V̇), section F = 0 with F decreasing: the maximum of V); without mass it
adds the quasi-static slider of docs/rate-state.md ("The model") in (V, θ):

    θ' = 1 − Vθ/Dc (aging) | −(Vθ/Dc) ln(Vθ/Dc) (slip),
    V' = V g,   g = [k(V_lp − V) − b θ'/θ] / (a + ηV)

(k(V_lp − V) − ηV̇ = a V̇/V + b θ̇/θ), by Taylor recurrences of the same kind (Cauchy products and
series division, order 30, step from the last two coefficients), section g = 0 with g decreasing (the
maximum of V); V_min at g = 0 with g increasing.

``cycle`` solves P(x) = x on that section by Newton with a finite-difference Jacobian (relative step
1e-20 at 45 digits) from a given start, until the step is below 1e-(dps − 10); it returns the period,
ln(V_max/V_lp), ln(V_min/V_lp), the closure |P(x) − x| relative, and the largest |eigenvalue| of the
return map's Jacobian (the nontrivial Floquet multiplier; the massless map on (V, θ) has rank one, its
other eigenvalue is 0).
"""

from __future__ import annotations

from mpmath import mp, mpf

import _indep3_rate_state as ind3


def _series_qs(law, p, V0, th0, order):
    """Taylor coefficients of V, θ (order + 1) and g (order) of the quasi-static slider."""
    a, b, dc, k, vlp, eta = p
    cw = 1 / dc
    V, T = [V0], [th0]
    w, L, r, N, D, g, Vg = [], [], [], [], [], [], []
    for n in range(order):
        w.append(cw * sum(V[j] * T[n - j] for j in range(n + 1)))
        if law == "aging":
            td = (1 if n == 0 else 0) - w[n]
        else:
            if n == 0:
                L.append(mp.log(w[0]))
            else:
                L.append((n * w[n] - sum(j * L[j] * w[n - j] for j in range(1, n))) / (n * w[0]))
            td = -sum(w[j] * L[n - j] for j in range(n + 1))
        r.append((td - sum(T[j] * r[n - j] for j in range(1, n + 1))) / T[0])          # θ'/θ
        N.append(k * ((vlp if n == 0 else 0) - V[n]) - b * r[n])
        D.append((a if n == 0 else 0) + eta * V[n])
        g.append((N[n] - sum(D[j] * g[n - j] for j in range(1, n + 1))) / D[0])        # N / D
        Vg.append(sum(V[j] * g[n - j] for j in range(n + 1)))
        V.append(Vg[n] / (n + 1))
        T.append(td / (n + 1))
    return V, T, g


def _step(cs_scales, order):
    eps = mpf(10) ** (-(mp.dps - 4))
    h = None
    for cs, scale in cs_scales:
        for n in (order - 1, order):
            if n < len(cs) and cs[n] != 0:
                hn = (eps * scale / abs(cs[n])) ** (mpf(1) / n)
                h = hn if h is None else min(h, hn)
    return h * mpf("0.5")


def _deriv_at(c, s):
    return ind3._ev([(n + 1) * c[n + 1] for n in range(len(c) - 1)], s)


def return_map_qs(law, p, V0, th0, order=30, max_steps=200000):
    """From (V0, θ0) to the next g = 0 with g decreasing (V_max): (V, θ, T, V_min); the start need not lie
    on the section (the map then has rank one)."""
    t, V, th = mpf(0), mpf(V0), mpf(th0)
    vmin, lo = None, mpf(10) ** -9
    for _ in range(max_steps):
        Vs, Ts, gs = _series_qs(law, p, V, th, order)
        h = _step(((Vs, abs(V)), (Ts, abs(th)), (gs, max(abs(gs[0]), p[3] * p[4] * mpf(10) ** -3 / p[0]))), order)
        s = ind3._root(gs, h, lo)
        lo = mpf(0)
        if s is None:
            V, th, t = ind3._ev(Vs, h), ind3._ev(Ts, h), t + h
            continue
        V, th, t = ind3._ev(Vs, s), ind3._ev(Ts, s), t + s
        if _deriv_at(gs, s) > 0:
            vmin, lo = V, mpf(10) ** -9      # the minimum of V; search on past this root
            continue
        return V, th, t, vmin
    raise RuntimeError("no return to the section")


def to_section_qs(law, p, V, th):
    """The first V_max (g = 0, g decreasing) after (V, θ)."""
    V1, th1, _, _ = return_map_qs(law, p, V, th)
    return [V1, th1]


def cycle(law, a, b, dc, k, v_lp, mass, eta, start, dps=45, newton=30):
    """The cycle through the neighbourhood of ``start`` = (V, θ[, F]) (any point near it; not necessarily on
    the section). ``mass`` 0 or None: quasi-static."""
    with mp.workdps(dps):
        inertial = bool(mass)
        if inertial:
            p = tuple(mpf(x) for x in (a, b, dc, k, v_lp, mass, eta))
            x = ind3._to_section(law, p, *(mpf(v) for v in start))
            pmap = lambda V, th: ind3.return_map(law, p, V, th)
        else:
            p = tuple(mpf(x) for x in (a, b, dc, k, v_lp, eta))
            x = to_section_qs(law, p, *(mpf(v) for v in start[:2]))
            pmap = lambda V, th: return_map_qs(law, p, V, th)
        converged = False
        for _ in range(newton):
            V1, th1, T, _vmin = pmap(*x)
            r = [V1 - x[0], th1 - x[1]]
            J = mp.matrix(2, 2)
            for j in range(2):
                y = list(x)
                d = x[j] * mpf(10) ** -20
                y[j] += d
                Vj, thj, _, _ = pmap(*y)
                J[0, j] = (Vj - y[0] - r[0]) / d
                J[1, j] = (thj - y[1] - r[1]) / d
            dx = mp.lu_solve(J, mp.matrix(r))
            x = [x[0] - dx[0], x[1] - dx[1]]
            if max(abs(dx[0] / x[0]), abs(dx[1] / x[1])) < mpf(10) ** -(dps - 10):
                converged = True
                break
        mults = [abs(z) for z in mp.eig(J + mp.eye(2), left=False, right=False)]
        V1, th1, T, vmin = pmap(*x)
        closure = max(abs(V1 - x[0]) / x[0], abs(th1 - x[1]) / x[1])
        return {"period": T, "ln_v_max": mp.log(x[0] / p[4]), "ln_v_min": mp.log(vmin / p[4]),
                "closure": closure, "multiplier_max": max(mults), "converged": converged}


def jacobian_eigs_qs(law, a, b, dc, k, v_lp, eta):
    """Eigenvalues of the quasi-static (V, θ) Jacobian at steady sliding (V_lp, Dc/V_lp)."""
    p = tuple(mpf(x) for x in (a, b, dc, k, v_lp, eta))

    def f(V, th):
        w = V * th / p[2]
        td = 1 - w if law == "aging" else -w * mp.log(w)
        return [V * (p[3] * (p[4] - V) - p[1] * td / th) / (p[0] + p[5] * V), td]

    x0 = [p[4], p[2] / p[4]]
    J = mp.matrix(2, 2)
    for i in range(2):
        for j in range(2):
            J[i, j] = mp.diff(lambda s, i=i, j=j: f(*[x0[m] + (s if m == j else 0) for m in range(2)])[i], 0)
    return sorted(mp.eig(J, left=False, right=False), key=lambda z: -mp.re(z))


def eigs(law, a, b, dc, k, v_lp, mass, eta):
    if mass:
        return ind3.jacobian_eigs(law, a, b, dc, k, v_lp, mass, eta)
    return jacobian_eigs_qs(law, a, b, dc, k, v_lp, eta)
