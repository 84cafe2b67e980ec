"""Independent mpmath reference for the Burridge–Knopoff chain, written for tests/test_indep4_chain.py.

The model as docs/chain.md states it ("The model", "Friction drop σ"), in physical variables:

    σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j + νt + δ_j   (free: a missing neighbour is the block itself;
                                                            periodic: j ± 1 mod N; N = 1: σ = −U + νt),
    slipping: U̇_j = V_j, V̇_j = σ_j − Φ_σ(V_j/ν_f),  Φ_σ(x) = (1 − σ_f) Φ(x/(1 − σ_f)),

a stuck block starts when σ_j reaches 1, a slipping one sticks when V_j returns to 0. δ_j is a constant
per event: the reference integrates each event from the *double* state (σ_j, U_j, t) that the engine is
given (``CompiledChain.restore``), so δ_j = σ_j − (its formula) is that state's rounding (≤ 1e-16) and the
reference and the engine solve the same problem; the difference measures only the engine's integration.

Nothing from the package: own Taylor recurrences (series of 1/(a + x), of exp, products), own step
rule, own event location (sign changes on 24 sample points of each step's polynomial, then Newton
safeguarded by bisection, in mpmath). Order P = 40 at 40 digits by default; the step is the radius
estimated from the last two coefficients times ε^{1/P}, ε = 10^{4 − dps}, and for the fading laws
(Φ = s1 e^f) at most the step over which f changes by 2 (first version without it: 5e-4 off in potency on a
lone block of exp(−x − 4x²) at x = 6.6, where e^f ~ 1e-76 is below 40 digits, found by the engines and a
60-digit rerun).
"""

from __future__ import annotations

from mpmath import mp, mpf

from _indep4_taylor import deriv as _deriv, horner as _horner, refine as _refine   # the same author's series helpers

LAWS = ("carlson-langer", "piecewise-linear", "exponential", "exp(-x-4*x^2)",
        "piecewise(1 - x, 0.5, 0.75 - x/2, 1.5, 0)")


class _Law:
    """Φ_σ as Taylor recurrences, piece by piece. ``breaks``: V/ν_f values (already times 1 − σ_f)."""

    def __init__(self, law, s1):
        self.law, self.s1 = law, s1
        if law == "piecewise-linear":
            self.breaks = [s1]
        elif law.startswith("piecewise(1 - x, 0.5"):
            self.breaks = [s1 / 2, s1 * mpf("1.5")]
        else:
            self.breaks = []

    def piece_of(self, x):
        return sum(1 for b in self.breaks if x >= b)

    def coeff(self, x, y, aux, k, piece):
        """y_k of Φ_σ(x(t)) given x_0..x_k and y_0..y_{k−1} (aux: the law's own helper series)."""
        s1, law = self.s1, self.law
        if law == "carlson-langer":            # y (s1 + x) = s1²
            acc = s1 * s1 if k == 0 else mpf(0)
            for i in range(1, k + 1):
                acc -= x[i] * y[k - i]
            return acc / (s1 + x[0])
        if law in ("exponential", "exp(-x-4*x^2)"):   # y = s1 e^f
            c = mpf(4) if law != "exponential" else mpf(0)
            xs = [x[i] / s1 for i in range(k + 1)]
            fk = -xs[k] - c * sum(xs[i] * xs[k - i] for i in range(k + 1))
            aux.append(fk)                     # aux holds f_0..f_k
            if k == 0:
                return s1 * mp.exp(fk)
            return sum(i * aux[i] * y[k - i] for i in range(1, k + 1)) / k
        if law == "piecewise-linear":
            if piece == 0:
                return s1 - x[0] if k == 0 else -x[k]
            return mpf(0)
        # three pieces: 1 − x, 0.75 − x/2, 0 in x/s1 (so s1 − X, 0.75 s1 − X/2, 0 in X = V/ν_f)
        if piece == 0:
            return s1 - x[0] if k == 0 else -x[k]
        if piece == 1:
            return mpf("0.75") * s1 - x[0] / 2 if k == 0 else -x[k] / 2
        return mpf(0)


