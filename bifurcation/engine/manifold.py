"""The fast unstable manifold of the ν = 0 fixed point, as a power series (parameterisation method).

At ν = 0 the equation of motion is Ü = −U + g(U̇/ν_f) (docs/physics.md) with the fixed point U = U̇ = 0;
linearised, Ü − 2αU̇ + U = 0 with eigenvalues λ± = α ± ω. As ν → 0 the finite-ν trajectory tends to
the orbit that leaves the fixed point along the fast direction λ = λ+ (Eq. 14 is that orbit on the
linear piece of Eq. 12). Write it as U(t) = P(s), s = e^{λt}, P(s) = Σ_{n≥1} u_n s^n, u_1 = 1. Then
U̇ = Σ nλ u_n s^n, Ü = Σ n²λ² u_n s^n, y = U̇/ν_f = 2αU̇, and with g(y) = y + Σ_{k≥2} c_k y^k,

    (n²λ² − 2αnλ + 1) u_n = [Σ_{k≥2} c_k y^k]_n ,

whose right side needs u_1 … u_{n−1} only. The factor is (nλ − λ+)(nλ − λ−) > 0 for n ≥ 2, also at
the Jordan point α = 1 (it is (n − 1)² there): no resonance, so the series is well defined for every
ν_f ≤ 1/2. Starting the ν = 0 integration on P(s0) instead of on the tangent s0·(1, λ) removes the
curvature error of the start; the series is truncated where its tail is below 1e-40 relative.
"""

from __future__ import annotations

import mpmath

__all__ = ["fast_manifold_start", "manifold_coefficients"]

_DPS = 60


def _series_mul(a, b, n):
    return [mpmath.fsum(a[i] * b[k - i] for i in range(k + 1)) for k in range(n + 1)]


def _nonlinear_part(coeffs, y, n):
    """[Σ_{k≥2} c_k y^k] as a series to order n (y has no constant term)."""
    out = [mpmath.mpf(0)] * (n + 1)
    power = _series_mul(y, y, n)
    for k in range(2, len(coeffs)):
        if k > n:
            break
        for m in range(n + 1):
            out[m] += coeffs[k] * power[m]
        power = _series_mul(power, y, n)
    return out


def manifold_coefficients(coeffs, alpha, order: int):
    """u_1..u_order of P(s) for drop Taylor coefficients ``coeffs`` (c_0 = 0, c_1 = 1)."""
    alpha = mpmath.mpf(alpha)
    omega = mpmath.sqrt(alpha**2 - 1)
    lam = alpha + omega
    u = [mpmath.mpf(0), mpmath.mpf(1)] + [mpmath.mpf(0)] * (order - 1)
    for n in range(2, order + 1):
        y = [2 * alpha * k * lam * u[k] for k in range(n + 1)]
        rhs = _nonlinear_part(coeffs, y, n)[n]
        u[n] = rhs / ((n * lam) ** 2 - 2 * alpha * n * lam + 1)
    return u, lam


def fast_manifold_start(law, nu_f, *, y_start: float = 1e-3, order: int = 12, tries: int = 6) -> tuple:
    """A point (U, U̇) on the fast manifold where U̇/ν_f ≈ y, accurate to ≪ 1e-34 relative.

    y is the largest of ``y_start``, ``y_start``/10, … (``tries`` values) where the series tail is
    below 1e-40 of its first term; the coefficients do not depend on y and are computed once.
    Returns mpmath numbers (U, U̇) at 60 digits, or raises ValueError if no y converges.
    """
    with mpmath.workdps(_DPS):
        alpha = 1 / (2 * mpmath.mpf(nu_f))
        if alpha < 1:
            raise ValueError("the fast manifold exists for ν_f ≤ 1/2 only")
        coeffs = law.drop_taylor(order + 1, dps=_DPS)
        u, lam = manifold_coefficients(coeffs, alpha, order)
        y = mpmath.mpf(y_start)
        for _ in range(tries):
            # s0 such that the linear term alone gives y: y ≈ 2α λ s.
            s0 = y / (2 * alpha * lam)
            terms = [u[n] * s0**n for n in range(1, order + 1)]
            if max(abs(terms[-1]), abs(terms[-2])) < mpmath.mpf("1e-40") * abs(terms[0]):
                U = mpmath.fsum(terms)
                Ud = mpmath.fsum(n * lam * u[n] * s0**n for n in range(1, order + 1))
                return U, Ud
            y /= 10
        raise ValueError(f"manifold series not converged for U̇/ν_f down to {mpmath.nstr(y * 10, 3)}")
