"""Independent references for the rate-and-state slider (tests/test_indep_rate_state.py).

Model (docs/rate-state.md, "The model"): μ = μ0 + a ln(V/V*) + Σ b_i ln(V* θ_i/(c_i Dc_i)),
c = 1 (aging, slip), 2 (PRZ); dθ/dt = 1 − Vθ/Dc (aging), −(Vθ/Dc) ln(Vθ/Dc) (slip),
1 − (Vθ/(2Dc))² (PRZ); quasi-static k(δ_lp − δ) − ηV = μ, inertial M V̇ = k(δ_lp − δ) − ηV − μ.

Written here without the package's code, in variables the engine does not use (V and θ, and the
spring force τ = k(δ_lp − δ) with inertia; the engine integrates ln V, ln θ and the net force):

* `hopf_closed_form`: the Hopf point of one state variable, derived here (see the docstring);
* `hopf_numeric`: k where the largest real part of the eigenvalues of the Jacobian of the (τ, V, θ)
  or (V, θ) right-hand side vanishes (mpmath.diff, mpmath.eig, mpmath.findroot): any number of
  state variables, and a second method for the closed form;
* `cycle_period`: the attracting limit cycle by shooting on the Poincaré section V = V_lp (upwards),
  Newton at 40 digits on the return map integrated by tests/_indep_taylor.py, started from a scipy
  LSODA transient (a different integrator, double precision, used only to land near the cycle).
"""

from __future__ import annotations

import math

import numpy as np
from mpmath import mp, mpf

import _indep_taylor as tt

C = {"aging": 1, "slip": 1, "prz": 2}


def theta_dot(law, v, th, dc, lib):
    """dθ/dt; `lib` supplies log (mpmath or the Taylor nodes)."""
    if law == "aging":
        return 1 - v * th / dc
    if law == "slip":
        r = v * th / dc
        return -r * lib.log(r)
    if law == "prz":
        r = v * th / (2 * dc)
        return 1 - r * r
    raise ValueError(law)


def hopf_closed_form(a, b, dc, v, mass=0, eta=0):
    """One state variable, any of the three laws (they share the linearisation at steady state).

    Linearising at V = V_lp, θ = c Dc/V_lp: δ(dθ/dt)/θ = −p(δV/V + δθ/θ), p = V/Dc, for all three
    laws. Quasi-static, a' = a + ηV: a' ξ' = −kV ξ + b p (ξ + ζ), ζ' = −p(ξ + ζ) (ξ = δV/V, ζ = δθ/θ);
    trace 0 ⇒ k_c = (b − a')/Dc, and ω² = det = k_c V p/a'. Inertial: the characteristic polynomial
    of (δ, V, θ) is M V s³ + (M V p + a') s² + (kV + (a' − b)p) s + kVp; s = iω in its real and
    imaginary parts gives ω² = kVp/(MVp + a') = (kV + (a' − b)p)/(MV), hence
    k_c = (b − a')/Dc · (1 + MV²/(a' Dc)), ω_c² = (b − a')p²/a' (independent of M).
    """
    a, b, dc, v, mass, eta = (mpf(q) for q in (a, b, dc, v, mass, eta))
    ap = a + eta * v
    p = v / dc
    kc = (b - ap) / dc * (1 + mass * v * v / (ap * dc))
    wc = p * mp.sqrt((b - ap) / ap)
    return kc, wc


def _rhs_physical(laws, a, bs, dcs, vlp, k, mass, eta, lib):
    """Right-hand side on the state (τ, V, θ_1..) with inertia, (V, θ_1..) quasi-static."""
    def f(s):
        if mass:
            tau, v, ths = s[0], s[1], s[2:]
        else:
            v, ths = s[0], s[1:]
        thd = [theta_dot(law, v, th, dc, lib) for law, th, dc in zip(laws, ths, dcs)]
        if mass:
            mu = a * lib.log(v) + sum(b * lib.log(th / (C[law] * dc)) for law, b, th, dc in zip(laws, bs, ths, dcs))
            return [k * (vlp - v), (tau - eta * v - mu) / mass, *thd]
        # quasi-static: k(V_lp − V) − η V' = a V'/V + Σ b θ'/θ
        num = k * (vlp - v) - sum(b * td / th for b, td, th in zip(bs, thd, ths))
        return [num * v / (a + eta * v), *thd]
    return f


