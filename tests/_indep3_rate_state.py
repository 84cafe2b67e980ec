"""A third independent reference for the rate-and-state slider with mass and radiation damping
(tests/test_indep3_rate_state.py).

Written without the package, without tests/_indep_taylor.py, tests/_indep_rate_state.py or
tests/_xref_*.py: the model of docs/rate-state.md ("The model") in the variables (V, θ, F), F = M V̇
the net force (the engine integrates ln V, ln θ and F),

    V' = F/M,   θ' = 1 − Vθ/Dc (aging) | −(Vθ/Dc) ln(Vθ/Dc) (slip) | 1 − (Vθ/(2Dc))² (PRZ),
    F' = k(V_lp − V) − η F/M − a F/(M V) − b θ'/θ,

(F = k(δ_lp − δ) − ηV − μ, μ = μ0 + a ln V + b ln(θ/(c Dc)), differentiated once), by its own
Taylor recurrences in mpmath (order 30, 45 digits, step from the last two coefficients), with
* ``jacobian_eigs``: the eigenvalues of the Jacobian of that right-hand side at steady sliding
  (mpmath.diff, mpmath.eig) and ``hopf_k``: the k where their largest real part crosses 0 (findroot);
* ``cycle``: the attracting cycle by Newton shooting on the section F = 0, F decreasing (the maximum of
  V), the return map integrated in mpmath, started from a scipy LSODA transient (double precision,
  rtol 1e-11) of the same equations.
"""

from __future__ import annotations

import math

from mpmath import mp, mpf


def _c(law):
    return 2 if law == "prz" else 1


def rhs(law, p, V, th, F):
    a, b, dc, k, vlp, m, eta = p
    w = V * th / (_c(law) * dc)
    if law == "aging":
        td = 1 - w
    elif law == "slip":
        td = -w * mp.log(w)
    else:
        td = 1 - w * w
    return [F / m, td, k * (vlp - V) - eta * F / m - a * F / (m * V) - b * td / th]


def _series(law, p, V0, th0, F0, order):
    a, b, dc, k, vlp, m, eta = p
    cw = 1 / (_c(law) * dc)
    V, T, F = [V0], [th0], [F0]
    w, L, Td, r, q = [], [], [], [], []
    for n in range(order):
        w.append(cw * sum(V[j] * T[n - j] for j in range(n + 1)))
        if law == "aging":
            td = (1 if n == 0 else 0) - w[n]
        elif law == "slip":
            if n == 0:
                L.append(mp.log(w[0]))
            else:
                L.append((n * w[n] - sum(j * L[j] * w[n - j] for j in range(1, n))) / (n * w[0]))
            td = -sum(w[j] * L[n - j] for j in range(n + 1))
        else:
            td = (1 if n == 0 else 0) - sum(w[j] * w[n - j] for j in range(n + 1))
        Td.append(td)
        r.append((td - sum(T[j] * r[n - j] for j in range(1, n + 1))) / T[0])
        q.append((F[n] - sum(V[j] * q[n - j] for j in range(1, n + 1))) / V[0])
        fd = k * ((vlp if n == 0 else 0) - V[n]) - eta * F[n] / m - a * q[n] / m - b * r[n]
        V.append(F[n] / (m * (n + 1)))
        T.append(td / (n + 1))
        F.append(fd / (n + 1))
    return V, T, F


def _ev(c, s):
    out = mpf(0)
    for x in reversed(c):
        out = out * s + x
    return out


def _root(c, h, lo, samples=16):
    a = h * lo
    fa = _ev(c, a)
    for i in range(1, samples + 1):
        b = h * i / samples
        if b <= a:
            continue
        fb = _ev(c, b)
        if (fa > 0) != (fb > 0):
            x0, x1 = a, b
            for _ in range(mp.prec + 4):
                mid = (x0 + x1) / 2
                if (_ev(c, mid) > 0) == (fa > 0):
                    x0 = mid
                else:
                    x1 = mid
            return (x0 + x1) / 2
        a, fa = b, fb
    return None


def return_map(law, p, V0, th0, order=30, max_steps=100000):
    """From (V0, θ0, F = 0) on the section, to the next F = 0 with F decreasing: (V, θ, T, V_min)."""
    eps = mpf(10) ** (-(mp.dps - 4))
    a = p[0]
    t, V, th, F = mpf(0), mpf(V0), mpf(th0), mpf(0)
    vmin = None
    started = False
    for _ in range(max_steps):
        Vs, Ts, Fs = _series(law, p, V, th, F, order)
        h = None
        for cs, scale in ((Vs, abs(V)), (Ts, abs(th)), (Fs, max(abs(F), a * mpf(10) ** -3))):
            for n in (order - 1, order):
                if cs[n] != 0:
                    hn = (eps * scale / abs(cs[n])) ** (mpf(1) / n)
                    h = hn if h is None else min(h, hn)
        h = h * mpf("0.5")
        s = _root(Fs, h, mpf(10) ** -9 if not started else mpf(0))
        started = True
        if s is None:
            V, th, F, t = _ev(Vs, h), _ev(Ts, h), _ev(Fs, h), t + h
            continue
        V, th, t = _ev(Vs, s), _ev(Ts, s), t + s
        dF = _ev([(n + 1) * Fs[n + 1] for n in range(order)], s)
        F = mpf(0)
        if dF > 0:
            vmin = V              # F crosses 0 upward: the minimum of V
            # next search starts just past this root
            Vs, Ts, Fs = _series(law, p, V, th, F, order)
            started = False
            continue
        return V, th, t, vmin
    raise RuntimeError("no return to the section")


