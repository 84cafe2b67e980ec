"""An independent first Lyapunov coefficient l1 of the rate-and-state slider's Hopf point (no code of
the package; the right-hand side and the Hopf point (k_c, ω_c) come from tests/_xref_rate_state.py, in
the physical variables u = (V, θ_i[, F]) with F = M V̇, not the engine's (ln V, ln θ_i, z)).

Formula: the projection formula for l1 of Kuznetsov's Elements of Applied Bifurcation Theory, Ch. 3,
Sec. 5, as quoted in Badiale & Cravero, arXiv:2511.08428, Eq. (1):

    l1 = Re[⟨p, C(q,q,q̄)⟩ − 2⟨p, B(q, A⁻¹B(q,q̄))⟩ + ⟨p, B(q̄, (2iω − A)⁻¹B(q,q))⟩] / (2ω),

A q = iω q, Aᵀp = −iω p, ⟨p, q⟩ = 1 (⟨u, v⟩ = ū·v). Here q and p come from the null space of
A ∓ iωI by an mpmath SVD (not a hand-rolled elimination), A from mpmath.diff column by column, and
B, C are built entry by entry from the second and third partial derivatives ∂²f_i/∂u_j∂u_k,
∂³f_i/∂u_j∂u_k∂u_l (mpmath.diff on the real field, then contracted with the complex vectors:
B(x, y)_i = Σ f_i,jk x_j y_k), not as directional derivatives in complex directions.

Coordinates: the cubic normal-form coefficient c1 of ż = iωz + c1 z|z|² belongs to the parametrisation
u = u* + z q + z̄ q̄ + …; a change of variables with linear part T carries q to Tq with the same c1,
and rescaling q by α multiplies c1 by |α|². With |q| = 1 in (V, θ, F), the engine's l1 (|q| = 1 in
(ln V, ln θ, z), T = diag(1/V*, 1/θ_i*, 1)) is l1_here / |T q|². The sign and the zeros of l1
(degenerate points, Bautin points) do not depend on the coordinates at all.
"""

from __future__ import annotations

import itertools

from mpmath import mp, mpf, mpc, matrix, diff, lu_solve, eye, svd_c, conj, fsum, sqrt, findroot

import _xref_rate_state as ref


def _steady(laws, dcs, v_lp, inertial):
    return [v_lp] + [ref.C[law] * dc / v_lp for law, dc in zip(laws, dcs)] + ([mpf(0)] if inertial else [])


def _derivatives(f, u0):
    """f_i,j, f_i,jk, f_i,jkl at u0 (symmetric: computed for j ≤ k ≤ l only)."""
    n = len(u0)
    d1, d2, d3 = {}, {}, {}
    for order, store in ((1, d1), (2, d2), (3, d3)):
        for idx in itertools.combinations_with_replacement(range(n), order):
            cnt = [idx.count(j) for j in range(n)]
            for i in range(n):
                store[(i,) + idx] = diff(lambda *x, i=i: f(list(x))[i], u0, cnt)
    return d1, d2, d3


def _sym(store, i, idx):
    return store[(i,) + tuple(sorted(idx))]


def _null(M):
    """The right singular vector of M for its smallest singular value (and that value)."""
    U, S, V = svd_c(M)
    j = min(range(M.cols), key=lambda c: abs(S[c]))
    return matrix([conj(V[j, c]) for c in range(M.cols)]), abs(S[j])


def lyapunov(laws, a, bs, dcs, v_lp, mass=None, eta=0, *, guess, dps=40):
    """dict(k_c, omega_c, l1 (in V, θ, F), l1_engine_coords (in ln V, ln θ, z), residuals)."""
    with mp.workdps(dps):
        k_c, w = ref.hopf(laws, a, bs, dcs, v_lp, mass, eta, guess=guess, dps=dps)
        a_, v, eta_ = mpf(a), mpf(v_lp), mpf(eta)
        bs_, dcs_ = [mpf(b) for b in bs], [mpf(d) for d in dcs]
        m_ = None if mass is None else mpf(mass)
        f = ref.rhs(laws, a_, bs_, dcs_, k_c, v, m_, eta_)
        u0 = _steady(laws, dcs_, v, mass is not None)
        n = len(u0)
        d1, d2, d3 = _derivatives(f, u0)
        A = matrix(n, n)
        for i in range(n):
            for j in range(n):
                A[i, j] = d1[(i, j)]
        iw = mpc(0, w)
        q, sq = _null(A - iw * eye(n))
        q = q / sqrt(fsum(abs(z) ** 2 for z in q))
        p, sp = _null(A.T + iw * eye(n))
        pq = fsum(conj(p[i]) * q[i] for i in range(n))
        p = p / conj(pq)

        def B(x, y):
            return matrix([fsum(_sym(d2, i, (j, k)) * x[j] * y[k] for j in range(n) for k in range(n))
                           for i in range(n)])

        def C(x, y, z):
            return matrix([fsum(_sym(d3, i, (j, k, l)) * x[j] * y[k] * z[l]
                                for j in range(n) for k in range(n) for l in range(n)) for i in range(n)])

        def dot(x, y):
            return fsum(conj(x[i]) * y[i] for i in range(n))

        qb = matrix([conj(z) for z in q])
        h11 = lu_solve(A, B(q, qb))
        h20 = lu_solve(2 * iw * eye(n) - A, B(q, q))
        bracket = dot(p, C(q, q, qb)) - 2 * dot(p, B(q, h11)) + dot(p, B(qb, h20))
        l1 = bracket.real / (2 * w)
        scale = [1 / v] + [1 / th for th in u0[1:1 + len(laws)]] + ([mpf(1)] if mass is not None else [])
        tq2 = fsum(abs(scale[i] * q[i]) ** 2 for i in range(n))
        # dλ/dk = ⟨p, (∂A/∂k) q⟩ (first-order perturbation of a simple eigenvalue, ⟨p, q⟩ = 1); A is
        # affine in k (k multiplies V_lp − V, zero at the steady state), so ∂A/∂k = A(k + 1) − A(k).
        dA = ref._jacobian(ref.rhs(laws, a_, bs_, dcs_, k_c + 1, v, m_, eta_), u0) - A
        dlam = dot(p, dA * q)
        return dict(k_c=k_c, omega_c=w, l1=l1, l1_engine_coords=l1 / tq2, null_residuals=(sq, sp),
                    bracket=bracket, dlambda_dk=dlam, q=q, steady=u0)


