"""Independent mpmath reference for the Burridge–Knopoff chain (tests/test_indep_chain.py).

The model exactly as docs/chain.md states it ("The model", "Friction drop σ"):
    σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j + νt   (free: U_0 ≡ U_1, U_{N+1} ≡ U_N; or periodic),
slipping: U̇_j = V_j, V̇_j = σ_j − Φ_σ(V_j/ν_f), Φ_σ(x) = (1 − σ_f)Φ(x/(1 − σ_f)); a stuck block starts
when σ_j reaches 1; a slipping block sticks when V_j returns to 0. Events: from a failure of the
all-stuck chain until all are stuck; hypocentre, n_blocks, potency Σ ΔU_j, duration, max V at the
exact maxima.

Written without the package's code, in physical variables U_j, V_j and absolute time t (the engine
uses per-segment scaled variables and a stress state), at 40 digits with tests/_indep_taylor.py:
only slipping blocks are integrated, stuck ones are constants; every stop, start, kink crossing and
velocity maximum is a root of its function's Taylor polynomial on the step.
"""

from __future__ import annotations

from mpmath import mp, mpf

import _indep_taylor as tt


def _friction(law, sig):
    """Φ_σ(x) per smooth piece (node functions) and the breakpoints of x."""
    s1 = 1 - sig
    if law == "carlson-langer":
        return [lambda x: s1 * s1 / (s1 + x)], []
    if law == "exponential":
        return [lambda x: s1 * tt.exp(-x / s1)], []
    if law == "piecewise-linear":
        return [lambda x: s1 - x, lambda x: 0 * x], [s1]
    raise ValueError(law)


def chain_catalog(law, n, ell, nu, nu_f, u0, events, ends="free", sigma=0, dps=40, order=32):
    with mp.workdps(dps):
        tol = mpf(10) ** -(dps - 4)
        ell2, nu, nu_f, sig = mpf(ell) ** 2, mpf(nu), mpf(nu_f), mpf(sigma)
        pieces, breaks = _friction(law, sig)
        periodic = ends == "periodic"
        U = [mpf(u) for u in u0]
        V = [mpf(0)] * n
        piece = [0] * n
        t = mpf(0)

        def nb(j):
            if periodic:
                return (j - 1) % n, (j + 1) % n
            return max(j - 1, 0), min(j + 1, n - 1)

        def stress(u, tt_):
            out = []
            for j in range(n):
                a, b = nb(j)
                out.append(ell2 * (u[a] - 2 * u[j] + u[b]) - u[j] + nu * tt_) if n > 1 else \
                    out.append(-u[j] + nu * tt_)
            return out

        cat = []
        for _ in range(events):
            # quiescent jump: every block stuck, σ grows as νt
            s = stress(U, t)
            h = max(range(n), key=lambda j: s[j])
            t = t + (1 - s[h]) / nu
            t_start, u_start = t, list(U)
            slipping = {h}
            touched = {h}
            fresh = {h}           # blocks whose V = 0 at the step start: skip the root at 0
            skip = set()          # (kind, j) at zero at the step start
            vmax = mpf(0)
            sysm, key = None, None
            for _step in range(10 ** 6):
                if not slipping:
                    break
                order_sl = sorted(slipping)
                k2 = (tuple(order_sl), tuple(piece[j] for j in order_sl))
                if k2 != key:
                    key = k2
                    sysm = _build(n, order_sl, piece, pieces, breaks, U, ell2, nu, nu_f, nb, periodic)
                pos = {j: i for i, j in enumerate(order_sl)}
                x0 = []
                for j in order_sl:
                    x0 += [U[j], V[j]]
                sysm.stuck_u(U)
                xs, gs, _ = sysm.series(t, x0, order)
                hstep = tt.step_size(xs, order, tol)
                hits = []
                for gi, (kind, j) in enumerate(sysm.labels):
                    z = (kind, j) in skip or (kind in ("stop", "max") and j in fresh)
                    r = tt.first_root(gs[gi], hstep, skip0=z)
                    if r is None:
                        continue
                    if kind == "max" and tt.peval(tt.pderiv(gs[gi]), r) >= 0:
                        continue
                    hits.append((r, kind, j, gi))
                skip, fresh = set(), set()
                if hits:
                    r = min(p[0] for p in hits)
                    hits = [p for p in hits if p[0] == r]
                else:
                    r = hstep
                vals = [tt.peval(c, r) for c in xs]
                for j in order_sl:
                    U[j], V[j] = vals[2 * pos[j]], vals[2 * pos[j] + 1]
                t = t + r
                for _r, kind, j, gi in hits:
                    if kind == "stop":
                        V[j] = mpf(0)
                        slipping.discard(j)
                    elif kind == "start":
                        slipping.add(j)
                        touched.add(j)
                        V[j] = mpf(0)
                        fresh.add(j)
                        piece[j] = 0
                    elif kind == "switch":
                        piece[j] = 1 if tt.peval(tt.pderiv(gs[gi]), r) > 0 else 0
                        skip.add(("switch", j))
                    elif kind == "max":
                        vmax = max(vmax, V[j])
                        skip.add(("max", j))
            else:
                raise RuntimeError("event did not end")
            cat.append({"t_start": t_start, "hypocentre": h, "n_blocks": len(touched),
                        "potency": sum(U[j] - u_start[j] for j in range(n)),
                        "duration": t - t_start, "max_velocity": vmax})
        return cat


def _build(n, order_sl, piece, pieces, breaks, U, ell2, nu, nu_f, nb, periodic):
    """The system of the slipping blocks; stuck blocks' U are constants (refreshed per step)."""
    consts = {j: tt.Const(U[j]) for j in range(n) if j not in order_sl}
    labels = []

    def u_of(x, j):
        return x[2 * order_sl.index(j)] if j in order_sl else consts[j]

    def sig(t, x, j):
        if n == 1:
            return nu * t - u_of(x, j)
        a, b = nb(j)
        return ell2 * (u_of(x, a) - 2 * u_of(x, j) + u_of(x, b)) - u_of(x, j) + nu * t

    def rhs(t, x):
        out = []
        for i, j in enumerate(order_sl):
            v = x[2 * i + 1]
            out += [v, sig(t, x, j) - pieces[piece[j]](v / nu_f)]
        return out

    def events(t, x):
        f = rhs(t, x)
        g = []
        labels.clear()
        for i, j in enumerate(order_sl):
            v = x[2 * i + 1]
            g.append(v / nu_f)
            labels.append(("stop", j))
            for b in breaks:
                g.append(v / nu_f - b)
                labels.append(("switch", j))
            g.append(f[2 * i + 1])
            labels.append(("max", j))
        for j in range(n):
            if j not in order_sl:
                g.append(sig(t, x, j) - 1)
                labels.append(("start", j))
        return g

    sysm = tt.System(2 * len(order_sl), rhs, events)
    sysm.labels = list(labels)

    def stuck_u(Unow):
        for j, c in consts.items():
            c.v = Unow[j]

    sysm.stuck_u = stuck_u
    return sysm
