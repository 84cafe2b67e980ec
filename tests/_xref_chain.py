"""A second independent reference for Burridge–Knopoff chains (no code of the package or of
tests/_indep_chain.py): the model of docs/chain.md, "The model" and "Friction drop", integrated by
mpmath.odefun (mpmath's adaptive Taylor method) on the whole chain in absolute time,

    σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j + νt,   free (U_0 = U_1, U_{N+1} = U_N) or periodic ends,
    slipping: U̇_j = V_j, V̇_j = σ_j − 1 + g_σ(V_j/ν_f),  g_σ(x) = σ + (1 − σ) g(x/(1 − σ)),  g = 1 − Φ,
    stuck (V_j = 0) while σ_j < 1; starts when σ_j reaches 1; a slipping block sticks when V_j returns to 0.

One odefun per segment between discrete changes (a start, a stop, a switch of a piece of a
piecewise-linear law), each started from the exact state at the change. Events are sign changes on
a grid of step h, refined by mpmath.findroot on the dense output. Quiescent phases are jumped:
t += (1 − max σ)/ν.
"""

from __future__ import annotations

from mpmath import mp, mpf, odefun, findroot

from _xref_block import LINEAR, SMOOTH


def _g_pieces(law):
    """[(x_left, g)] on x = V/((1 − σ)ν_f): one piece for an analytic law, the linear pieces otherwise."""
    if law in SMOOTH:
        return [(mpf(0), SMOOTH[law])]
    return [(mpf(a), (lambda p, q: (lambda x: p + q * x))(mpf(p), mpf(q))) for a, p, q in LINEAR[law]]


def chain_events(law, u0, *, ell, nu, nu_f, sigma=0, ends="free", events=5, dps=30, h=None):
    """The first ``events`` events: list of dict(t_start, hypocentre, n_blocks, potency, duration,
    max_velocity) as mpf / int."""
    with mp.workdps(dps):
        n = len(u0)
        ell2, nu, nu_f, sigma = mpf(ell) ** 2, mpf(nu), mpf(nu_f), mpf(sigma)
        pieces = _g_pieces(law)
        breaks = [a for a, _ in pieces[1:]]
        scale = (1 - sigma) * nu_f               # x = V / scale
        h = mpf(h) if h is not None else min(mpf(1) / 40, scale / 8)

        def nb(U, j, d):
            k = j + d
            if 0 <= k < n:
                return U[k]
            return U[k % n] if ends == "periodic" else U[j]

        def stress(t, U, j):
            return ell2 * (nb(U, j, 1) - 2 * U[j] + nb(U, j, -1)) - U[j] + nu * t

        def accel(t, U, V, j, piece):
            g = pieces[piece][1]
            return stress(t, U, j) - 1 + sigma + (1 - sigma) * g(V[j] / scale)

        U = [mpf(x) for x in u0]
        V = [mpf(0)] * n
        t = mpf(0)
        out = []
        while len(out) < events:
            s = [stress(t, U, j) for j in range(n)]
            hyp = max(range(n), key=lambda j: s[j])
            t = t + (1 - s[hyp]) / nu
            t_start, u_start = t, list(U)
            slipping = {hyp}
            piece = [0] * n
            moved = {hyp}
            vmax = mpf(0)
            while slipping:
                sl = sorted(slipping)
                pc = list(piece)

                def rhs(tt, y, sl=sl, pc=pc):
                    Uy, Vy = y[:n], y[n:]
                    dU = [Vy[j] if j in sl else mpf(0) for j in range(n)]
                    dV = [accel(tt, Uy, Vy, j, pc[j]) if j in sl else mpf(0) for j in range(n)]
                    return dU + dV

                t0 = t
                F = odefun(rhs, t0, U + V)
                ta, ya = t0, U + V
                prev_acc = {j: accel(t0, U, V, j, piece[j]) for j in sl}
                while True:
                    tb = ta + h
                    yb = F(tb)
                    Ub, Vb = yb[:n], yb[n:]
                    cands = []
                    for j in range(n):
                        if j in slipping:
                            if Vb[j] <= 0 and (ta > t0 or Vb[j] < 0):
                                cands.append((findroot(lambda x, j=j: F(x)[n + j], (ta, tb), solver="anderson"),
                                              "stop", j))
                            k = piece[j]
                            if k + 1 < len(pieces) and Vb[j] / scale >= breaks[k]:
                                b = breaks[k]
                                cands.append((findroot(lambda x, j=j, b=b: F(x)[n + j] / scale - b, (ta, tb),
                                                       solver="anderson"), "up", j))
                            if k > 0 and Vb[j] / scale <= breaks[k - 1]:
                                b = breaks[k - 1]
                                cands.append((findroot(lambda x, j=j, b=b: F(x)[n + j] / scale - b, (ta, tb),
                                                       solver="anderson"), "down", j))
                            ab = accel(tb, Ub, Vb, j, piece[j])
                            if prev_acc[j] is not None and prev_acc[j] > 0 >= ab:
                                tm = findroot(lambda x, j=j: accel(x, F(x)[:n], F(x)[n:], j, piece[j]), (ta, tb),
                                              solver="anderson")
                                if tm <= tb:
                                    vmax = max(vmax, F(tm)[n + j])
                            prev_acc[j] = ab
                        elif stress(tb, Ub, j) >= 1:
                            cands.append((findroot(lambda x, j=j: stress(x, F(x)[:n], j) - 1, (ta, tb),
                                                   solver="anderson"), "start", j))
                    if cands:
                        te, kind, j = min(cands, key=lambda c: c[0])
                        ye = F(te)
                        U, V = list(ye[:n]), list(ye[n:])
                        for i in slipping:
                            vmax = max(vmax, V[i])
                        t = te
                        if kind == "stop":
                            V[j] = mpf(0)
                            slipping.discard(j)
                            piece[j] = 0
                        elif kind == "start":
                            slipping.add(j)
                            moved.add(j)
                        else:
                            piece[j] += 1 if kind == "up" else -1
                            V[j] = breaks[piece[j] - 1 if kind == "up" else piece[j]] * scale
                        break
                    ta = tb
                    for i in slipping:
                        vmax = max(vmax, Vb[i])
            out.append(dict(t_start=t_start, hypocentre=hyp, n_blocks=len(moved),
                            potency=sum(U[j] - u_start[j] for j in range(n)), duration=t - t_start,
                            max_velocity=vmax))
        return out
