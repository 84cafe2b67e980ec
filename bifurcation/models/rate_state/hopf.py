"""The steady state at V = V_lp, its linearisation, the Hopf point and its first Lyapunov coefficient.

Steady state (docs/rate-state.md): x* = ln V_lp, y_i* = ln(c_i Dc_i/V_lp), z* = 0. The Jacobian A(k) and
the second and third derivatives B, C of the right-hand side (``_system.rhs_expressions`` evaluated
on mpmath numbers, the very equations the integrator compiles) are taken by ``mpmath.diff`` at
``dps`` digits (50 by default).

The Hopf point k_c is found numerically: max Re λ(A(k)) (``mpmath.eig``) is bracketed on a geometric
scan of k over 16 decades around Σ b_i/Dc_i and its sign change refined by ``mpmath.findroot``
(Anderson's bracketing method); ω_c = Im λ there. Closed forms, one state variable (all three laws
share the linearisation at steady state): k_c = (b − a)/Dc quasi-static (Ruina 1983),
k_c = (b − a)/Dc · [1 + M V²/(a Dc)] with inertia (Rice & Ruina 1983), and in both cases
ω_c = (V/Dc) √((b − a)/a). With radiation damping η, a becomes a' = a + ηV wherever it multiplies
ẋ: k_c = (b − a')/Dc · [1 + M V²/(a' Dc)] (M = 0: quasi-static), ω_c = (V/Dc) √((b − a')/a'), and
no Hopf point when ηV ≥ b − a (all derived in docs/rate-state.md).

First Lyapunov coefficient (Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed., Eq. 3.20):
with A q = iω q, Aᵀ p = −iω p, ⟨q, q⟩ = 1, ⟨p, q⟩ = 1 (⟨u, v⟩ = ū·v),

    l1 = Re[⟨p, C(q,q,q̄)⟩ − 2⟨p, B(q, A⁻¹B(q,q̄))⟩ + ⟨p, B(q̄, (2iω − A)⁻¹B(q,q))⟩] / (2ω).

l1 < 0: supercritical (small stable cycles on the unstable side k < k_c); l1 > 0: subcritical (small
unstable cycles for k > k_c, a jump at k_c); |l1| at the level of the working precision: degenerate
(the quasi-static aging law: a family of cycles at k_c, Ranjith & Rice, JMPS 47, 1207 (1999)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath as mp

from .spec import SliderSpec, _finite
from ._system import parameters, rhs_expressions

__all__ = ["HopfPoint", "closed_form", "hopf_point", "jacobian", "lyapunov_by_simulation", "steady_state"]


@dataclass(frozen=True)
class HopfPoint:
    """The Hopf point of a slider at V_lp, with its normal-form coefficient."""

    k_c: float
    omega_c: float
    lyapunov_coefficient: float
    criticality: str            # "subcritical", "supercritical" or "degenerate"
    k_c_closed_form: float      # NaN for two state variables (no closed form here)
    omega_c_closed_form: float
    eigenvector: tuple          # q (complex, ⟨q, q⟩ = 1) in (ln V, ln θ_i[, z])
    adjoint: tuple              # p, ⟨p, q⟩ = 1
    degenerate_tolerance: float
    rel_dev_k_c: float = math.nan       # |k_c − closed form|/closed form, at the working precision
    rel_dev_omega_c: float = math.nan

    def to_record(self) -> dict:
        return {"k_c": self.k_c, "omega_c": self.omega_c, "lyapunov_coefficient": self.lyapunov_coefficient,
                "criticality": self.criticality, "k_c_closed_form": self.k_c_closed_form,
                "omega_c_closed_form": self.omega_c_closed_form}


def steady_state(spec: SliderSpec, v_lp) -> list:
    """(x*, y_i*[, 0]) at V = V_lp, in mpmath numbers."""
    v = mp.mpf(v_lp)
    ys = [mp.log(mp.mpf(law.steady_factor) * mp.mpf(d) / v) for law, d in zip(spec.laws, spec.dc)]
    return [mp.log(v), *ys] + ([mp.mpf(0)] if spec.inertial else [])


def _pars(spec: SliderSpec, k, v_lp):
    return [mp.mpf(v) for v in parameters(spec, k, v_lp)]


def _field(spec, k, v_lp):
    par = _pars(spec, k, v_lp)

    def f(u):
        return rhs_expressions(spec.state_law, spec.inertial, u, par, mp.exp, mp.log, damped=spec.damped)
    return f


def jacobian(spec: SliderSpec, k, v_lp) -> mp.matrix:
    """A = ∂f/∂u at the steady state (mpmath.diff at the current precision)."""
    f = _field(spec, k, v_lp)
    u0 = steady_state(spec, v_lp)
    n = len(u0)
    A = mp.matrix(n, n)
    for j in range(n):
        col = [mp.diff(lambda s, i=i: f(_shift(u0, j, s))[i], 0) for i in range(n)]
        for i in range(n):
            A[i, j] = col[i]
    return A


def _shift(u, j, s):
    v = list(u)
    v[j] = v[j] + s
    return v


def _loses_stability(spec, v_lp) -> bool:
    """Whether Re λ(k) changes sign on ``hopf_point``'s grid of k (the quasi-static scale ± 8 decades)."""
    scale = sum(mp.mpf(bi) / mp.mpf(d) for bi, d in zip(spec.b, spec.dc))
    g = [mp.re(_max_real(spec, scale * mp.mpf(10) ** (e / mp.mpf(2)), v_lp)) for e in range(-16, 17)]
    return any(g[i] > 0 >= g[i + 1] for i in range(len(g) - 1))