class _MpLib:
    log = staticmethod(mp.log)


def _steady(laws, a, bs, dcs, vlp, mass):
    ths = [C[law] * dc / vlp for law, dc in zip(laws, dcs)]
    if mass:
        mu = a * mp.log(vlp) + sum(b * mp.log(th / (C[law] * dc)) for law, b, th, dc in zip(laws, bs, ths, dcs))
        return [mu + 0, vlp, *ths]  # τ − ηV − μ = 0 is set by the caller (η enters)
    return [vlp, *ths]


def max_real_eig(laws, a, bs, dcs, vlp, k, mass=0, eta=0):
    a, vlp, k, mass, eta = (mpf(q) for q in (a, vlp, k, mass, eta))
    bs, dcs = [mpf(b) for b in bs], [mpf(d) for d in dcs]
    f = _rhs_physical(laws, a, bs, dcs, vlp, k, mass, eta, _MpLib)
    x0 = _steady(laws, a, bs, dcs, vlp, mass)
    if mass:
        x0[0] = x0[0] + eta * vlp
    n = len(x0)
    jac = mp.matrix(n, n)
    for j in range(n):
        def fj(h, j=j):
            x = list(x0)
            x[j] = x[j] + h
            return f(x)
        cols = [mp.diff(lambda h, i=i: fj(h)[i], 0) for i in range(n)]
        for i in range(n):
            jac[i, j] = cols[i]
    ev = mp.eig(jac, left=False, right=False)
    return max(ev, key=lambda z: mp.re(z))


def hopf_numeric(laws, a, bs, dcs, vlp, mass=0, eta=0, k_guess=None, bracket=False):
    """k_c where max Re λ(J(k)) = 0, and ω_c = |Im λ| there. With `bracket`, a sign change of the
    largest real part is first looked for on a geometric scan k_guess·[0.1, 10] (64 points) and the
    root refined by the Anderson bracketing method (for two state variables, where the guess is poor)."""
    g = lambda k: mp.re(max_real_eig(laws, a, bs, dcs, vlp, k, mass, eta))
    if bracket:
        ks = [mpf(k_guess) * mpf(10) ** (mpf(2 * i) / 63 - 1) for i in range(64)]
        vals = [g(k) for k in ks]
        i = next(i for i in range(63) if (vals[i] > 0) != (vals[i + 1] > 0))
        kc = mp.findroot(g, (ks[i], ks[i + 1]), solver="anderson")
    else:
        kc = mp.findroot(g, mpf(k_guess))
    return kc, abs(mp.im(max_real_eig(laws, a, bs, dcs, vlp, kc, mass, eta)))


class _NodeLib:
    log = staticmethod(tt.log)


def _system(laws, a, bs, dcs, vlp, k, mass, eta):
    f = _rhs_physical(laws, a, bs, dcs, vlp, k, mass, eta, _NodeLib)
    iv = 1 if mass else 0           # index of V in the state
    dim = len(laws) + 1 + (1 if mass else 0)

    def rhs(t, x):
        return f(x)

    def events(t, x):
        r = f(x)
        return [x[iv] / vlp - 1, r[iv] / vlp]  # the section, V' = 0 (extrema)

    return tt.System(dim, rhs, events), iv


def _turn(sysm, iv, x0, vlp, order, tol):
    """From a section point (V = V_lp, V rising) to the next: (state, period, ln V/V_lp max, min)."""
    t, x = mpf(0), list(x0)
    vmax, vmin = x[iv], x[iv]
    first_sec, first_ext = True, False
    for _ in range(200000):
        xs, gs, _ = sysm.series(t, x, order)
        h = tt.step_size(xs, order, tol)
        hits = []
        r = tt.first_root(gs[0], h, skip0=first_sec)
        if r is not None and tt.peval(tt.pderiv(gs[0]), r) > 0:
            hits.append((r, "sec"))
        elif r is not None:
            h = r  # a downward crossing: end the step there, carry on
        r = tt.first_root(gs[1], h, skip0=first_ext)
        if r is not None:
            hits.append((r, "ext"))
        first_sec = first_ext = False
        r, kind = min(hits, key=lambda p: p[0]) if hits else (h, None)
        if kind is None and r == h and tt.first_root(gs[0], h) is not None:
            first_sec = True  # stopped at a downward crossing of the section
        x = [tt.peval(c, r) for c in xs]
        t += r
        if kind == "ext":
            first_ext = True
            vmax, vmin = max(vmax, x[iv]), min(vmin, x[iv])
        elif kind == "sec":
            x[iv] = mpf(vlp)
            return x, t, mp.log(vmax / vlp), mp.log(vmin / vlp)
    raise RuntimeError("no return to the section")


