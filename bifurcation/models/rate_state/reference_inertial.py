"""An independent mpmath reference for cycles of the slider with mass: Taylor series, two phases.

No heyoka, not the engine's variables and not its slow-manifold series (``slow_manifold.py``). The
variables are rsfmodel's, as in ``reference.py``: the spring force τ = k(δ_lp − δ), the slip rate V
itself and the states θ_i, with

    dτ/dt = k(V_lp − V),   M dV/dt = τ − ηV − μ(V, θ),   dθ_i/dt = the law's rate (laws.py),
    μ = μ0 + a ln(V/V*) + Σ_i b_i ln(V* θ_i/(c_i Dc_i)).

**Inertial phase** (V not tiny): the Taylor coefficients of (τ, V, θ) by the recurrences of automatic
differentiation (``reference.py``'s, plus ln V and V_{n+1} = (τ − ηV − μ)_n/(M(n + 1))).

**Slow phase** (|ε| = M|dV/dt|/(a + ηV) below ``switch``, V below V_lp/e, and the fast transient below
1e-40): the state is (τ', θ) with τ' = τ − M dV/dt = μ + ηV, V from that quasi-static relation
(``reference._velocity``) and

    dτ'/dt = k(V_lp − V) − M d²V/dt².

The forcing M V̈ is found by fixed-point iteration on the step's Taylor coefficients: start from the
massless coefficients (M V̈ = 0), put F_n = M(n + 1)(n + 2)V_{n+2} of the last iterate into the
τ' recurrence, repeat until no coefficient changes by more than 1e-40 relative (each pass gains one
order of ε; the series is computed ``extra`` orders beyond the step's so that the top coefficients the
iteration cannot reach are not used). This is the slow solution of the full second-order system: the
same asymptotic series in M as the engine's, reached numerically and to convergence instead of
symbolically and truncated at a fixed order.

Switches happen at step ends where the conditions hold (not at an exact level: both phases are
accurate on both sides of it). The return to V = V_lp (upwards) and the velocity extrema are roots of
the step's polynomials (``mpmath.findroot``). ``switch`` is chosen far from the engine's (1e-3 against
1e-4) and the period is shown not to move when it changes (tests/data/make_rate_state_deep_inertial.py).
"""

from __future__ import annotations

import mpmath as mp

from .laws import resolve_state_law
from .reference import _horner, _mpf, _velocity

__all__ = ["reference_inertial_cycle"]


def _log_series(f, n, out):
    """Append the n-th coefficient of ln f to ``out`` (n f_0 l_n = n f_n − Σ_{j<n} j l_j f_{n−j})."""
    if n == 0:
        out.append(mp.log(f[0]))
    else:
        s = mp.fsum(j * out[j] * f[n - j] for j in range(1, n))
        out.append((n * f[n] - s) / (n * f[0]))


def _conv(f, g, n):
    return mp.fsum(f[j] * g[n - j] for j in range(n + 1))