def _max_real(spec, k, v_lp):
    ev = mp.eig(jacobian(spec, k, v_lp), left=False, right=False)
    return max(ev, key=lambda z: mp.re(z))


def closed_form(spec: SliderSpec, v_lp) -> tuple[float, float]:
    """(k_c, ω_c) from the closed forms (one state variable), or NaN for two."""
    if spec.n_states != 1:
        return math.nan, math.nan
    b, dc, v = (mp.mpf(spec.b[0]), mp.mpf(spec.dc[0]), mp.mpf(v_lp))
    a = mp.mpf(spec.a) + mp.mpf(spec.damping) * v   # radiation damping adds ηV to a (docs/rate-state.md)
    k_qs = (b - a) / dc
    k_c = k_qs if not spec.inertial else k_qs * (1 + mp.mpf(spec.mass) * v * v / (a * dc))
    omega = (v / dc) * mp.sqrt((b - a) / a) if b > a else mp.nan
    return k_c, omega


def hopf_point(*, a, b, dc, state_law, v_lp, mass=None, damping=0.0, dps: int = 50,
               lyapunov: bool = True) -> HopfPoint:
    """The Hopf point of the steady state at V = V_lp, found numerically, and l1 (module docstring).

    Raises ``InputError`` when the steady state is stable for every k (Σ b_i ≤ a: velocity
    strengthening; with one state variable also ηV_lp ≥ b − a: damping outweighs the weakening).
    """
    from ...errors import InputError

    spec = SliderSpec(a=a, b=b, dc=dc, state_law=state_law, k=1.0, mass=mass, damping=damping)
    v_lp = _finite("v_lp", v_lp, positive=True, fix="give a load-point velocity > 0")
    if sum(spec.b) <= spec.a:
        raise InputError("b", spec.b, f"sums to <= a = {spec.a:g}: velocity strengthening, steady sliding is "
                         "stable for every k and there is no Hopf point", "give b > a")
    if spec.n_states == 1 and spec.damping * v_lp >= spec.b[0] - spec.a:
        raise InputError("damping", spec.damping, f"gives ηV_lp = {spec.damping * v_lp:g} >= b - a = "
                         f"{spec.b[0] - spec.a:g}: steady sliding is stable for every k and there is no Hopf point",
                         "give damping < (b - a)/V_lp")
    with mp.workdps(dps):
        scale = sum(mp.mpf(bi) / mp.mpf(d) for bi, d in zip(spec.b, spec.dc))
        if spec.inertial:
            scale *= 1 + mp.mpf(spec.mass) * mp.mpf(v_lp) ** 2 / (mp.mpf(spec.a) * min(map(mp.mpf, spec.dc)))
        grid = [scale * mp.mpf(10) ** (e / mp.mpf(2)) for e in range(-16, 17)]
        g = [mp.re(_max_real(spec, kk, v_lp)) for kk in grid]
        # Stable (Re λ < 0) for large k; the last sign change going down in k is k_c.
        idx = [i for i in range(len(g) - 1) if g[i] > 0 >= g[i + 1]]
        if not idx:
            if spec.inertial and _loses_stability(SliderSpec(a=a, b=b, dc=dc, state_law=state_law, k=1.0,
                                                             damping=damping), v_lp):
                # the same slider without its mass has a Hopf point: the mass is at fault (--mass 1e300 was
                # reported as "b, mass", naming no option, issue 21 walk)
                ratio = mp.mpf(spec.mass) * mp.mpf(v_lp) ** 2 / (mp.mpf(spec.a) * min(map(mp.mpf, spec.dc)))
                raise InputError("mass", spec.mass, f"gives no loss of stability of steady sliding over 16 decades "
                                 f"of k (M V_lp²/(a Dc) = {float(ratio):.3g}; without the mass there is a Hopf point)",
                                 "give a smaller mass such as 1e-3, or none for the quasi-static slider")
            raise InputError("b", spec.b, "gives no loss of stability of steady sliding over 16 decades of k",
                             "check a, b, dc (a Hopf point needs b > a)")
        i = idx[-1]
        try:
            k_c = mp.findroot(lambda kk: mp.re(_max_real(spec, kk, v_lp)), (grid[i], grid[i + 1]),
                              solver="anderson", tol=mp.mpf(10) ** (-dps + 8))
        except (ValueError, ZeroDivisionError):   # mpmath's "could not find root", or a zero secant (a = 1e-300,
            # b = 1e300: a traceback before, issue 21 walk): parameters far outside any physical scale
            raise InputError("a, b, dc, v_lp", (spec.a, spec.b, spec.dc, v_lp),
                             f"give no Hopf point to {dps - 8} digits: the root of Re λ(k) did not converge",
                             "give values of physical size (e.g. a = 0.01, b = 0.015, dc = 0.01, v_lp = 1; "
                             "docs/rate-state.md)") from None
        lam = _max_real(spec, k_c, v_lp)
        omega = abs(mp.im(lam))
        k_cf, w_cf = closed_form(spec, v_lp)
        dev = (float(abs(k_c / k_cf - 1)), float(abs(omega / w_cf - 1))) if spec.n_states == 1 else (math.nan,) * 2
        if not lyapunov:
            return HopfPoint(float(k_c), float(omega), math.nan, "not computed", float(k_cf), float(w_cf),
                             (), (), math.nan, *dev)
        try:
            l1, q, p = _lyapunov(spec, k_c, v_lp, omega)
        except ZeroDivisionError:   # mpmath's "matrix is numerically singular": a traceback before (review)
            eta = (f"η = M V_lp²/(a Dc) = {spec.mass * v_lp ** 2 / (spec.a * min(spec.dc)):.3g}: "
                   if spec.inertial else "")
            raise InputError("mass" if spec.inertial else "a, b, dc, v_lp",
                             spec.mass if spec.inertial else (spec.a, spec.b, spec.dc, v_lp),
                             f"{eta}the first Lyapunov coefficient's linear system is singular at {dps} digits",
                             ("give a smaller mass" if spec.mass * v_lp ** 2 / (spec.a * min(spec.dc)) > 1 else
                              "give a larger mass, or omit --mass for the quasi-static slider")   # (5e-324 was told
                             if spec.inertial else                                               # "smaller")
                             "give values of physical size (e.g. a = 0.01, b = 0.015, dc = 0.01, v_lp = 1)") from None
        # Degenerate: |l1| below half the working digits of the size of its terms (the terms are
        # O(1); a true zero comes out at ~10^-dps, a nonzero l1 far above 10^-dps/2).
        tol = mp.mpf(10) ** (-dps // 2)
        scale_l1 = _l1_scale(spec, k_c, v_lp, q, p, omega)
        crit = "degenerate" if abs(l1) <= tol * scale_l1 else ("subcritical" if l1 > 0 else "supercritical")
        return HopfPoint(float(k_c), float(omega), float(l1), crit, float(k_cf), float(w_cf),
                         tuple(complex(z) for z in q), tuple(complex(z) for z in p), float(tol * scale_l1), *dev)


def _multilinear(f, u0, vectors):
    """∂^m/∂s_1…∂s_m f(u0 + Σ s_j v_j) at 0 (complex directions: f is analytic)."""
    m = len(vectors)
    n = len(u0)

    def g(*s):
        u = [u0[i] + sum(s[j] * vectors[j][i] for j in range(m)) for i in range(n)]
        return f(u)

    out = []
    for i in range(n):
        out.append(mp.diff(lambda *s: g(*s)[i], [0] * m, [1] * m))
    return mp.matrix(out)


def _lyapunov(spec, k, v_lp, omega):
    A = jacobian(spec, k, v_lp)
    n = A.rows
    f = _field(spec, k, v_lp)
    u0 = steady_state(spec, v_lp)
    iw = mp.mpc(0, omega)
    q = _null_vector(A - iw * mp.eye(n))
    q = q / mp.sqrt(mp.fsum(abs(z) ** 2 for z in q))
    p = _null_vector(A.T + iw * mp.eye(n))
    pq = mp.fsum(mp.conj(p[i]) * q[i] for i in range(n))
    p = p / mp.conj(pq)  # ⟨p, q⟩ = Σ p̄_i q_i = 1
    qb = mp.matrix([mp.conj(z) for z in q])

    def dot(u, v):
        return mp.fsum(mp.conj(u[i]) * v[i] for i in range(n))

    B_qq = _multilinear(f, u0, [q, q])
    B_qqb = _multilinear(f, u0, [q, qb])
    C_qqqb = _multilinear(f, u0, [q, q, qb])
    h11 = mp.lu_solve(A, B_qqb)
    h20 = mp.lu_solve(2 * iw * mp.eye(n) - A, B_qq)
    term = (dot(p, C_qqqb) - 2 * dot(p, _multilinear(f, u0, [q, h11]))
            + dot(p, _multilinear(f, u0, [qb, h20])))
    return mp.re(term) / (2 * omega), q, p


def _l1_scale(spec, k, v_lp, q, p, omega):
    """The size of the terms whose sum is l1: the scale against which 'degenerate' is judged."""
    f = _field(spec, k, v_lp)
    u0 = steady_state(spec, v_lp)
    n = len(u0)
    qb = mp.matrix([mp.conj(z) for z in q])
    C = _multilinear(f, u0, [q, q, qb])
    return max(mp.fsum(abs(p[i]) * abs(C[i]) for i in range(n)) / (2 * omega), mp.mpf(10) ** (-300))


def _null_vector(M):
    """A unit vector spanning the (numerically one-dimensional) kernel of the square matrix M."""
    n = M.rows
    # Solve with the last component fixed to 1 in the best-conditioned way: drop each equation in turn.
    best = None
    for drop in range(n):
        for fix in range(n):
            rows = [i for i in range(n) if i != drop]
            cols = [j for j in range(n) if j != fix]
            sub = mp.matrix([[M[i, j] for j in cols] for i in rows]) if n > 1 else None
            rhs = mp.matrix([-M[i, fix] for i in rows])
            try:
                sol = mp.lu_solve(sub, rhs) if n > 1 else mp.matrix([])
            except ZeroDivisionError:
                continue
            v = [mp.mpf(0)] * n
            v[fix] = mp.mpf(1)
            for c, j in enumerate(cols):
                v[j] = sol[c]
            res = mp.norm(M * mp.matrix(v)) / mp.norm(mp.matrix(v))
            if best is None or res < best[0]:
                best = (res, mp.matrix(v))
    return best[1]


def lyapunov_by_simulation(spec: SliderSpec, point: HopfPoint, v_lp, eps: float, precision="double") -> float:
    """l1 measured on the engine: the growth of a small cycle over one period at k = k_c.

    In the normal form ż = iωz + c1 z|z|², l1 = Re c1/ω, |z| grows by 2π l1 |z|³ per period. Start at
    u0 = u* + 2ε Re(e^{iφ} q) on the section x = ln V_lp (φ puts the ln V component at 0, with ẋ > 0),
    integrate to the next upward crossings of V_lp (exact events) and return (|z1| − |z0|)/(2π|z0|³),
    z = ⟨p, u − u*⟩. Its error is O(ε) (the centre manifold's quadratic part).
    """
    import cmath

    import numpy as np

    from .simulate import run_spec
    from .spec import load_history

    q = np.array(point.eigenvector)
    p = np.array(point.adjoint)
    u_star = np.array([float(v) for v in steady_state(spec, v_lp)])
    phi = math.pi / 2 - cmath.phase(q[0])
    spec_k = SliderSpec(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, k=point.k_c, mass=spec.mass,
                        mu0=spec.mu0, v_ref=spec.v_ref, damping=spec.damping)
    f = _field(spec_k, point.k_c, v_lp)
    for turn in (0.0, math.pi):
        d = 2 * eps * (cmath.exp(1j * (phi + turn)) * q).real
        d[0] = 0.0
        with mp.workdps(20):
            if float(f([mp.mpf(x) for x in u_star + d])[0]) > 0:
                break
    u0 = u_star + d
    period = 2 * math.pi / point.omega_c
    # The start is on the centre eigenspace, not the centre manifold: with a stable direction (inertia)
    # its O(ε²) offset decays over the first periods, so the growth is read between the upward
    # crossings ``skip`` and ``skip + 1`` (same phase: the O(ε²) terms of z cancel in the difference).
    skip = 8 if u_star.size > 2 else 0  # a stable direction besides the centre plane
    r = run_spec(spec_k, load_history(v_lp), [0.0, (skip + 1.5) * period], ln_v0=u0[0],
                 ln_theta0=list(u0[1:1 + spec.n_states]), z0=u0[-1] if spec.inertial else 0.0,
                 thresholds=[v_lp], precision=precision)
    ups = [np.array([float(x) for x in s]) for (t, s), c in zip(r.crossing_states, r.crossings) if c[2] > 0]
    z_a = abs(np.vdot(p, (ups[skip - 1] if skip else u0) - u_star))
    z_b = abs(np.vdot(p, ups[skip] - u_star))
    return (z_b - z_a) / (2 * math.pi * z_a ** 3)
