"""An independent high-precision reference for the quasi-static slider: Taylor series in mpmath.

No heyoka, and not the engine's variables: this integrates rsfmodel's own formulation, the spring
force τ = k(δ_lp − δ) and the states θ_i themselves,

    dτ/dt = k (V_lp − V),   τ = μ + ηV,   μ = μ0 + a ln(V/V*) + Σ_i b_i ln(V* θ_i/(c_i Dc_i)),
    dθ_i/dt = the law's rate (laws.py, in θ rather than ln θ).

Without radiation damping (η = 0) τ = μ and V = V* exp[(μ − μ0 − Σ b_i ln(…))/a]. With it, V solves
a ln(V/V*) + ηV = R := τ − μ0 − Σ b_i ln(…): V = (a/η) W((ηV*/a) e^{R/a}) (Lambert W, at each step's
start), and the Taylor coefficients L_n of L = ln(V/V*) follow from a L_n + η V_n = R_n with
V_n = L_n V_0 + (1/n) Σ_{j=1}^{n−1} j L_j V_{n−j}: L_n = (R_n − η S_n)/(a + η V_0).

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


def _velocity(a, eta, vref, r):
    """V with a ln(V/V*) + ηV = r (η ≥ 0)."""
    if eta == 0:
        return vref * mp.exp(r / a)
    # a ln(V/V*) + ηV = r  ⇔  (ηV/a) e^{ηV/a} = (ηV*/a) e^{r/a}
    return (a / eta) * mp.re(mp.lambertw((eta * vref / a) * mp.exp(r / a)))


def _coefficients(spec: SliderSpec, v_lp, mu, thetas, order: int):
    """Taylor coefficients [τ_n], [[θ_i,n]] at the current point (τ = ``mu`` + ηV), up to ``order``."""
    a, k, mu0, vref = _mpf(spec.a), _mpf(spec.k), _mpf(spec.mu0), _mpf(spec.v_ref)
    eta = _mpf(spec.damping)
    laws = [resolve_state_law(n).name for n in spec.state_law]
    n_s = len(laws)
    b = [_mpf(x) for x in spec.b]
    dc = [_mpf(x) for x in spec.dc]
    scale = [vref / (_mpf(resolve_state_law(n).steady_factor) * d) for n, d in zip(laws, dc)]
    M = [mu]
    TH = [[t] for t in thetas]
    LT = [[] for _ in range(n_s)]          # ln(V* θ_i/(c_i Dc_i))
    ARG, V = [], []                        # L = ln(V/V*) and V = V* e^L
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
        r = M[n] - (mu0 if n == 0 else 0) - mp.fsum(bi * LT[i][n] for i, bi in enumerate(b))
        if n == 0:
            V.append(_velocity(a, eta, vref, r))
            ARG.append(mp.log(V[0] / vref))
        else:
            partial = mp.fsum(j * ARG[j] * V[n - j] for j in range(1, n)) / n
            ARG.append((r - eta * partial) / (a + eta * V[0]))
            V.append(ARG[n] * V[0] + partial)
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
                  tol_digits: int = 36, safety: float = 0.5, v0=None, theta0=None):
    """μ, θ_i and V at ``times`` (mpf values), quasi-static (with radiation damping ``spec.damping``).

    The start is rsfmodel's: V0 the first load-point velocity and θ_i at steady state there, μ(t0) =
    μ0 + a ln(V0/V*) + Σ b_i ln(V* θ_i/(c_i Dc_i)) (unless ``v0``/``theta0`` are given: decimal strings
    or numbers, converted at ``dps`` digits). Returns a dict of lists of mpf: ``mu``, ``theta`` (per
    variable), ``v``, ``t``, and ``steps``.
    """
    if spec.inertial:
        raise ValueError("the mpmath reference is for the quasi-static slider")
    with mp.workdps(dps):
        tol = _mpf(10) ** (-tol_digits)
        v0 = _mpf(history.velocities[0] if v0 is None else v0)
        if theta0 is None:
            thetas = [_mpf(resolve_state_law(n).steady_factor) * _mpf(d) / v0
                      for n, d in zip(spec.state_law, spec.dc)]
        else:
            thetas = [_mpf(x) for x in theta0]
        vref = _mpf(spec.v_ref)
        lt0 = mp.fsum(_mpf(b) * mp.log(vref * th / (resolve_state_law(n).steady_factor * _mpf(d)))
                      for b, th, n, d in zip(spec.b, thetas, spec.state_law, spec.dc))
        # the integrated variable is the spring force τ = μ + ηV
        mu = _mpf(spec.mu0) + _mpf(spec.a) * mp.log(v0 / vref) + lt0 + _mpf(spec.damping) * v0
        t = _mpf(history.times[0])
        stops = sorted({_mpf(x) for x in times} | {_mpf(x) for x in history.times[1:]})
        stops = [s for s in stops if s >= t]
        want = {_mpf(x) for x in times}
        out = {"mu": [], "theta": [[] for _ in thetas], "v": [], "t": []}
        steps = 0
        a = _mpf(spec.a)

        def record():
            lt = mp.fsum(_mpf(b) * mp.log(vref * th / (resolve_state_law(n).steady_factor * _mpf(d)))
                         for b, th, n, d in zip(spec.b, thetas, spec.state_law, spec.dc))
            v = _velocity(a, _mpf(spec.damping), vref, mu - _mpf(spec.mu0) - lt)
            out["t"].append(t)
            out["mu"].append(mu - _mpf(spec.damping) * v)
            out["v"].append(v)
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


def _section_function(spec: SliderSpec, v_lp):
    """g(τ, θ) = a ln(V/V*) + ηV − a ln(V_lp/V*) − ηV_lp: zero on the section V = V_lp, increasing in V."""
    a, eta, vref, mu0 = _mpf(spec.a), _mpf(spec.damping), _mpf(spec.v_ref), _mpf(spec.mu0)
    laws = [resolve_state_law(n) for n in spec.state_law]
    offset = mu0 + a * mp.log(v_lp / vref) + eta * v_lp

    def g(tau, thetas):
        return tau - offset - mp.fsum(_mpf(b) * mp.log(vref * th / (law.steady_factor * _mpf(d)))
                                      for b, th, law, d in zip(spec.b, thetas, laws, spec.dc))
    return g


def reference_cycle(spec: SliderSpec, v_lp, theta0, *, turns: int = 2, dps: int = 40, order: int = 30,
                    tol_digits: int = 32, safety: float = 0.5, max_steps: int = 200_000) -> dict:
    """Turns of the quasi-static (damped) slider from the section V = V_lp, crossed upwards, in mpmath.

    Starts at V = V_lp with θ_i = ``theta0`` (decimal strings or numbers) and integrates τ = μ + ηV and
    θ_i by the Taylor recurrences of ``reference_run``, step size from a relative tolerance
    (h = ρ (tol·|c_0|/|c_N|)^{1/N} for each θ_i, which spans tens of decades in a stick-slip cycle, and
    for τ with |c_0| floored at 0.1). The return to the section is the root of g(t) = a ln(V/V_lp) + η(V − V_lp) on the
    step where g goes from < 0 to ≥ 0 (g from the τ and θ polynomials; ``mpmath.findroot``), the velocity
    extrema the roots of g′ (dV/dt = 0 ⇔ dg/dt = 0). Returns per turn: ``period``, ``theta`` at the
    return, ``ln_v_max``, ``ln_v_min`` (ln(V/V_lp); the start's 0 included) and ``steps``; all mpf.
    """
    if spec.inertial:
        raise ValueError("the mpmath cycle reference is for the quasi-static slider")
    with mp.workdps(dps):
        v_lp = _mpf(v_lp)
        a, eta, vref = _mpf(spec.a), _mpf(spec.damping), _mpf(spec.v_ref)
        tol = mp.mpf(10) ** (-tol_digits)
        g = _section_function(spec, v_lp)
        thetas = [_mpf(x) for x in theta0]
        out = []

        def velocity(tau, ths):
            return _velocity(a, eta, vref, g(tau, ths) + a * mp.log(v_lp / vref) + eta * v_lp)

        for _ in range(turns):
            # on the section: τ from V = V_lp and θ (g = 0)
            tau = g(mp.mpf(0), thetas) * -1
            t, steps, left = mp.mpf(0), 0, False
            top = bottom = mp.mpf(0)
            while True:
                M, TH = _coefficients(spec, v_lp, tau, thetas, order)
                scales = [(M, max(abs(M[0]), mp.mpf(1) / 10))] + [(c, abs(c[0])) for c in TH]
                h = min((tol * s / abs(c[-1])) ** (mp.mpf(1) / order) if c[-1] != 0 else mp.inf
                        for c, s in scales)
                h = safety * h

                def g_at(s):
                    return g(_horner(M, s), [_horner(c, s) for c in TH])

                dM = [j * M[j] for j in range(1, len(M))]
                dTH = [[j * c[j] for j in range(1, len(c))] for c in TH]

                def dg_at(s):
                    ths = [_horner(c, s) for c in TH]
                    return _horner(dM, s) - mp.fsum(_mpf(b) * _horner(dc_, s) / th
                                                    for b, dc_, th in zip(spec.b, dTH, ths))

                g0, g1 = g_at(0), g_at(h)
                d0, d1 = dg_at(0), dg_at(h)
                if d0 * d1 < 0 and (steps > 0 or t > 0):
                    s = mp.findroot(dg_at, (mp.mpf(0), h), solver="anderson")
                    x = mp.log(velocity(_horner(M, s), [_horner(c, s) for c in TH]) / v_lp)
                    top, bottom = max(top, x), min(bottom, x)
                if g1 < 0:
                    left = True
                if left and g0 < 0 <= g1:
                    s = mp.findroot(g_at, (mp.mpf(0), h), solver="anderson")
                    thetas = [_horner(c, s) for c in TH]
                    t += s
                    steps += 1
                    break
                tau = _horner(M, h)
                thetas = [_horner(c, h) for c in TH]
                t += h
                steps += 1
                if steps >= max_steps:
                    raise RuntimeError(f"reference_cycle: no return within {max_steps} steps (t = {t})")
            out.append({"period": t, "theta": thetas, "ln_v_max": top, "ln_v_min": bottom, "steps": steps})
        return {"turns": out}