class _Model:
    def __init__(self, spec, v_lp):
        self.a, self.k, self.mu0, self.vref = _mpf(spec.a), _mpf(spec.k), _mpf(spec.mu0), _mpf(spec.v_ref)
        self.eta, self.mass, self.v_lp = _mpf(spec.damping), _mpf(spec.mass), _mpf(v_lp)
        self.laws = [resolve_state_law(n).name for n in spec.state_law]
        self.b = [_mpf(x) for x in spec.b]
        self.dc = [_mpf(x) for x in spec.dc]
        self.scale = [self.vref / (_mpf(resolve_state_law(n).steady_factor) * d) for n, d in zip(self.laws, self.dc)]

    def state_rate(self, i, P, LP, Q2, n):
        """n-th coefficient of dθ_i/dt from P = Vθ/Dc (and ln P, (P/2)²)."""
        law = self.laws[i]
        if law == "aging":
            return (1 if n == 0 else 0) - P[n]
        if law == "slip":
            _log_series(P, n, LP)
            return -_conv(P, LP, n)
        Q2.append(_conv(P, P, n) / 4)
        return (1 if n == 0 else 0) - Q2[n]

    def lt0(self, thetas):
        return mp.fsum(b * mp.log(s * th) for b, s, th in zip(self.b, self.scale, thetas))

    def inertial(self, tau, v, thetas, order):
        """Coefficients [τ_n], [V_n], [[θ_i,n]] of the inertial system."""
        n_s = len(thetas)
        T, V, TH = [tau], [v], [[t] for t in thetas]
        LV, LT = [], [[] for _ in range(n_s)]
        P, LP, Q2 = [[] for _ in range(n_s)], [[] for _ in range(n_s)], [[] for _ in range(n_s)]
        for n in range(order):
            _log_series(V, n, LV)
            for i in range(n_s):   # LT_i = ln(V* θ_i/(c_i Dc_i)); its n ≥ 1 coefficients are those of ln θ_i
                if n == 0:
                    LT[i].append(mp.log(self.scale[i] * TH[i][0]))
                else:
                    _log_series(TH[i], n, LT[i])
            if n == 0:
                mu = self.mu0 + self.a * (LV[0] - mp.log(self.vref)) + mp.fsum(b * LT[i][0] for i, b in enumerate(self.b))
            else:
                mu = self.a * LV[n] + mp.fsum(b * LT[i][n] for i, b in enumerate(self.b))
            V.append((T[n] - self.eta * V[n] - mu) / (self.mass * (n + 1)))
            T.append(self.k * ((self.v_lp if n == 0 else 0) - V[n]) / (n + 1))
            for i in range(n_s):
                P[i].append(_conv(V, TH[i], n) / self.dc[i])
                TH[i].append(self.state_rate(i, P[i], LP[i], Q2[i], n) / (n + 1))
        return T, V, TH

    def slow(self, taup, thetas, order, forcing):
        """Coefficients [τ'_n], [V_n], [[θ_i,n]] with dτ'/dt = k(V_lp − V) − forcing(t) (``reference._coefficients``
        with the forcing series added)."""
        a, eta = self.a, self.eta
        n_s = len(thetas)
        M, V, ARG, TH = [taup], [], [], [[t] for t in thetas]
        LT = [[] for _ in range(n_s)]
        P, LP, Q2 = [[] for _ in range(n_s)], [[] for _ in range(n_s)], [[] for _ in range(n_s)]
        for n in range(order):
            for i in range(n_s):
                if n == 0:
                    LT[i].append(mp.log(self.scale[i] * TH[i][0]))
                else:
                    _log_series(TH[i], n, LT[i])
            r = M[n] - (self.mu0 if n == 0 else 0) - mp.fsum(b * LT[i][n] for i, b in enumerate(self.b))
            if n == 0:
                V.append(_velocity(a, eta, self.vref, r))
                ARG.append(mp.log(V[0] / self.vref))
            else:
                partial = mp.fsum(j * ARG[j] * V[n - j] for j in range(1, n)) / n
                ARG.append((r - eta * partial) / (a + eta * V[0]))
                V.append(ARG[n] * V[0] + partial)
            f = forcing[n] if n < len(forcing) else 0
            M.append((self.k * ((self.v_lp if n == 0 else 0) - V[n]) - f) / (n + 1))
            for i in range(n_s):
                P[i].append(_conv(V, TH[i], n) / self.dc[i])
                TH[i].append(self.state_rate(i, P[i], LP[i], Q2[i], n) / (n + 1))
        return M, V, TH

    def slow_converged(self, taup, thetas, use, extra, tol):
        """The slow solution's coefficients up to order ``use`` (module docstring); (M, V, TH, iterations).

        Computed to order use + extra: each pass leaves one more coefficient at the top wrong (the forcing
        F_n needs V_{n+2}), so at most ``extra`` passes are allowed before the used ones would be."""
        forcing, last = [], None
        for it in range(1, extra + 1):
            M, V, TH = self.slow(taup, thetas, use + extra, forcing)
            if last is not None:
                scale = max(abs(c) for c in V[:use])
                if max(abs(p - q) for p, q in zip(V[:use], last[:use])) <= tol * scale:
                    return M[:use + 1], V[:use], [c[:use + 1] for c in TH], it
            last = V
            forcing = [self.mass * (n + 1) * (n + 2) * V[n + 2] for n in range(len(V) - 2)]
        raise RuntimeError(f"reference_inertial_cycle: the slow-manifold iteration did not converge in {extra} "
                           "passes (raise extra, or lower switch)")


def _step_size(series, tol, order, safety):
    h = mp.inf
    for c, s in series:
        if c[order] != 0:
            h = min(h, (tol * s / abs(c[order])) ** (mp.mpf(1) / order))
    return safety * h


