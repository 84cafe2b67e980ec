"""An independent high-precision reference for the rate-and-state chain: Taylor series in mpmath.

No heyoka, and not the engine's variables: the velocities V_j and states θ_j themselves (and, with
inertia, the net forces z_j = M V̇_j), with the potency P = Σδ_j, from the force balance

    quasi-dynamic:  V̇_j = V_j [k(V_lp − V_j) + ℓ²k ΔV_j − b θ̇_j/θ_j] / (a + η V_j)
    inertial:       V̇_j = z_j/M,  ż_j = k(V_lp − V_j) + ℓ²k ΔV_j − (a/V_j + η) V̇_j − b θ̇_j/θ_j
    state:          θ̇_j = 1 − Vθ/Dc (aging), −(Vθ/Dc) ln(Vθ/Dc) (slip), 1 − (Vθ/(2Dc))² (PRZ)

(the same physics as _system.py, written again from the equations in docs/rs-chain.md), with Taylor
coefficients from the recurrences of automatic differentiation (products, quotients, logarithms:
Jorba & Zou, Exp. Math. 14, 99 (2005)). Events are found on each step's polynomial: V_j − v_th is
sampled at 16 points of the step and every sign change refined by ``mpmath.findroot`` (bisection);
velocity maxima are the roots of V̇_j where it changes from + to −. Slow (minutes for a few events):
the tests read its output from tests/data/rs_chain_reference.json, made by
tests/data/make_rs_chain_reference.py.
"""

from __future__ import annotations

import mpmath as mp

__all__ = ["reference_catalog"]


def _conv(f, g, n):
    return mp.fsum(f[i] * g[n - i] for i in range(n + 1))


def _div(num, den, out, n):
    """Coefficient n of out = num/den (out[0..n−1] known)."""
    return (num[n] - mp.fsum(den[i] * out[n - i] for i in range(1, n + 1))) / den[0]


def _lap(v, j, n_blocks, periodic):
    if n_blocks == 1:
        return mp.mpf(0)
    if n_blocks == 2 and periodic:
        return 2 * (v[1 - j] - v[j])
    left = v[j - 1] if j > 0 else (v[n_blocks - 1] if periodic else None)
    right = v[j + 1] if j < n_blocks - 1 else (v[0] if periodic else None)
    return mp.fsum(w - v[j] for w in (left, right) if w is not None)


def _coefficients(p, V, TH, Z, order):
    """Taylor coefficients of V_j, θ_j (, z_j) and P from their values V, TH, Z at the current point."""
    n_b = len(V)
    inertial = Z is not None
    V = [[v] for v in V]
    TH = [[t] for t in TH]
    Z = [[z] for z in Z] if inertial else None
    P = [mp.mpf(0)]
    PR = [[] for _ in range(n_b)]     # Vθ/Dc
    LG = [[] for _ in range(n_b)]     # ln(Vθ/Dc)  (slip)
    G = [[] for _ in range(n_b)]      # θ̇
    R = [[] for _ in range(n_b)]      # θ̇/θ
    DEN = [[] for _ in range(n_b)]    # a + ηV
    NUM = [[] for _ in range(n_b)]    # quasi-dynamic: k(V_lp − V) + ℓ²kΔV − bθ̇/θ
    W = [[] for _ in range(n_b)]      # quasi-dynamic: V̇/V = NUM/DEN
    U = [[] for _ in range(n_b)]      # inertial: V̇/V
    for n in range(order):
        vn = [V[j][n] for j in range(n_b)]
        for j in range(n_b):
            PR[j].append(_conv(V[j], TH[j], n) / p["dc"])
            one = 1 if n == 0 else 0
            if p["law"] == "aging":
                g = one - PR[j][n]
            elif p["law"] == "slip":
                if n == 0:
                    LG[j].append(mp.log(PR[j][0]))
                else:
                    LG[j].append((n * PR[j][n] - mp.fsum(i * LG[j][i] * PR[j][n - i] for i in range(1, n)))
                                 / (n * PR[j][0]))
                g = -_conv(PR[j], LG[j], n)
            else:
                g = one - _conv(PR[j], PR[j], n) / 4
            G[j].append(g)
            R[j].append(_div(G[j], TH[j], R[j], n))
            drive = p["k"] * ((p["v_lp"] if n == 0 else 0) - vn[j]) + p["ell2"] * p["k"] * _lap(vn, j, n_b,
                                                                                                 p["periodic"])
            DEN[j].append((p["a"] if n == 0 else 0) + p["eta"] * vn[j])
            if not inertial:
                num = drive - p["b"] * R[j][n]
                NUM[j].append(num)
                W[j].append(_div(NUM[j], DEN[j], W[j], n))
                V[j].append(_conv(V[j], W[j], n) / (n + 1))
            else:
                vdot = [Z[j][i] / p["mass"] for i in range(n + 1)]
                U[j].append(_div(vdot, V[j], U[j], n))
                # (a/V + η) V̇ = a U + η V̇
                zdot = drive - p["a"] * U[j][n] - p["eta"] * vdot[n] - p["b"] * R[j][n]
                V[j].append(vdot[n] / (n + 1))
                Z[j].append(zdot / (n + 1))
            TH[j].append(G[j][n] / (n + 1))
        P.append(mp.fsum(vn) / (n + 1))
    return V, TH, Z, P