def _transient(law, p, V0, th0, periods_t):
    import numpy as np
    from scipy.integrate import solve_ivp
    a, b, dc, k, vlp, m, eta = (float(x) for x in p)

    def f(t, y):
        V, th, F = y
        w = V * th / (_c(law) * dc)
        td = 1 - w if law == "aging" else (-w * math.log(w) if law == "slip" else 1 - w * w)
        return [F / m, td, k * (vlp - V) - eta * F / m - a * F / (m * V) - b * td / th]

    sol = solve_ivp(f, (0, periods_t), [float(V0), float(th0), 0.0], method="LSODA", rtol=1e-11, atol=1e-14,
                    dense_output=False, events=None)
    V, th, F = sol.y[:, -1]
    return V, th, F


def cycle(law, a, b, dc, k, v_lp, mass, eta, perturb=1e-2, transient=300.0, dps=45, newton=8):
    """Period, ln(V_max/V_lp), ln(V_min/V_lp) of the attracting cycle; closure |P(x) − x| relative."""
    with mp.workdps(dps):
        p = tuple(mpf(x) for x in (a, b, dc, k, v_lp, mass, eta))
        th_ss = _c(law) * p[2] / p[4]
        V, th, F = _transient(law, p, float(v_lp) * math.exp(perturb), float(th_ss), transient)
        # land on the section with the mpmath integrator: one return from the transient's end state
        # (F ≠ 0 there, so integrate to the next downward F = 0 first)
        x = _to_section(law, p, mpf(V), mpf(th), mpf(F))
        for _ in range(newton):
            V1, th1, T, _vmin = return_map(law, p, *x)
            r = [V1 - x[0], th1 - x[1]]
            d = [x[0] * mpf(10) ** -20, x[1] * mpf(10) ** -20]
            J = mp.matrix(2, 2)
            for j in range(2):
                y = list(x)
                y[j] += d[j]
                Vj, thj, _, _ = return_map(law, p, *y)
                J[0, j] = (Vj - y[0] - r[0]) / d[j]
                J[1, j] = (thj - y[1] - r[1]) / d[j]
            dx = mp.lu_solve(J, mp.matrix(r))
            x = [x[0] - dx[0], x[1] - dx[1]]
            if max(abs(dx[0] / x[0]), abs(dx[1] / x[1])) < mpf(10) ** -(dps - 10):
                break
        mults = [abs(z) for z in mp.eig(J + mp.eye(2), left=False, right=False)]
        V1, th1, T, vmin = return_map(law, p, *x)
        closure = max(abs(V1 - x[0]) / x[0], abs(th1 - x[1]) / x[1])
        return {"period": T, "ln_v_max": mp.log(x[0] / p[4]), "ln_v_min": mp.log(vmin / p[4]),
                "closure": closure, "multiplier_max": max(mults)}


def _to_section(law, p, V, th, F, order=30):
    eps = mpf(10) ** (-(mp.dps - 4))
    for _ in range(100000):
        Vs, Ts, Fs = _series(law, p, V, th, F, order)
        h = None
        for cs, scale in ((Vs, abs(V)), (Ts, abs(th)), (Fs, max(abs(F), p[0] * mpf(10) ** -3))):
            for n in (order - 1, order):
                if cs[n] != 0:
                    hn = (eps * scale / abs(cs[n])) ** (mpf(1) / n)
                    h = hn if h is None else min(h, hn)
        h = h * mpf("0.5")
        s = _root(Fs, h, mpf(10) ** -9)
        if s is not None:
            dF = _ev([(n + 1) * Fs[n + 1] for n in range(order)], s)
            V, th = _ev(Vs, s), _ev(Ts, s)
            if dF < 0:
                return [V, th]
            F = mpf(0)
            continue
        V, th, F = _ev(Vs, h), _ev(Ts, h), _ev(Fs, h)
    raise RuntimeError("section not reached")


def jacobian_eigs(law, a, b, dc, k, v_lp, mass, eta):
    """Eigenvalues of the (V, θ, F) Jacobian at steady sliding (V_lp, c Dc/V_lp, 0)."""
    p = tuple(mpf(x) for x in (a, b, dc, k, v_lp, mass, eta))
    x0 = [p[4], _c(law) * p[2] / p[4], mpf(0)]
    J = mp.matrix(3, 3)
    for i in range(3):
        for j in range(3):
            def f(s, i=i, j=j):
                y = list(x0)
                y[j] = y[j] + s
                return rhs(law, p, *y)[i]
            J[i, j] = mp.diff(f, 0)
    ev = mp.eig(J, left=False, right=False)
    return sorted(ev, key=lambda z: -mp.re(z))


def hopf_k(law, a, b, dc, v_lp, mass, eta, k_guess):
    """k where the largest real part of the eigenvalues crosses zero, and the frequency there."""
    g = lambda k: mp.re(jacobian_eigs(law, a, b, dc, k, v_lp, mass, eta)[0])
    k = mp.findroot(g, (mpf(k_guess) * (1 - mpf(10) ** -3), mpf(k_guess) * (1 + mpf(10) ** -3)), solver="anderson")
    return k, abs(mp.im(jacobian_eigs(law, a, b, dc, k, v_lp, mass, eta)[0]))