def _first_root(c, h, skip0, samples=24):
    """First root of the polynomial c in (0, h] (None if no sign change is seen on the samples)."""
    f0 = _horner(c, mpf(0))
    if f0 != 0 and not skip0:
        # no root on [0, h] if |c_0| exceeds every other term's largest size there
        hk, bound = mpf(1), mpf(0)
        for a in c[1:]:
            hk *= h
            bound += abs(a) * hk
        if bound < abs(f0):
            return None
    tiny = mpf(10) ** (-mp.dps + 6) * max(1, max(abs(a) for a in c[:3]))
    prev_r, prev_f = mpf(0), f0
    if skip0 or abs(f0) <= tiny:
        prev_f = None            # the root at 0 is the one just handled: sign from the next sample
    for s in range(1, samples + 1):
        r = h * s / samples
        fr = _horner(c, r)
        if prev_f is None:
            if fr != 0:
                prev_r, prev_f = r, fr
            continue
        if fr == 0:
            return r
        if (fr > 0) != (prev_f > 0):
            return _refine(c, prev_r, r, prev_f)
        prev_r, prev_f = r, fr
    if prev_f is None:
        # sign unknown over the whole step: look in (0, first sample] from a nonzero point near 0
        return None
    return None


def event(law, n, ell, nu, nu_f, ends, sigma_f, s0, u0, t0, *, dps=40, order=40, max_steps=200000):
    """One event from the between-events state (σ_j, U_j, t) given as doubles (or strings).

    Returns dict(t_start, hypocentre, n_blocks, potency, duration, max_velocity, steps, sigma, u, t): the
    catalog entry (mpf) and the state after it (mpf; σ_j at the end time, with the event's δ_j)."""
    with mp.workdps(dps):
        P = order
        eps = mpf(10) ** (4 - dps)
        l2, nu, nu_f, s1 = mpf(ell) ** 2, mpf(nu), mpf(nu_f), 1 - mpf(sigma_f)
        lw = _Law(law, s1)
        U = [mpf(u) for u in u0]
        t = mpf(t0)
        periodic = ends == "periodic"

        def nbrs(j):
            if n == 1:
                return j, j
            if periodic:
                return (j - 1) % n, (j + 1) % n
            return (j - 1 if j > 0 else j), (j + 1 if j < n - 1 else j)

        def formula(Us, tt):
            out = []
            for j in range(n):
                a, b = nbrs(j)
                out.append(l2 * (Us[a] - 2 * Us[j] + Us[b]) - Us[j] + nu * tt)
            return out

        delta = [mpf(s) - f for s, f in zip(s0, formula(U, t))]
        # quiescent: σ_j + ν(t' − t); the largest reaches 1 first (ties: the lowest index)
        sig = [mpf(s) for s in s0]
        h0 = max(range(n), key=lambda j: (sig[j], -j))
        t = t + (1 - sig[h0]) / nu
        t_start, U_start = t, list(U)
        V = [mpf(0)] * n
        slipping, touched = {h0}, {h0}
        piece = [0] * n
        fresh = {h0}            # V = 0 at the step start: its stop root at 0 is skipped
        just = set()            # (kind, j) roots at the step start
        vmax = mpf(0)
        steps = 0
        while slipping:
            steps += 1
            if steps > max_steps:
                raise RuntimeError("event did not end")
            sl = sorted(slipping)
            # Taylor series of U_j, V_j (stuck: constants) and σ_j
            Us = {j: [U[j]] for j in range(n)}
            Vs = {j: [V[j]] for j in sl}
            Ps = {j: [] for j in sl}
            aux = {j: [] for j in sl}
            Ss = {j: [] for j in range(n)}
            for k in range(P + 1):
                for j in range(n):
                    a, b = nbrs(j)
                    s = l2 * (Us[a][k] - 2 * Us[j][k] + Us[b][k]) - Us[j][k]
                    if k == 0:
                        s += nu * t + delta[j]
                    elif k == 1:
                        s += nu
                    Ss[j].append(s)
                if k == P:
                    break
                for j in sl:
                    x = [v / nu_f for v in Vs[j]]
                    Ps[j].append(lw.coeff(x, Ps[j], aux[j], k, piece[j]))
                for j in range(n):
                    if j in slipping:
                        Us[j].append(Vs[j][k] / (k + 1))
                        Vs[j].append((Ss[j][k] - Ps[j][k]) / (k + 1))
                    else:
                        Us[j].append(mpf(0))
            # step: radius from the last two coefficients of every slipping U, V
            rho = None
            for j in sl:
                for c in (Us[j], Vs[j]):
                    scale = max(1, abs(c[0]))
                    for kk in (P - 1, P):
                        if c[kk] != 0:
                            r = (scale / abs(c[kk])) ** (mpf(1) / kk)
                            rho = r if rho is None else min(rho, r)
            hstep = (rho if rho is not None else mpf(1)) * eps ** (mpf(1) / P)
            # fading friction (Φ = s1 e^f): the radius above cannot see a factor e^f below rounding at the
            # step start that comes back before its end, so each step changes f by at most 2 (bounded by
            # Σ|f_k| h^k; 2^40/40! = 1e-36): e^f grows by ≤ e² per step and is always resolved where it matters
            # (or the step keeps f below −K, K = dps·ln 10 + 20: e^f then stays below the rounding of 1)
            K = dps * mp.log(10) + 20
            for j in sl:
                fser = aux[j]
                if fser:
                    while True:
                        bnd = sum(abs(fser[kk]) * hstep ** kk for kk in range(1, len(fser)))
                        if bnd <= 2 or fser[0] + bnd <= -K:
                            break
                        hstep /= 2
            # event functions on the step
            hits = []
            for j in sl:
                r = _first_root(Vs[j], hstep, j in fresh)
                if r is not None:
                    hits.append((r, "stop", j))
                for bi, bk in enumerate(lw.breaks):
                    r = _first_root([Vs[j][0] / nu_f - bk] + [c / nu_f for c in Vs[j][1:]], hstep,
                                    ("switch", j) in just)
                    if r is not None:
                        hits.append((r, "switch", j))
                dv = _deriv(Vs[j])
                r = _first_root(dv, hstep, ("max", j) in just or j in fresh)
                if r is not None and _horner(_deriv(dv), r) < 0:
                    hits.append((r, "max", j))
            for j in range(n):
                if j not in slipping:
                    r = _first_root([Ss[j][0] - 1] + Ss[j][1:], hstep, False)
                    if r is not None:
                        hits.append((r, "start", j))
            fresh, just = set(), set()
            if hits:
                r = min(p[0] for p in hits)
                hits = [p for p in hits if p[0] <= r * (1 + mpf(10) ** (-dps + 8))]
            else:
                r = hstep
            for j in sl:
                U[j] = _horner(Us[j], r)
                V[j] = _horner(Vs[j], r)
                vmax = max(vmax, V[j])
            t = t + r
            for _r, kind, j in hits:
                if kind == "stop":
                    V[j] = mpf(0)
                    slipping.discard(j)
                elif kind == "start":
                    slipping.add(j)
                    touched.add(j)
                    fresh.add(j)
                    V[j] = mpf(0)
                    piece[j] = 0
                elif kind == "switch":
                    piece[j] = _switch(lw, piece[j], _horner(_deriv(Vs[j]), r))
                    just.add(("switch", j))
                elif kind == "max":
                    just.add(("max", j))
        sig_end = [f + d for f, d in zip(formula(U, t), delta)]
        return {"t_start": t_start, "hypocentre": h0, "n_blocks": len(touched),
                "potency": sum(U[j] - U_start[j] for j in range(n)), "duration": t - t_start,
                "max_velocity": vmax, "steps": steps, "sigma": sig_end, "u": U, "t": t}


