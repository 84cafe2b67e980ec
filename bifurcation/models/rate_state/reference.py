"""An independent high-precision reference for the quasi-static slider: Taylor series in mpmath.

No heyoka, and not the engine's variables: this integrates rsfmodel's own formulation, the friction μ
and the states θ_i themselves,

    dμ/dt = k (V_lp − V),   V = V* exp[(μ − μ0 − Σ_i b_i ln(V* θ_i/(c_i Dc_i))) / a],
    dθ_i/dt = the law's rate (laws.py, in θ rather than ln θ),

with Taylor coefficients from the classical recurrences of automatic differentiation (Moore 1966;
Jorba & Zou, Exp. Math. 14, 99 (2005)): for a product (fg)_n = Σ_j f_j g_{n−j}; for e = exp f,
n e_n = Σ_{j=1}^{n} j f_j e_{n−j}; for l = ln f, n f_0 l_n = n f_n − Σ_{j=1}^{n−1} j l_j f_{n−j}; and
y_{n+1} = F(y)_n/(n + 1). Steps of order ``order`` at ``dps`` digits, the step size from the last two
coefficients (h = ρ·(tol/|y_N|)^{1/N}), clipped to land exactly on every output time and load step.

Slow (seconds per case): the tests read its output from a golden file made by
tests/data/make_rate_state_reference.py.
"""

from __future__ import annotations

import mpmath as mp

from .laws import resolve_state_law
from .spec import LoadHistory, SliderSpec

__all__ = ["reference_run"]


def _mpf(x):
    """``x`` in mpmath: a decimal given as text (``engine._exact``) from its text, exactly."""
    from ...engine._exact import decimal_text

    text = decimal_text(x)
    return mp.mpf(text) if text is not None else mp.mpf(x)


def _coefficients(spec: SliderSpec, v_lp, mu, thetas, order: int):
    """Taylor coefficients [μ_n], [[θ_i,n]] at the current point, up to ``order``."""
    a, k, mu0, vref = _mpf(spec.a), _mpf(spec.k), _mpf(spec.mu0), _mpf(spec.v_ref)
    laws = [resolve_state_law(n).name for n in spec.state_law]
    n_s = len(laws)
    b = [_mpf(x) for x in spec.b]
    dc = [_mpf(x) for x in spec.dc]
    scale = [vref / (_mpf(resolve_state_law(n).steady_factor) * d) for n, d in zip(laws, dc)]
    M = [mu]
    TH = [[t] for t in thetas]
    LT = [[] for _ in range(n_s)]          # ln(V* θ_i/(c_i Dc_i))
    ARG, V = [], []                        # (μ − μ0 − Σ b LT)/a and V = V* e^ARG
    P = [[] for _ in range(n_s)]           # V θ_i / Dc_i
    LP = [[] for _ in range(n_s)]          # ln P (slip law)
    Q2 = [[] for _ in range(n_s)]          # (P/2)² (PRZ)

    def conv(f, g, n, lo=0):
        return mp.fsum(f[j] * g[n - j] for j in range(lo, n + 1))

    for n in range(order):
        for i in range(n_s):
            f = TH[i]
            if n == 0:
                LT[i].append(mp.log(scale[i] * f[0]))
            else:
                s = mp.fsum(j * LT[i][j] * f[n - j] for j in range(1, n))
                LT[i].append((n * f[n] - s) / (n * f[0]))
        arg = (M[n] - (mu0 if n == 0 else 0) - mp.fsum(bi * LT[i][n] for i, bi in enumerate(b))) / a
        ARG.append(arg)
        if n == 0:
            V.append(vref * mp.exp(arg))
        else:
            V.append(mp.fsum(j * ARG[j] * V[n - j] for j in range(1, n + 1)) / n)
        M.append(k * ((v_lp if n == 0 else 0) - V[n]) / (n + 1))
        for i, law in enumerate(laws):
            P[i].append(conv(V, TH[i], n) / dc[i])
            if law == "aging":
                rate = (1 if n == 0 else 0) - P[i][n]
            elif law == "slip":
                if n == 0:
                    LP[i].append(mp.log(P[i][0]))
                else:
                    s = mp.fsum(j * LP[i][j] * P[i][n - j] for j in range(1, n))
                    LP[i].append((n * P[i][n] - s) / (n * P[i][0]))
                rate = -conv(P[i], LP[i], n)
            else:  # prz
                Q2[i].append(conv(P[i], P[i], n) / 4)
                rate = (1 if n == 0 else 0) - Q2[i][n]
            TH[i].append(rate / (n + 1))
    return M, TH


def _horner(c, h):
    s = c[-1]
    for x in reversed(c[:-1]):
        s = s * h + x
    return s


def reference_run(spec: SliderSpec, history: LoadHistory, times, *, dps: int = 40, order: int = 36,
                  tol_digits: int = 36, safety: float = 0.5):
    """μ, θ_i and V at ``times`` (mpf values), quasi-static, from the steady state at V = V*·… .

    The start is rsfmodel's: μ(t0) = μ0 + a ln(V0/V*) with V0 the first load-point velocity and θ_i at
    steady state there. Returns a dict of lists of mpf: ``mu``, ``theta`` (per variable), ``v``, and
    ``steps``.
    """
    if spec.inertial:
        raise ValueError("the mpmath reference is for the quasi-static slider")
    with mp.workdps(dps):
        tol = _mpf(10) ** (-tol_digits)
        v0 = _mpf(history.velocities[0])
        mu = _mpf(spec.mu0) + _mpf(spec.a) * mp.log(v0 / _mpf(spec.v_ref))
        thetas = [_mpf(resolve_state_law(n).steady_factor) * _mpf(d) / v0
                  for n, d in zip(spec.state_law, spec.dc)]
        t = _mpf(history.times[0])
        stops = sorted({_mpf(x) for x in times} | {_mpf(x) for x in history.times[1:]})
        stops = [s for s in stops if s >= t]
        want = {_mpf(x) for x in times}
        out = {"mu": [], "theta": [[] for _ in thetas], "v": [], "t": []}
        steps = 0
        vref, a = _mpf(spec.v_ref), _mpf(spec.a)

        def record():
            lt = mp.fsum(_mpf(b) * mp.log(vref * th / (resolve_state_law(n).steady_factor * _mpf(d)))
                         for b, th, n, d in zip(spec.b, thetas, spec.state_law, spec.dc))
            out["t"].append(t)
            out["mu"].append(mu)
            out["v"].append(vref * mp.exp((mu - _mpf(spec.mu0) - lt) / a))
            for i, th in enumerate(thetas):
                out["theta"][i].append(th)

        for stop in stops:
            v_lp = _mpf(history.velocity_at(float(t)))
            while t < stop:
                M, TH = _coefficients(spec, v_lp, mu, thetas, order)
                h = min((tol / abs(c[-1])) ** (_mpf(1) / order) if c[-1] != 0 else mp.inf
                        for c in [M, *TH])
                h = min(safety * h, stop - t)
                mu = _horner(M, h)
                thetas = [_horner(c, h) for c in TH]
                t = stop if stop - t == h else t + h
                steps += 1
            if stop in want:
                record()
        out["steps"] = steps
        return out
