"""Independent mpmath reference for the rate-and-state chain (tests/test_indep_rs_chain.py).

The model as docs/rs-chain.md states it: block j, slip δ_j, F_j = k(δ_lp − δ_j) + ℓ²k(δ_{j+1} − 2δ_j + δ_{j−1})
(free ends: one neighbour; periodic), μ_j = a ln V_j + b ln(θ_j/(c Dc)) (μ0 drops out),
quasi-dynamic F_j − ηV_j = μ_j, i.e. (a + ηV_j) V̇_j/V_j = k(V_lp − V_j) + ℓ²k(ΔV)_j − b θ̇_j/θ_j;
inertial M V̇_j = F_j − ηV_j − μ_j with Ḟ_j = k(V_lp − V_j) + ℓ²k(ΔV)_j. Events: a block slips while
V_j > v_th; an event is a connected time with at least one block slipping (t_start, hypocentre,
n_blocks, potency ΔΣδ_j, duration, the largest V_j at an exact maximum above v_th).
Start (docs/rs-chain.md, "Runs"): ln V_j = ln V_lp + A r_j, r = default_rng(seed).uniform(−1, 1, N),
θ_j = c Dc/V_lp, net force 0.

Written without the package's code, in V_j, θ_j (and F_j), P = Σδ_j (the engine uses ln V, ln θ and
the net force), at 40 digits with tests/_indep_taylor.py.
"""

from __future__ import annotations

import numpy as np
from mpmath import mp, mpf

import _indep_taylor as tt
from _indep_rate_state import C, theta_dot


class _NodeLib:
    log = staticmethod(tt.log)


def rs_chain_catalog(*, n, law, a, b, dc, k, ell, v_lp, mass, eta, v_th, periodic, amplitude, seed, events,
                     dps=40, order=30):
    with mp.workdps(dps):
        tol = mpf(10) ** -(dps - 4)
        a, b, dc, k, l2k, vlp, mass, eta, vth = (mpf(q) for q in (a, b, dc, k, mpf(ell) ** 2 * mpf(k), v_lp,
                                                                   mass, eta, v_th))
        r = np.random.default_rng(int(seed)).uniform(-1.0, 1.0, n)
        x0 = [float(np.log(float(v_lp))) + amplitude * float(q) for q in r]   # as the documented start
        V0 = [mp.exp(mpf(x)) for x in x0]
        th0 = [C[law] * dc / vlp] * n

        def nbs(j):
            if periodic:
                return [(j - 1) % n, (j + 1) % n]
            return [q for q in (j - 1, j + 1) if 0 <= q < n]

        def lap(V, j):
            return sum((V[q] - V[j] for q in nbs(j)), 0 * V[j])

        inertial = mass > 0

        def rhs(t, x):
            if inertial:
                F, V, TH = x[:n], x[n:2 * n], x[2 * n:3 * n]
            else:
                V, TH = x[:n], x[n:2 * n]
            thd = [theta_dot(law, V[j], TH[j], dc, _NodeLib) for j in range(n)]
            out = []
            if inertial:
                mu = [a * tt.log(V[j]) + b * tt.log(TH[j] / (C[law] * dc)) for j in range(n)]
                out += [k * (vlp - V[j]) + l2k * lap(V, j) for j in range(n)]
                out += [(F[j] - eta * V[j] - mu[j]) / mass for j in range(n)]
            else:
                out += [V[j] * (k * (vlp - V[j]) + l2k * lap(V, j) - b * thd[j] / TH[j]) / (a + eta * V[j])
                        for j in range(n)]
            out += thd
            out.append(sum(V[1:], V[0]))
            return out

        iv = n if inertial else 0

        def evs(t, x):
            f = rhs(t, x)
            return [x[iv + j] / vth - 1 for j in range(n)] + [f[iv + j] / vth for j in range(n)]

        sysm = tt.System((3 if inertial else 2) * n + 1, rhs, evs)
        if inertial:
            F0 = [a * mp.log(V0[j]) + b * mp.log(th0[j] / (C[law] * dc)) + eta * V0[j] for j in range(n)]
            x = F0 + V0 + th0 + [mpf(0)]
        else:
            x = V0 + th0 + [mpf(0)]
        t = mpf(0)
        above = [x[iv + j] > vth for j in range(n)]
        assert not any(above)
        cat, cur, skip = [], None, set()
        for _ in range(10 ** 7):
            xs, gs, _ = sysm.series(t, x, order)
            h = tt.step_size(xs, order, tol)
            hits = []
            for gi in range(2 * n):
                rr = tt.first_root(gs[gi], h, skip0=gi in skip)
                if rr is not None:
                    hits.append((rr, gi))
            skip = set()
            if hits:
                rr = min(p[0] for p in hits)
                hits = [p for p in hits if p[0] == rr]
            else:
                rr = h
            x = [tt.peval(c, rr) for c in xs]
            t += rr
            for _r, gi in hits:
                skip.add(gi)
                j = gi % n
                if gi < n:                          # a crossing of v_th
                    up = tt.peval(tt.pderiv(gs[gi]), rr) > 0
                    above[j] = up
                    if up and cur is None:
                        cur = {"t_start": t, "hypocentre": j, "blocks": {j}, "p0": x[-1] - 0,
                               "max_velocity": mpf(0), "gap": mp.inf}
                    elif up:
                        if j not in cur["blocks"]:
                            cur["gap"] = min(cur["gap"], t - cur["t_start"])
                        cur["blocks"].add(j)
                    if not any(above) and cur is not None:
                        cat.append({"t_start": cur["t_start"], "hypocentre": cur["hypocentre"],
                                    "n_blocks": len(cur["blocks"]), "potency": x[-1] - cur["p0"],
                                    "duration": t - cur["t_start"], "max_velocity": cur["max_velocity"],
                                    "gap": cur["gap"]})
                        cur = None
                        if len(cat) == events:
                            return cat
                elif above[j] and tt.peval(tt.pderiv(gs[gi]), rr) < 0:   # a maximum above v_th
                    cur["max_velocity"] = max(cur["max_velocity"], x[iv + j])
        raise RuntimeError("too many steps")