def _horner(c, h):
    s = c[-1]
    for x in reversed(c[:-1]):
        s = s * h + x
    return s


def _dhorner(c, h):
    s = mp.mpf(0)
    for i in range(len(c) - 1, 0, -1):
        s = s * h + i * c[i]
    return s


def _roots(fn, h, samples=16):
    """Sign changes of fn on [0, h] (sampled), each refined: [(s, sign of fn just after)]."""
    out = []
    grid = [h * i / samples for i in range(samples + 1)]
    vals = [fn(s) for s in grid]
    for s0, s1, f0, f1 in zip(grid, grid[1:], vals, vals[1:]):
        if f0 == 0 or (f0 < 0) == (f1 < 0):
            continue
        root = mp.findroot(fn, (s0, s1), solver="anderson")
        if not (s0 <= root <= s1):
            root = mp.findroot(fn, (s0, s1), solver="illinois")
        out.append((root, 1 if f1 > 0 else -1))
    return out


def reference_catalog(*, n, law, a, b, dc, k, ell, v_lp, mass, eta, v_th, periodic, x0, y0, events,
                      dps=40, order=30, tol_digits=34, safety=0.5, max_steps=200_000) -> dict:
    """The first ``events`` events from V_j = e^{x0_j}, θ_j = e^{y0_j} (z_j = 0): catalog fields as mpf lists."""
    with mp.workdps(dps):
        p = {"law": law, "a": mp.mpf(a), "b": mp.mpf(b), "dc": mp.mpf(dc), "k": mp.mpf(k),
             "ell2": mp.mpf(ell) ** 2, "v_lp": mp.mpf(v_lp), "mass": mp.mpf(mass), "eta": mp.mpf(eta),
             "periodic": bool(periodic)}
        inertial = mass > 0
        vth = mp.mpf(v_th)
        V = [mp.exp(mp.mpf(x)) for x in x0]
        TH = [mp.exp(mp.mpf(y)) for y in y0]
        Z = [mp.mpf(0)] * n if inertial else None
        P = mp.mpf(0)
        t = mp.mpf(0)
        tol = mp.mpf(10) ** (-tol_digits)
        above = [False] * n
        cat = {"t_start": [], "hypocentre": [], "n_blocks": [], "potency": [], "duration": [], "max_velocity": []}
        cur = None
        steps = 0
        while len(cat["t_start"]) < events and steps < max_steps:
            cv, ct, cz, cp = _coefficients(p, V, TH, Z, order)
            series = [*cv, *ct, *(cz or [])]
            h = mp.inf
            for c in series:
                scale = max(abs(c[0]), 1)
                for m in (order - 1, order):
                    if c[m] != 0:
                        h = min(h, (tol * scale / abs(c[m])) ** (mp.mpf(1) / m))
            h = safety * h
            found = []
            for j in range(n):
                for s, sign in _roots(lambda s, c=cv[j]: _horner(c, s) - vth, h):
                    found.append((s, 0 if sign > 0 else 2, j))
                for s, sign in _roots(lambda s, c=cv[j]: _dhorner(c, s), h):
                    if sign < 0:
                        found.append((s, 1, j))
            for s, kind, j in sorted(found):
                if len(cat["t_start"]) >= events:
                    break
                ps = t + s
                if kind == 0 and not above[j]:
                    if not any(above):
                        cur = {"t": ps, "j": j, "blocks": {j}, "p0": P + _horner(cp, s), "vmax": vth}
                    above[j] = True
                    cur["blocks"].add(j)
                elif kind == 2 and above[j]:
                    above[j] = False
                    if not any(above):
                        cat["t_start"].append(cur["t"])
                        cat["hypocentre"].append(cur["j"])
                        cat["n_blocks"].append(len(cur["blocks"]))
                        cat["potency"].append(P + _horner(cp, s) - cur["p0"])
                        cat["duration"].append(ps - cur["t"])
                        cat["max_velocity"].append(cur["vmax"])
                        cur = None
                elif kind == 1 and above[j]:
                    cur["vmax"] = max(cur["vmax"], _horner(cv[j], s))
            V = [_horner(c, h) for c in cv]
            TH = [_horner(c, h) for c in ct]
            Z = [_horner(c, h) for c in cz] if inertial else None
            P = P + _horner(cp, h)
            t = t + h
            steps += 1
        cat["steps"] = steps
        return cat