def _transient_guess(laws, a, bs, dcs, vlp, k, mass, eta, periods=60):
    """scipy LSODA (double) from steady sliding perturbed by 1e-2 in ln V, to near the cycle."""
    from scipy.integrate import solve_ivp

    fl = _rhs_physical(laws, a, bs, dcs, vlp, k, mass, eta, np)
    iv = 1 if mass else 0
    ths = [C[law] * dc / vlp for law, dc in zip(laws, dcs)]
    # in (ln V, ln θ, [τ]) to keep LSODA sane over decades of V
    def f(t, z):
        s = list(np.exp(z[:1 + len(laws)]))
        s = ([z[-1]] + s) if mass else s
        d = fl(s)
        dv = d[iv] / s[iv]
        dth = [dt / th for dt, th in zip(d[iv + 1:], s[iv + 1:])]
        return [dv, *dth] + ([d[0]] if mass else [])
    mu0 = a * math.log(vlp) + sum(b * math.log(th / (C[law] * dc)) for law, b, th, dc in zip(laws, bs, ths, dcs))
    z0 = [math.log(vlp) + 1e-2, *map(math.log, ths)] + ([mu0 + eta * vlp] if mass else [])
    _kc, wc = hopf_closed_form(a, bs[0], dcs[0], vlp, mass, eta)
    tp = 2 * math.pi / float(wc)
    ev = lambda t, z: z[0] - math.log(vlp)
    ev.direction = 1
    sol = solve_ivp(f, (0, periods * tp), z0, method="LSODA", rtol=1e-11, atol=1e-13, events=ev)
    ze = sol.y_events[0][-1]
    th = list(np.exp(ze[1:1 + len(laws)]))
    return ([ze[-1]] if mass else []) + [vlp] + th


def cycle_period(laws, a, bs, dcs, vlp, k, mass=0, eta=0, dps=45, order=36):
    """Period and ln(V/V_lp) extrema of the attracting cycle: shooting on V = V_lp (upwards)."""
    guess = _transient_guess(laws, a, bs, dcs, vlp, k, mass, eta)
    iv = 1 if mass else 0
    free = [i for i in range(len(guess)) if i != iv]

    def run(x, d, o, tol):
        with mp.workdps(d):
            p = [mpf(q) for q in (a, vlp, k, mass, eta)]
            sysm, _ = _system(laws, p[0], [mpf(b) for b in bs], [mpf(c) for c in dcs], p[1], p[2], p[3], p[4])
            return _turn(sysm, iv, [mpf(q) for q in x], p[1], o, tol)

    # Newton at 20 digits (Jacobian by differences), then at `dps`
    x = [mpf(q) for q in guess]
    for d, o, tol, its in ((24, 22, mpf(10) ** -21, 8), (dps, order, mpf(10) ** -(dps - 4), 2)):
        with mp.workdps(d):
            for _ in range(its):
                y, *_r = run(x, d, o, tol)
                res = [y[i] - x[i] for i in free]
                if d != dps:
                    jac = mp.matrix(len(free), len(free))
                    for jj, j in enumerate(free):
                        hj = abs(x[j]) * mpf(10) ** -9
                        xp = list(x)
                        xp[j] += hj
                        yp, *_r = run(xp, d, o, tol)
                        for ii, i in enumerate(free):
                            jac[ii, jj] = (yp[i] - xp[i] - res[ii]) / hj
                dx = mp.lu_solve(jac, mp.matrix(res))
                for jj, j in enumerate(free):
                    x[j] = x[j] - dx[jj]
                if max(abs(dx[jj] / x[j]) for jj, j in enumerate(free)) < mpf(10) ** -(d - 4):
                    break
    with mp.workdps(dps):
        y, period, lmax, lmin = run(x, dps, order, mpf(10) ** -(dps - 4))
        closure = max(abs(y[i] - x[i]) / abs(x[i]) for i in free)
        return {"period": period, "ln_v_max": lmax, "ln_v_min": lmin, "closure": closure}
