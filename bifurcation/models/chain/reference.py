"""Independent high-precision reference for small chains, in mpmath (no heyoka, no engine code).

The chain of docs/chain.md integrated in the *physical* variables U_j, V_j, t (no scaling, no offsets,
no windows: every block of the chain in one system) by a Taylor-series method of order ``order`` at
``dps`` digits. The stress is recomputed from its definition, σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j
+ νt, so the precision trap of small ν is met with digits, not with the engine's algebra.

Each step: Taylor coefficients of every block by the recursions of the ODE (g = 1 − Φ by series
arithmetic: x/(1+x) by series division, 1 − e^{−x} by the series exponential, the pieces of Eq. (12)
as polynomials), a step size from the last coefficients, then the events inside the step: a stop
(V_j back to 0), a start (σ_j up to 1), a switch (V_j/ν_f across a breakpoint), each the first sign
change on a grid of sub-steps refined by bisection of the step polynomial to the working precision.
Velocity maxima are roots of the acceleration polynomial. Quiescent phases are jumped as
t + (1 − max σ)/ν.

Friction drop ``sigma`` = σ > 0 (docs/chain.md, "Friction drop"): a slipping block feels
Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)), so the series of g_σ = σ + (1 − σ) g(y) is built from the series of
y = x/(1 − σ) (exact in mpmath), and a breakpoint b of the law is crossed at V = (1 − σ) b ν_f. The
static threshold stays 1; a block at rest never moves backwards.

Slow (about a second per event for N = 8): tests use it live on small cases, and
``tests/chain_golden_gen.py`` uses it to write the golden catalogs of ``tests/data/``.
"""

from __future__ import annotations

import mpmath

__all__ = ["LAWS", "reference_chain"]

#: law name → breakpoints (in x = V/ν_f) of its pieces
LAWS = {"carlson-langer": (), "exponential": (), "piecewise-linear": (1,)}


def _drop_series(law: str, piece: int, x: list, k: int, g: list, aux: list) -> None:
    """Append g_k, the k-th Taylor coefficient of g(x(t)), given x_0..x_k and g_0..g_{k−1}."""
    if law == "carlson-langer":          # g (1 + x) = x
        s = x[k] - mpmath.fsum(x[i] * g[k - i] for i in range(1, k + 1))
        g.append(s / (1 + x[0]))
    elif law == "exponential":           # e = exp(−x), g = 1 − e
        if k == 0:
            aux.append(mpmath.exp(-x[0]))
        else:
            aux.append(-mpmath.fsum(i * x[i] * aux[k - i] for i in range(1, k + 1)) / k)
        g.append(1 - aux[0] if k == 0 else -aux[k])
    elif law == "piecewise-linear":      # Eq. (12): g = x on [0, 1), 1 above
        g.append(x[k] if piece == 0 else (mpmath.mpf(1) if k == 0 else mpmath.mpf(0)))
    else:
        raise ValueError(f"reference_chain has no series for law {law!r}; use one of {sorted(LAWS)}")


def _poly(c: list, s):
    """Σ c_k s^k by Horner's rule."""
    acc = c[-1]
    for a in reversed(c[:-1]):
        acc = acc * s + a
    return acc


