"""The compiled baselines of ``bifurcation bench --suite rs-chain`` (numba; only the bench imports this).

The chain of the bench (quasi-dynamic, aging law, free ends, radiation damping η > 0) in the engine's
variables (x_j = ln V_j, y_j = ln θ_j, P = Σ δ_j; ``_system.rhs_expressions``), written out by hand:

- ``dop853_catalog``: a fully compiled integrator, what a performance-minded user writes: scipy's DOP853
  (Hairer's 8(5,3) pair, its coefficient tables ``scipy.integrate._ivp.dop853_coefficients``, scipy's step
  control, error norm and 7th-order dense output, transcribed to one ``numba.njit`` loop) with the event
  definition as one scalar function g = max_j x_j − ln v_th, checked at the end of every step; a sign
  change is located on the step's dense output by the Illinois method to the rounding of t. An event
  starts at an upward root and ends at the next downward one; its potency is the change of P between
  them. As in the engine, P restarts from 0 after every step ending outside an event.
- ``rhs``/``jac``: the right-hand side and its Jacobian as ``numba.njit`` functions for scipy's LSODA
  (``solve_ivp(method="LSODA", jac=...)``, the event functions jitted too): the second column.

Like scipy's event handling, a sign change of g inside one step with none at its ends (a block rising
above v_th and back within one step) is not seen; the engine locates each block's crossings on every
step's Taylor polynomials.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["build", "dop853_catalog"]

_kernels: dict = {}


def build() -> dict:
    """Compile the kernels once (numba is imported only here): ``rhs``, ``jac``, ``catalog``."""
    if _kernels:
        return _kernels
    import numba as nb
    from scipy.integrate._ivp import dop853_coefficients as dc_

    n_stages = dc_.N_STAGES                      # 12 (+1: the FSAL evaluation at the step's end)
    A = np.ascontiguousarray(dc_.A)              # 16 × 16 (rows 13..15: the dense output's extra stages)
    B = np.ascontiguousarray(dc_.B)
    C = np.ascontiguousarray(dc_.C)
    E3 = np.ascontiguousarray(dc_.E3)
    E5 = np.ascontiguousarray(dc_.E5)
    D = np.ascontiguousarray(dc_.D)              # 4 × 16
    power = dc_.INTERPOLATOR_POWER               # 7
    safety, min_factor, max_factor, exponent = 0.9, 0.2, 10.0, -1.0 / 8.0   # scipy's RungeKutta, order 7

    @nb.njit(cache=False, fastmath=False)
    def rhs_into(u, out, v, n, a, b, dc, k, ell2, v_lp, eta):
        for j in range(n):
            v[j] = math.exp(u[j])
        total = 0.0
        for j in range(n):
            ydot = math.exp(-u[n + j]) - v[j] / dc                   # aging: θ̇/θ = 1/θ − V/Dc
            lap = 0.0
            if j > 0:
                lap += v[j - 1] - v[j]
            if j < n - 1:
                lap += v[j + 1] - v[j]
            out[j] = (k * (v_lp - v[j]) + ell2 * k * lap - b * ydot) / (a + eta * v[j])
            out[n + j] = ydot
            total += v[j]
        out[2 * n] = total

    @nb.njit(cache=False)
    def rhs(t, u, n, a, b, dc, k, ell2, v_lp, eta):
        out = np.empty_like(u)
        rhs_into(u, out, np.empty(n), n, a, b, dc, k, ell2, v_lp, eta)
        return out

    @nb.njit(cache=False)
    def jac(t, u, n, a, b, dc, k, ell2, v_lp, eta):
        m = 2 * n + 1
        J = np.zeros((m, m))
        v = np.exp(u[:n])
        for j in range(n):
            e = math.exp(-u[n + j])
            ydot = e - v[j] / dc
            lap, neighbours = 0.0, 0
            if j > 0:
                lap += v[j - 1] - v[j]
                neighbours += 1
                J[j, j - 1] = ell2 * k * v[j - 1] / (a + eta * v[j])
            if j < n - 1:
                lap += v[j + 1] - v[j]
                neighbours += 1
                J[j, j + 1] = ell2 * k * v[j + 1] / (a + eta * v[j])
            den = a + eta * v[j]
            num = k * (v_lp - v[j]) + ell2 * k * lap - b * ydot
            dnum_dx = -k * v[j] - ell2 * k * neighbours * v[j] + b * v[j] / dc
            J[j, j] = dnum_dx / den - num * eta * v[j] / (den * den)
            J[j, n + j] = b * e / den
            J[n + j, j] = -v[j] / dc
            J[n + j, n + j] = -e
            J[2 * n, j] = v[j]
        return J

    @nb.njit(cache=False)
    def gmax(u, n, ln_th):
        g = u[0]
        for j in range(1, n):
            if u[j] > g:
                g = u[j]
        return g - ln_th

    @nb.njit(cache=False)
    def dense(F, y_old, x, out):
        # scipy's Dop853DenseOutput: Horner-like in x and 1 − x on the 7 coefficient rows
        m = y_old.size
        for i in range(m):
            s = 0.0
            for r in range(power):
                s += F[power - 1 - r, i]
                s *= x if r % 2 == 0 else 1.0 - x
            out[i] = s + y_old[i]

    @nb.njit(cache=False)
    def rms(vec):
        s = 0.0
        for z in vec:
            s += z * z
        return math.sqrt(s / vec.size)

    @nb.njit(cache=False)
    def catalog(y0, t_end, events, n, a, b, dc, k, ell2, v_lp, eta, ln_th, rtol, atol):
        m = y0.size
        ip = 2 * n
        K = np.zeros((16, m))
        v = np.empty(n)
        y = y0.copy()
        y_new = np.empty(m)
        f = np.empty(m)
        f_new = np.empty(m)
        tmp = np.empty(m)
        F = np.empty((power, m))
        at = np.empty(m)
        scale = np.empty(m)
        t_start = np.empty(events)
        potency = np.empty(events)
        duration = np.empty(events)
        rhs_into(y, f, v, n, a, b, dc, k, ell2, v_lp, eta)
        nfev = 1
        # scipy's select_initial_step (Hairer, Nørsett & Wanner I, II.4)
        for i in range(m):
            scale[i] = atol + abs(y[i]) * rtol
        d0, d1 = rms(y / scale), rms(f / scale)
        h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h0 = min(h0, t_end)
        for i in range(m):
            tmp[i] = y[i] + h0 * f[i]
        rhs_into(tmp, f_new, v, n, a, b, dc, k, ell2, v_lp, eta)
        nfev += 1
        d2 = rms((f_new - f) / scale) / h0
        h1 = max(1e-6, h0 * 1e-3) if (d1 <= 1e-15 and d2 <= 1e-15) else (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100 * h0, h1, t_end)

        t = 0.0
        count, steps = 0, 0
        inside = False
        t_up = p_up = 0.0
        g_old = gmax(y, n, ln_th)
        while t < t_end and count < events:
            rejected = False
            while True:
                h = min(h_abs, t_end - t)
                if h < 1e-300:
                    return t_start[:count], potency[:count], duration[:count], steps, nfev, False
                K[0, :] = f
                for s in range(1, n_stages):
                    for i in range(m):
                        acc = 0.0
                        for r in range(s):
                            acc += A[s, r] * K[r, i]
                        tmp[i] = y[i] + h * acc
                    rhs_into(tmp, K[s], v, n, a, b, dc, k, ell2, v_lp, eta)
                for i in range(m):
                    acc = 0.0
                    for r in range(n_stages):
                        acc += B[r] * K[r, i]
                    y_new[i] = y[i] + h * acc
                rhs_into(y_new, f_new, v, n, a, b, dc, k, ell2, v_lp, eta)
                K[n_stages, :] = f_new
                nfev += n_stages
                e5 = e3 = 0.0
                for i in range(m):
                    sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                    s5 = s3 = 0.0
                    for r in range(n_stages + 1):
                        s5 += E5[r] * K[r, i]
                        s3 += E3[r] * K[r, i]
                    e5 += (s5 / sc) ** 2
                    e3 += (s3 / sc) ** 2
                err = 0.0 if (e5 == 0.0 and e3 == 0.0) else h * e5 / math.sqrt((e5 + 0.01 * e3) * m)
                if err < 1.0:
                    factor = max_factor if err == 0.0 else min(max_factor, safety * err ** exponent)
                    if rejected:
                        factor = min(1.0, factor)
                    h_next = h_abs * factor
                    break
                h_abs *= max(min_factor, safety * err ** exponent)
                rejected = True
            steps += 1
            g_new = gmax(y_new, n, ln_th)
            up, down = g_old < 0.0 <= g_new, g_old >= 0.0 > g_new
            if up or down:
                # the dense output of this step (scipy's DOP853._dense_output_impl)
                for s in range(n_stages + 1, 16):
                    for i in range(m):
                        acc = 0.0
                        for r in range(s):
                            acc += A[s, r] * K[r, i]
                        tmp[i] = y[i] + h * acc
                    rhs_into(tmp, K[s], v, n, a, b, dc, k, ell2, v_lp, eta)
                nfev += 3
                for i in range(m):
                    dy = y_new[i] - y[i]
                    F[0, i] = dy
                    F[1, i] = h * K[0, i] - dy
                    F[2, i] = 2 * dy - h * (f_new[i] + K[0, i])
                    for r in range(4):
                        acc = 0.0
                        for q in range(16):
                            acc += D[r, q] * K[q, i]
                        F[3 + r, i] = h * acc
                # Illinois on G(x) = g(dense(x)), x in [0, 1], until the bracket is below the rounding of t
                lo, hi, g_lo, g_hi = 0.0, 1.0, g_old, g_new
                side = 0
                x = 1.0
                for _ in range(200):
                    if (hi - lo) * h <= 2.2e-16 * max(abs(t), h):
                        break
                    x = (lo * g_hi - hi * g_lo) / (g_hi - g_lo)
                    if not (lo < x < hi):
                        x = 0.5 * (lo + hi)
                    dense(F, y, x, at)
                    g_x = gmax(at, n, ln_th)
                    if (g_x < 0.0) == (g_lo < 0.0):
                        lo, g_lo = x, g_x
                        if side == -1:
                            g_hi *= 0.5
                        side = -1
                    else:
                        hi, g_hi = x, g_x
                        if side == 1:
                            g_lo *= 0.5
                        side = 1
                x = hi            # the first point on the far side of the root
                dense(F, y, x, at)
                t_ev = t + x * h
                if up and not inside:
                    inside, t_up, p_up = True, t_ev, at[ip]
                elif down and inside:
                    inside = False
                    t_start[count] = t_up
                    potency[count] = at[ip] - p_up
                    duration[count] = t_ev - t_up
                    count += 1
            t += h
            y, y_new = y_new, y
            f, f_new = f_new, f
            g_old = g_new
            if not inside:
                y[ip] = 0.0      # between events P restarts from 0 (the engine does the same)
            h_abs = h_next
        return t_start[:count], potency[:count], duration[:count], steps, nfev, True

    _kernels.update(rhs=rhs, jac=jac, catalog=catalog, gmax=gmax)
    return _kernels


def dop853_catalog(spec, state0, t_end: float, events: int, rtol: float, atol: float) -> dict:
    """The first ``events`` events by the compiled DOP853 (stops at ``t_end`` at the latest)."""
    k = build()
    t_start, potency, duration, steps, nfev, ok = k["catalog"](
        np.asarray(state0, dtype=float), float(t_end), int(events), spec.n, spec.a, spec.b, spec.dc, spec.k,
        spec.ell ** 2, spec.v_lp, spec.eta, math.log(spec.v_th), float(rtol), float(atol))
    return {"t_start": t_start, "potency": potency, "duration": duration, "steps": int(steps),
            "nfev": int(nfev), "status": 0 if ok else -1}