def small_cycle(r, kappa):
    """The cycle of the truncated normal form ż = λ(k) z + c1 z|z|², c1 = bracket/2 (so that l1 = Re c1/ω),
    λ(k) ≈ iω_c + λ'(k − k_c): |z|² = −Re λ/Re c1, frequency Im λ + Im c1 |z|². On u = u* + 2 Re(z q) the
    half-range of ln V is 2|z||q_V|/V*. Returns (half-range of ln V, period), both to leading order."""
    dk = (kappa - 1) * r["k_c"]
    c1 = r["bracket"] / 2
    z2 = -(r["dlambda_dk"].real * dk) / c1.real
    half = 2 * sqrt(z2) * abs(r["q"][0]) / r["steady"][0]
    omega = r["omega_c"] + r["dlambda_dk"].imag * dk + c1.imag * z2
    return half, 2 * mp.pi / omega


def bautin_eta(law, a, b, dc, v_lp, bracket, *, dps=30):
    """η = M V²/(a Dc) where l1 = 0 on the Hopf curve of one state variable (inertial, undamped), by
    Anderson's bracketing method on l1(η). At each η the Hopf point is the root of det(J − iωI) = 0
    (``ref.hopf``); Newton starts there from (b − a)/Dc·(1 + η) and (V/Dc)√((b − a)/a), a guess only."""

    def l1(eta_n):
        mass = eta_n * mpf(a) * mpf(dc) / mpf(v_lp) ** 2
        guess = ((mpf(b) - mpf(a)) / mpf(dc) * (1 + eta_n), (mpf(v_lp) / mpf(dc)) * sqrt((mpf(b) - mpf(a)) / mpf(a)))
        return lyapunov([law], a, [b], [dc], v_lp, mass, guess=guess, dps=dps)["l1"]

    with mp.workdps(dps):
        return findroot(l1, (mpf(bracket[0]), mpf(bracket[1])), solver="anderson", tol=mpf(10) ** (-dps + 10))


def return_map_multipliers(laws, a, bs, dcs, k, v_lp, w, *, dps=20, h="1e-8", scan="0.01"):
    """The quasi-static slider's return map to the section V = V_lp (upward) from ln θ_i = w, by
    mpmath.odefun in (V, θ_i) (crossings by ``ref._crossings``: a scan of step ``scan`` and Anderson's
    root finding), and its nontrivial Floquet multipliers: the eigenvalues of ∂P/∂w by central
    differences of step h in ln θ (truncation ~h², rounding ~10^-dps/h). Returns (period, multipliers)."""
    from mpmath import odefun, exp, log, eig

    with mp.workdps(dps):
        a_, v = mpf(a), mpf(v_lp)
        f = ref.rhs(laws, a_, [mpf(b) for b in bs], [mpf(d) for d in dcs], mpf(k), v)
        h = mpf(h)

        def ret(ws):
            F = odefun(lambda t, y: f(y), 0, [v] + [exp(x) for x in ws])
            tc, yc, _ = ref._crossings(F, f, mpf(0), mpf(scan), 100, True, v)
            return tc, [log(x) for x in yc[1:]]

        w = [mpf(x) for x in w]
        period, _ = ret(w)
        n = len(w)
        J = matrix(n, n)
        for j in range(n):
            plus, minus = list(w), list(w)
            plus[j] += h
            minus[j] -= h
            P, M = ret(plus)[1], ret(minus)[1]
            for i in range(n):
                J[i, j] = (P[i] - M[i]) / (2 * h)
        return period, list(eig(J, left=False, right=False))