def _first_root(c: list, h, want, subdivisions: int, bits: int):
    """First s in (0, h] where the polynomial c changes sign as ``want`` says ("up": − → +, "down":
    + → −); None if there is none on the grid. Bracketed by bisection, then polished by Newton
    steps kept inside the bracket (quadratic convergence to the working precision)."""
    prev_s, prev_v = mpmath.mpf(0), c[0]
    neg_inside = (lambda v: v < 0) if want == "up" else (lambda v: v > 0)
    for i in range(1, subdivisions + 1):
        s = h * i / subdivisions
        v = _poly(c, s)
        hit = (prev_v < 0 <= v) if want == "up" else (prev_v > 0 >= v)
        if hit:
            lo, hi = prev_s, s
            for _ in range(12):
                mid = (lo + hi) / 2
                if neg_inside(_poly(c, mid)):
                    lo = mid
                else:
                    hi = mid
            dc = [k * c[k] for k in range(1, len(c))]
            x = (lo + hi) / 2
            eps = h * mpmath.mpf(2) ** (-bits)
            for _ in range(60):
                f, df = _poly(c, x), _poly(dc, x)
                step = f / df if df != 0 else mpmath.mpf(0)
                xn = x - step
                if not lo <= xn <= hi:   # Newton left the bracket: bisect once instead
                    if neg_inside(f):
                        lo = x
                    else:
                        hi = x
                    xn = (lo + hi) / 2
                if abs(xn - x) <= eps:
                    return xn
                x = xn
            return x
        prev_s, prev_v = s, v
    return None