def _switch(lw, piece, dvdt):
    """The piece after crossing a breakpoint: up if V increases there, down otherwise."""
    return min(piece + 1, len(lw.breaks)) if dvdt > 0 else max(piece - 1, 0)


def catalog(law, n, ell, nu, nu_f, ends, sigma_f, u0, events, *, dps=40, order=40):
    """``events`` events from U = u0 at t = 0, each started from the previous end state rounded to
    doubles (what ``CompiledChain.restore`` is given). Returns the list of (pre-event double state,
    event dict)."""
    with mp.workdps(dps):
        U = [mpf(float(u)) for u in u0]
        l2 = mpf(ell) ** 2
        s = []
        for j in range(n):
            if n == 1:
                a = b = j
            elif ends == "periodic":
                a, b = (j - 1) % n, (j + 1) % n
            else:
                a, b = (j - 1 if j > 0 else j), (j + 1 if j < n - 1 else j)
            s.append(l2 * (U[a] - 2 * U[j] + U[b]) - U[j])
        state = ([float(x) for x in s], [float(x) for x in U], 0.0)
    out = []
    for _ in range(events):
        e = event(law, n, ell, nu, nu_f, ends, sigma_f, *state, dps=dps, order=order)
        out.append((state, e))
        state = ([float(x) for x in e["sigma"]], [float(x) for x in e["u"]], float(e["t"]))
    return out
