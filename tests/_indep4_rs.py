"""Helper indep4's own mpmath references for the rate-and-state chain (N = 2, 3) and the rate-and-state
slider with mass and radiation damping (tests/test_indep4_rs.py). No code of the package; the series
machinery is tests/_indep4_taylor.py.

Chain (docs/rs-chain.md, "The model"), in V_j, θ_j (and with mass z_j = M V̇_j), P = Σ δ_j:
    θ̇_j = 1 − V_jθ_j/Dc (aging) | −(V_jθ_j/Dc) ln(V_jθ_j/Dc) (slip),
    F_j' = k(V_lp − V_j) + ℓ²k(V_{j+1} − 2V_j + V_{j−1})  (free ends: one neighbour; periodic),
    M = 0:  (a + ηV_j) V̇_j / V_j = F_j' − b θ̇_j/θ_j,
    M > 0:  V̇_j = z_j/M,  ż_j = F_j' − (a + ηV_j) V̇_j/V_j − b θ̇_j/θ_j,
events as documented: a block slips while V_j > v_th; an event is a connected time with one block or more
slipping (t_start, hypocentre, n_blocks, potency ΔP, duration, max V_j at its maxima above v_th).
Start: V_j = V_lp e^{A r_j}, r = default_rng(seed).uniform(−1, 1, N), θ_j = Dc/V_lp, z_j = 0.

Slider (docs/rate-state.md, "The model"): the same with N = 1, ℓ = 0, from V(0), θ(0) given, and its
ln V extrema (V̇ = 0) in place of events.
"""

from __future__ import annotations

import numpy as np
from mpmath import mp, mpf

import _indep4_taylor as T


def _theta_dot(law, V, th, dc):
    w = V * th / dc
    if law == "aging":
        return 1 - w
    if law == "slip":
        return -(w * T.slog(w))
    raise ValueError(law)


def _system(n, law, a, b, dc, k, l2k, vlp, mass, eta, periodic):
    inertial = mass > 0

    def nbs(j):
        if n == 1:
            return []
        if periodic:
            return [(j - 1) % n, (j + 1) % n] if n > 2 else [1 - j, 1 - j]
        return [q for q in (j - 1, j + 1) if 0 <= q < n]

    def rhs(t, x):
        V, TH = x[:n], x[n:2 * n]
        Z = x[2 * n:3 * n] if inertial else None
        out_v, out_th, out_z = [], [], []
        for j in range(n):
            thd = _theta_dot(law, V[j], TH[j], dc)
            load = k * (vlp - V[j])
            for q in nbs(j):
                load = load + l2k * (V[q] - V[j])
            sfx = b * thd / TH[j]
            if inertial:
                vd = Z[j] / mass
                out_v.append(vd)
                out_z.append(load - (a + eta * V[j]) * vd / V[j] - sfx)
            else:
                out_v.append(V[j] * (load - sfx) / (a + eta * V[j]))
            out_th.append(thd)
        pd = V[0]
        for j in range(1, n):
            pd = pd + V[j]
        return out_v + out_th + out_z + [pd]

    return rhs


def rs_chain_events(*, n, law, a, b, dc, k, ell, v_lp, mass, eta, v_th, periodic, amplitude, seed, events,
                    dps=40, order=30, t_max=1e6, max_steps=400000):
    """The first ``events`` catalog entries (mpf) and every ln V_j extremum above v_th seen on the way."""
    with mp.workdps(dps):
        a, b, dc, k, vlp, mass, eta, vth = (mpf(q) for q in (a, b, dc, k, v_lp, mass, eta, v_th))
        l2k = mpf(ell) ** 2 * k
        r = np.random.default_rng(int(seed)).uniform(-1.0, 1.0, n)
        V = [mp.exp(mp.log(vlp) + mpf(float(amplitude)) * mpf(float(q))) for q in r]
        x = V + [dc / vlp] * n + ([mpf(0)] * n if mass > 0 else []) + [mpf(0)]
        rhs = _system(n, law, a, b, dc, k, l2k, vlp, mass, eta, periodic)
        t = mpf(0)
        above = [v > vth for v in V]
        cat, cur = [], None
        just = set()
        for _ in range(max_steps):
            xs, h, f = T.step(rhs, x, t, order)
            hits = []
            for j in range(n):
                r1 = T.first_root([xs[j][0] - vth] + xs[j][1:], h, ("cross", j) in just)
                if r1 is not None:
                    hits.append((r1, "cross", j))
                dv = T.deriv(xs[j])
                r2 = T.first_root(dv, h, ("max", j) in just)
                if r2 is not None and T.horner(T.deriv(dv), r2) < 0:
                    hits.append((r2, "max", j))
            just = set()
            if hits:
                rr = min(p[0] for p in hits)
                hits = [p for p in hits if p[0] == rr]
            else:
                rr = h
            x = [T.horner(c, rr) for c in xs]
            t = t + rr
            for _r, kind, j in hits:
                just.add((kind, j))
                if kind == "cross":
                    up = not above[j]
                    above[j] = up
                    if up and cur is None:
                        cur = {"t_start": t, "hypocentre": j, "blocks": {j}, "p0": x[-1], "max_velocity": mpf(0)}
                    elif up:
                        cur["blocks"].add(j)
                    if not any(above):
                        cat.append({"t_start": cur["t_start"], "hypocentre": cur["hypocentre"],
                                    "n_blocks": len(cur["blocks"]), "potency": x[-1] - cur["p0"],
                                    "duration": t - cur["t_start"], "max_velocity": cur["max_velocity"]})
                        cur = None
                        if len(cat) == events:
                            return cat
                elif kind == "max" and above[j] and cur is not None:
                    cur["max_velocity"] = max(cur["max_velocity"], x[j])
            if t > t_max:
                break
        raise RuntimeError(f"rs-chain reference: {len(cat)} of {events} events in {max_steps} steps (t = {float(t):.6g})")


def slider_extrema(*, law, a, b, dc, k, v_lp, mass, eta, v0, t_end, dps=40, order=30, max_steps=400000,
                   max_extrema=None):
    """Slider from V = v0, θ = Dc/v0 (steady state at v0, the engine's default θ0), z = 0, under
    constant V_lp: its ln V extrema (t, ln V, +1 max / −1 min) up to t_end (or the first ``max_extrema``),
    and the state [V, θ, (z,) δ] there."""
    with mp.workdps(dps):
        a, b, dc, k, vlp, mass, eta = (mpf(q) for q in (a, b, dc, k, v_lp, mass, eta))
        rhs = _system(1, law, a, b, dc, k, mpf(0), vlp, mass, eta, False)
        x = [mpf(v0), dc / mpf(v0)] + ([mpf(0)] if mass > 0 else []) + [mpf(0)]
        t = mpf(0)
        ext = []
        skip = False
        t_end = mpf(t_end)
        for _ in range(max_steps):
            xs, h, f = T.step(rhs, x, t, order)
            h = min(h, t_end - t)
            dv = T.deriv(xs[0])
            r = T.first_root(dv, h, skip)
            skip = False
            if r is not None:
                x = [T.horner(c, r) for c in xs]
                t = t + r
                ext.append((t, mp.log(x[0]), 1 if T.horner(T.deriv(dv), r) < 0 else -1))
                skip = True
                if max_extrema is not None and len(ext) == max_extrema:
                    return ext, x
                continue
            x = [T.horner(c, h) for c in xs]
            t = t + h
            if t >= t_end:
                return ext, x
        raise RuntimeError(f"slider reference: t_end not reached in {max_steps} steps (t = {float(t):.6g})")