def reference_chain(law: str, *, n: int, ell, nu, nu_f, u0, ends: str = "free", events: int,
                    dps: int = 36, order: int = 36, t_max: float = 1e4, sigma=0) -> dict:
    """The first ``events`` events of the chain (docs/chain.md) in mpmath at ``dps`` digits.

    Returns a dict of lists: ``t_start``, ``hypocentre``, ``n_blocks``, ``potency``, ``duration``,
    ``max_velocity`` (mpmath numbers / ints) and the final ``u`` and ``t``. ``nu``, ``nu_f``, ``ell``
    and ``u0`` are taken as the exact binary numbers the engine sees when they are floats; so is the
    friction drop ``sigma`` (0 ≤ σ < 1). Tested up to σ = 0.2; at σ = 0.98 (exponential law, N = 5) runs at
    30 and 45 digits differed by 4e-6 in potency, while the engine's double and quad runs agreed to 1e-15:
    its step control is not converged there, so it is no reference for drops that large.
    """
    if law not in LAWS:
        raise ValueError(f"reference_chain has no series for law {law!r}; use one of {sorted(LAWS)}")
    with mpmath.workdps(dps):
        mpf = mpmath.mpf
        nu, nu_f, ell = mpf(nu), mpf(nu_f), mpf(ell)
        l2 = ell * ell
        drop = mpf(sigma)
        if not 0 <= drop < 1:
            raise ValueError(f"reference_chain needs 0 <= sigma < 1, got {sigma!r}")
        c_drop = 1 - drop
        # breakpoints in x = V/ν_f: the law's b at y = x/(1 − σ) = b
        breaks = [mpf(b) * c_drop for b in LAWS[law]]
        tol = mpf(10) ** (-(dps - 4))
        bits = int(dps * 3.33) + 8
        U = [mpf(x) for x in u0]
        V = [mpf(0)] * n
        t = mpf(0)
        slipping = [False] * n
        piece = [0] * n

        def nbrs(j):
            if ends == "periodic":
                return (j - 1) % n, (j + 1) % n
            return max(j - 1, 0), min(j + 1, n - 1)

        def stress(j, Uc, tc):
            a, b = nbrs(j)
            return l2 * (Uc[a] - 2 * Uc[j] + Uc[b]) - Uc[j] + nu * tc

        out = {k: [] for k in ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")}
        for _ in range(events):
            sig = [stress(j, U, t) for j in range(n)]
            h0 = max(range(n), key=lambda j: sig[j])
            t = t + (1 - sig[h0]) / nu
            t0, Ustart = t, list(U)
            slipping[h0], piece[h0] = True, 0
            touched, vmax = {h0}, mpf(0)
            while any(slipping):
                # Taylor coefficients, order by order
                cu = [[U[j]] for j in range(n)]
                cv = [[V[j]] for j in range(n)]
                cg = [[] for _ in range(n)]
                aux = [[] for _ in range(n)]
                cf = [[] for _ in range(n)]      # acceleration coefficients
                for k in range(order):
                    for j in range(n):
                        if not slipping[j]:
                            continue
                        a, b = nbrs(j)
                        sk = l2 * (cu[a][k] - 2 * cu[j][k] + cu[b][k]) - cu[j][k]
                        sk += nu * t if k == 0 else (nu if k == 1 else 0)
                        x = [cv[j][i] / (nu_f * c_drop) for i in range(k + 1)]   # y = x/(1 − σ)
                        _drop_series(law, piece[j], x, k, cg[j], aux[j])
                        gk = c_drop * cg[j][k] + (drop if k == 0 else 0)          # g_σ = σ + (1 − σ) g(y)
                        f = sk - (1 if k == 0 else 0) + gk
                        cf[j].append(f)
                    for j in range(n):
                        if slipping[j]:
                            cu[j].append(cv[j][k] / (k + 1))
                            cv[j].append(cf[j][k] / (k + 1))
                        else:
                            cu[j].append(mpf(0))
                            cv[j].append(mpf(0))
                # step size from the last two coefficients of the slipping blocks
                h = mpf(2)
                for j in range(n):
                    if slipping[j]:
                        for c in (cu[j], cv[j]):
                            for kk in (order - 1, order):
                                if c[kk] != 0:
                                    h = min(h, (tol / abs(c[kk])) ** (mpf(1) / kk))
                # events in (0, h]: (time, kind, block)
                found = []
                for j in range(n):
                    if slipping[j]:
                        r = _first_root(cv[j], h, "down", 4, bits)
                        if r is not None:
                            found.append((r, "stop", j))
                        hi_b = breaks[piece[j]] if piece[j] < len(breaks) else None
                        lo_b = breaks[piece[j] - 1] if piece[j] > 0 else None
                        if hi_b is not None:
                            r = _first_root([c - (hi_b * nu_f if i == 0 else 0) for i, c in enumerate(cv[j])],
                                            h, "up", 4, bits)
                            if r is not None:
                                found.append((r, "up", j))
                        if lo_b is not None:
                            r = _first_root([c - (lo_b * nu_f if i == 0 else 0) for i, c in enumerate(cv[j])],
                                            h, "down", 4, bits)
                            if r is not None:
                                found.append((r, "down", j))
                    else:
                        a, b = nbrs(j)
                        cs = [l2 * (cu[a][i] - 2 * cu[j][i] + cu[b][i]) - cu[j][i] for i in range(order + 1)]
                        cs[0] += nu * t - 1
                        cs[1] += nu
                        r = _first_root(cs, h, "up", 4, bits)
                        if r is not None:
                            found.append((r, "start", j))
                s_end = min(found)[0] if found else h
                # velocity maxima before s_end
                for j in range(n):
                    if slipping[j]:
                        r = _first_root(cf[j], s_end, "down", 4, bits)
                        if r is not None:
                            vmax = max(vmax, _poly(cv[j], r))
                        vmax = max(vmax, _poly(cv[j], s_end))
                U = [_poly(cu[j], s_end) for j in range(n)]
                V = [_poly(cv[j], s_end) for j in range(n)]
                t = t + s_end
                if t - t0 > t_max:
                    raise RuntimeError(f"reference event did not end before t_max = {t_max}")
                if found:
                    s_ev = min(found)[0]
                    for r, kind, j in found:
                        if r != s_ev:
                            continue
                        if kind == "stop":
                            slipping[j], V[j] = False, mpf(0)
                        elif kind == "start":
                            slipping[j], V[j], piece[j] = True, mpf(0), 0
                            touched.add(j)
                        elif kind == "up":
                            piece[j] += 1
                        else:
                            piece[j] -= 1
            out["t_start"].append(t0)
            out["hypocentre"].append(h0)
            out["n_blocks"].append(len(touched))
            out["potency"].append(mpmath.fsum(U[j] - Ustart[j] for j in range(n)))
            out["duration"].append(t - t0)
            out["max_velocity"].append(vmax)
        out["u"], out["t"] = U, t
        return out