def reference_inertial_cycle(spec, v_lp, start, *, turns: int = 1, dps: int = 40, order: int = 30,
                             extra: int = 24, tol_digits: int = 32, safety: float = 0.5, switch: float = 1e-3,
                             max_steps: int = 400_000, echo=None) -> dict:
    """Turns of the slider with mass from the section V = V_lp crossed upwards (module docstring).

    ``start`` = (θ_i…, dV/dt) on the section (decimal strings or numbers). Returns per turn ``period``,
    ``theta``, ``vdot`` at the return, ``ln_v_max``, ``ln_v_min`` (ln(V/V_lp), the start's 0 included),
    ``steps`` (inertial, slow), ``iterations`` (largest of the slow phase); all mpf.
    """
    with mp.workdps(dps):
        m = _Model(spec, v_lp)
        tol = mp.mpf(10) ** (-tol_digits)
        conv_tol = mp.mpf(10) ** (-(dps - 2))
        sw = _mpf(switch)
        n_s = len(m.laws)
        thetas = [_mpf(x) for x in start[:n_s]]
        vdot = _mpf(start[n_s])
        ln_lp = mp.log(m.v_lp)
        out = []
        for _ in range(turns):
            v = m.v_lp
            tau = m.mu0 + m.a * mp.log(v / m.vref) + m.lt0(thetas) + m.eta * v + m.mass * vdot
            phase, t, left = "inertial", mp.mpf(0), False
            top = bottom = mp.mpf(0)
            n_in = n_slow = it_max = 0
            while True:
                if phase == "inertial":
                    T, V, TH = m.inertial(tau, v, thetas, order)
                    h = _step_size([(T, max(abs(T[0]), mp.mpf(1) / 10)), (V, abs(V[0]))] + [(c, abs(c[0])) for c in TH],
                                   tol, order, safety)
                    vpoly = V
                else:
                    M, V, TH, its = m.slow_converged(taup, thetas, order + 1, extra, conv_tol)
                    it_max = max(it_max, its)
                    h = _step_size([(M, max(abs(M[0]), mp.mpf(1) / 10))] + [(c, abs(c[0])) for c in TH],
                                   tol, order, safety)
                    vpoly = V
                dV = [j * vpoly[j] for j in range(1, len(vpoly))]
                v0, v1 = vpoly[0], _horner(vpoly, h)
                d0, d1 = dV[0], _horner(dV, h)
                if d0 * d1 < 0:
                    s = mp.findroot(lambda q: _horner(dV, q), (mp.mpf(0), h), solver="anderson")
                    x = mp.log(_horner(vpoly, s)) - ln_lp
                    top, bottom = max(top, x), min(bottom, x)
                if v1 < m.v_lp:
                    left = True
                if left and v0 < m.v_lp <= v1:
                    s = mp.findroot(lambda q: _horner(vpoly, q) - m.v_lp, (mp.mpf(0), h), solver="anderson")
                    t += s
                    thetas = [_horner(c, s) for c in TH]
                    vdot = _horner(dV, s)
                    if phase == "inertial":
                        n_in += 1
                    else:
                        n_slow += 1
                    break
                t += h
                thetas = [_horner(c, h) for c in TH]
                if phase == "inertial":
                    n_in += 1
                    tau, v = _horner(T, h), v1
                    vdot = _horner(dV, h)
                    resist = m.a + m.eta * v
                    # (on the way down or already rising: the slip law's inertial plunge overshoots
                    # onto the manifold where V is already increasing again)
                    if v < m.v_lp / mp.e and abs(m.mass * vdot) / resist < sw:
                        taup = tau - m.mass * vdot
                        _, Vs, _, _ = m.slow_converged(taup, thetas, 4, extra, conv_tol)
                        # the fast transient's shift of ln V, far below the step tolerance
                        if abs(m.mass * (vdot - Vs[1])) / resist < tol / 100:
                            phase = "slow"
                else:
                    n_slow += 1
                    taup = _horner(M, h)
                    vdot = _horner(dV, h)
                    v = v1
                    if abs(m.mass * vdot) / (m.a + m.eta * v) > sw:
                        # back to the inertial equations, on the slow manifold
                        _, Vs, _, _ = m.slow_converged(taup, thetas, 4, extra, conv_tol)
                        v, vdot = Vs[0], Vs[1]
                        tau = taup + m.mass * vdot
                        phase = "inertial"
                if n_in + n_slow >= max_steps:
                    raise RuntimeError(f"reference_inertial_cycle: no return within {max_steps} steps (t = {t})")
                if echo and (n_in + n_slow) % 200 == 0:
                    echo(f"  {phase} t = {mp.nstr(t, 12)} ln V = {mp.nstr(mp.log(v), 8)} steps {n_in}+{n_slow}")
            out.append({"period": t, "theta": thetas, "vdot": vdot, "ln_v_max": top, "ln_v_min": bottom,
                        "steps": (n_in, n_slow), "iterations": it_max})
        return {"turns": out}
