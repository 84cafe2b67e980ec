r"""Closed forms of Vasconcelos, PRL 76, 4865 (1996), Eqs. (6)–(18), with the errata corrected.

Frame: U is measured from the position where the block starts; Eq. (6), Ü − 2αU̇ + U = νt with
U(0) = U̇(0) = Ü(0) = 0, holds while U̇ ≤ ν_f. α = 1/(2ν_f), ω = √|α² − 1|. Every formula here was
checked against the exact piecewise solution of ``bifurcation.theory.reference`` (tests/test_theory.py);
where the printed equation is wrong the corrected one is implemented and the printed one is recorded
in ``bifurcation.theory.errata.ERRATA``.

Every function takes numpy-broadcastable float arguments and returns float64 arrays; given mpmath
numbers (any argument an ``mpf``) it computes in mpmath at the current ``mpmath.mp.dps`` instead.
The formulas at ν_f = 1/2 (α = 1, ω = 0) are their limits, written without 0/0.
"""

from __future__ import annotations

import mpmath
import numpy as np

from ..errors import InputError

__all__ = [
    "alpha", "creep_coefficient", "creep_time_asymptotic", "delta0_piecewise_linear", "delta_creep",
    "displacement_creep", "displacement_limit_linear", "displacement_limit_piecewise_linear",
    "displacement_linear", "max_velocity_creep", "omega", "stop_time_creep", "tau1", "tau2",
    "velocity_linear",
]


# -- numpy / mpmath dispatch ------------------------------------------------------------------------
class _Numpy:
    exp, sin, cos = np.exp, np.sin, np.cos
    sqrt, log, log1p, atan, atan2 = np.sqrt, np.log, np.log1p, np.arctan, np.arctan2
    pi = np.pi

    @staticmethod
    def where(cond, a, b):
        return np.where(cond, a, b)

    @staticmethod
    def out(x):
        x = np.asarray(x, dtype=np.float64)
        return x[()] if x.ndim == 0 else x


class _Mp:
    exp, sin, cos = staticmethod(mpmath.exp), staticmethod(mpmath.sin), staticmethod(mpmath.cos)
    sqrt, log, log1p = staticmethod(mpmath.sqrt), staticmethod(mpmath.log), staticmethod(mpmath.log1p)
    atan, atan2 = staticmethod(mpmath.atan), staticmethod(mpmath.atan2)
    pi = mpmath.pi  # a constant evaluated at the working precision where it is used

    @staticmethod
    def where(cond, a, b):
        return a if cond else b

    @staticmethod
    def out(x):
        return x


def _ops(*args):
    if any(isinstance(a, (mpmath.mpf, mpmath.mpc)) for a in args):
        return _Mp, [mpmath.mpf(a) for a in args]
    return _Numpy, [np.asarray(a, dtype=np.float64) for a in args]


def _require(ok, name, value, problem, fix):
    if not np.all(ok):
        raise InputError(name, value, problem, fix)


def _alpha_omega(xp, nu_f):
    # α² − 1 = (1 − 2ν_f)(1 + 2ν_f)/(2ν_f)², factored so ω has no cancellation near ν_f = 1/2.
    return 1 / (2 * nu_f), xp.sqrt(abs((1 - 2 * nu_f) * (1 + 2 * nu_f))) / (2 * nu_f)


def _cos_sin(xp, nu_f, t, omega):
    """C(t), S(t) solving f'' = (α² − 1) f, C(0) = 1, C'(0) = 0, S(0) = 0, S'(0) = 1.

    cos ωt, sin(ωt)/ω for ν_f > 1/2; cosh ωt, sinh(ωt)/ω for ν_f < 1/2; 1, t at ν_f = 1/2.
    """
    if xp is not _Numpy:  # scalars: take the branch, never divide by ω = 0
        if nu_f > 0.5:
            return mpmath.cos(omega * t), mpmath.sin(omega * t) / omega
        if nu_f < 0.5:
            return mpmath.cosh(omega * t), mpmath.sinh(omega * t) / omega
        return mpmath.mpf(1), t
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        wt = omega * t
        c = np.where(nu_f > 0.5, np.cos(wt), np.where(nu_f < 0.5, np.cosh(wt), 1 + 0 * t))
        s = np.where(nu_f > 0.5, np.sin(wt) / omega, np.where(nu_f < 0.5, np.sinh(wt) / omega, t))
    return c, s


def _check_nu_f(nu_f, need: str):
    _require(nu_f > 0, "nu_f", nu_f, "must be positive", "give nu_f > 0")
    if need == "creep":
        _require(nu_f > 0.5, "nu_f", nu_f, "is not in the creep regime (Eqs. 7-10 need nu_f > 1/2)",
                 "use nu_f > 1/2, or the alpha >= 1 forms (Eq. 11 onwards) for nu_f <= 1/2")
    elif need == "stick-slip":
        _require(nu_f <= 0.5, "nu_f", nu_f, "is not in the stick-slip regime (this form needs nu_f <= 1/2)",
                 "use nu_f <= 1/2, or the creep forms (Eqs. 7-10) for nu_f > 1/2")
    elif need == "strict":
        _require(nu_f < 0.5, "nu_f", nu_f, "must be below 1/2 (Eq. 13 diverges at alpha = 1)",
                 "use nu_f < 1/2")


# -- the parameters ----------------------------------------------------------------------------------
def alpha(nu_f):
    r"""Negative damping of the linearised law, :math:`\alpha = 1/(2\nu_f)` (after Eq. 6)."""
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "any")
    return xp.out(1 / (2 * nu_f))


def omega(nu_f):
    r"""Frequency/rate :math:`\omega = \sqrt{|\alpha^2 - 1|}` (after Eqs. 7 and 11).

    Computed as :math:`\sqrt{|(1 - 2\nu_f)(1 + 2\nu_f)|}/(2\nu_f)`, exact to rounding near ν_f = 1/2.
    """
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "any")
    return xp.out(_alpha_omega(xp, nu_f)[1])


# -- the linear regime, Eqs. (6)-(11) ----------------------------------------------------------------
def _displacement(xp, t, nu, nu_f):
    a, w = _alpha_omega(xp, nu_f)
    c, s = _cos_sin(xp, nu_f, t, w)
    with np.errstate(over="ignore", invalid="ignore"):
        return nu * (xp.exp(a * t) * ((2 * a * a - 1) * s - 2 * a * c) + t + 2 * a)


def displacement_creep(t, nu, nu_f):
    r"""Eq. (7): the solution of Eq. (6) for ν_f > 1/2 (α < 1, ω = √(1 − α²)).

    .. math:: U(t) = \nu\left\{e^{\alpha t}\left[\frac{2\alpha^2 - 1}{\omega}\sin\omega t
              - 2\alpha\cos\omega t\right] + t + 2\alpha\right\}.

    Exact while U̇ ≤ ν_f. In float64 the bracket cancels at small t (U ≈ νt³/6): pass mpmath numbers
    for relative accuracy there.
    """
    xp, (t, nu, nu_f) = _ops(t, nu, nu_f)
    _check_nu_f(nu_f, "creep")
    return xp.out(_displacement(xp, t, nu, nu_f))


def displacement_linear(t, nu, nu_f):
    r"""Eq. (11): the solution of Eq. (6) for ν_f ≤ 1/2 (α ≥ 1, ω = √(α² − 1)).

    .. math:: U(t) = \nu\left\{e^{\alpha t}\left[\frac{2\alpha^2 - 1}{\omega}\sinh\omega t
              - 2\alpha\cosh\omega t\right] + t + 2\alpha\right\},

    and at α = 1 its limit :math:`\nu[e^t(t - 2) + t + 2]`. Valid until U̇ first reaches ν_f.
    """
    xp, (t, nu, nu_f) = _ops(t, nu, nu_f)
    _check_nu_f(nu_f, "stick-slip")
    return xp.out(_displacement(xp, t, nu, nu_f))


def velocity_linear(t, nu, nu_f):
    r"""U̇ of Eqs. (7) and (11), for any ν_f (the time derivative of the solution of Eq. 6).

    .. math:: \dot U(t) = \nu\{1 + e^{\alpha t}[\alpha S(t) - C(t)]\},

    with C, S = cos ωt, sin(ωt)/ω (ν_f > 1/2); cosh ωt, sinh(ωt)/ω (ν_f < 1/2); 1, t (ν_f = 1/2).
    """
    xp, (t, nu, nu_f) = _ops(t, nu, nu_f)
    _check_nu_f(nu_f, "any")
    a, w = _alpha_omega(xp, nu_f)
    c, s = _cos_sin(xp, nu_f, t, w)
    with np.errstate(over="ignore", invalid="ignore"):
        return xp.out(nu * (1 + xp.exp(a * t) * (a * s - c)))


def max_velocity_creep(nu, nu_f):
    r"""Eq. (8): the largest velocity of the creep cycle, reached at ωt = π,

    .. math:: \dot U_{\max} = \nu\,(1 + e^{\pi\alpha/\omega}).

    The linear solution (and so every creep formula) holds while this stays ≤ ν_f.
    """
    xp, (nu, nu_f) = _ops(nu, nu_f)
    _check_nu_f(nu_f, "creep")
    a, w = _alpha_omega(xp, nu_f)
    with np.errstate(over="ignore"):
        return xp.out(nu * (1 + xp.exp(xp.pi * a / w)))


def stop_time_creep(nu_f):
    r"""Eq. (9): the stop time t0 of a creep cycle (independent of ν), the root in (π/ω, 2π/ω) of

    .. math:: \frac{\alpha}{\omega}\sin\omega t - \cos\omega t + e^{-\alpha t} = 0

    (the OCR prints "α/w"). With cos φ = α, sin φ = ω and ωt = π + φ + ψ this is
    sin ψ = ω exp[−α(π + φ + ψ)/ω], whose left side increases and right side decreases on
    ψ ∈ [0, π/2): one root, found by bisection and Newton (float64) or ``findroot`` (mpmath).
    """
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "creep")
    a, w = _alpha_omega(xp, nu_f)
    phi = xp.atan2(w, a)

    def h(psi):
        return xp.sin(psi) - w * xp.exp(-a * (xp.pi + phi + psi) / w)

    def dh(psi):
        return xp.cos(psi) + a * xp.exp(-a * (xp.pi + phi + psi) / w)

    if xp is _Numpy:
        lo, hi = np.zeros_like(nu_f), np.full_like(nu_f, np.pi / 2)
        for _ in range(60):
            mid = (lo + hi) / 2
            up = h(mid) > 0
            lo, hi = np.where(up, lo, mid), np.where(up, mid, hi)
        psi = (lo + hi) / 2
        for _ in range(2):
            psi = psi - h(psi) / dh(psi)
    else:
        psi = mpmath.findroot(h, (mpmath.mpf(0), xp.pi / 2), solver="anderson")
        psi = psi - h(psi) / dh(psi)
    return xp.out((xp.pi + phi + psi) / w)


def creep_coefficient(nu_f):
    r"""Δ/ν of a creep cycle (Eq. 10, corrected), independent of ν:

    .. math:: \frac{\Delta}{\nu} = \sqrt{e^{2\alpha t_0} - \omega^2} + t_0 + \alpha.

    The paper prints −α (see ``ERRATA``): at t0, e^{αt0}[(α/ω) sin ωt0 − cos ωt0] = −1 turns Eq. (7)
    into Δ = ν(t0 − e^{αt0} sin(ωt0)/ω), and z = e^{αt0} sin(ωt0)/ω solves z² + 2αz + 1 − e^{2αt0} = 0
    with z < 0, so z = −α − √(e^{2αt0} − ω²).
    """
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "creep")
    a, w = _alpha_omega(xp, nu_f)
    t0 = stop_time_creep(nu_f)
    with np.errstate(over="ignore"):
        growth = xp.exp(a * t0)
        return xp.out(growth * xp.sqrt(1 - (w / growth) ** 2) + t0 + a)


def delta_creep(nu, nu_f):
    r"""Eq. (10), corrected: the slip of a creep cycle,

    .. math:: \Delta = \nu\left(\sqrt{e^{2\alpha t_0} - \omega^2} + t_0 + \alpha\right),

    exact for the piecewise-linear law as long as Eq. (8) stays ≤ ν_f (the printed −α is an erratum).
    """
    xp, (nu, nu_f) = _ops(nu, nu_f)
    return xp.out(nu * creep_coefficient(nu_f))


# -- stick-slip: the ν → 0 limit, Eqs. (13)-(18) -------------------------------------------------------
def creep_time_asymptotic(nu, nu_f):
    r"""Eq. (13): the creep time t1 (U̇(t1) = ν_f; the OCR reads U(t1)) as ν → 0, for ν_f < 1/2,

    .. math:: t_1 = (\alpha - \omega)\ln\left[\frac{\omega(\alpha + \omega)}{\alpha\nu}\right],

    from the fast mode of Eq. (11) alone, U̇ ≈ ν(α − ω)/(2ω) e^{(α+ω)t}. The error vanishes as ν → 0.
    """
    xp, (nu, nu_f) = _ops(nu, nu_f)
    _check_nu_f(nu_f, "strict")
    a, w = _alpha_omega(xp, nu_f)
    return xp.out((a - w) * xp.log(w * (a + w) / (a * nu)))


def _fast_mode(xp, tau, nu_f, a, w):
    """Eq. (14), ν_f(α − ω) e^{(α+ω)τ}."""
    with np.errstate(over="ignore"):
        return nu_f * (a - w) * xp.exp((a + w) * tau)


def _tau1(xp, a, w):
    """Eq. (16), 2 arctan(α + ω)."""
    return 2 * xp.atan(a + w)


def _log1p_ratio(xp, x):
    """log(1 + x)/x with its limit 1 at x = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return xp.where(x == 0, 1 + 0 * x, xp.log1p(x) / xp.where(x == 0, 1 + 0 * x, x))


def _tau2(xp, a, w):
    """Eq. (17), τ1 + ln(1 + ω/α)/(2ω), written as τ1 + [ln(1 + x)/x]/(2α), x = ω/α (finite at ω = 0)."""
    return _tau1(xp, a, w) + _log1p_ratio(xp, w / a) / (2 * a)


def displacement_limit_linear(tau, nu_f):
    r"""Eq. (14): the ν → 0 motion before the slip, τ = t − t1 ≤ 0, for ν_f ≤ 1/2,

    .. math:: U(\tau) = \nu_f(\alpha - \omega)\,e^{(\alpha + \omega)\tau}.

    The orbit leaving the fixed point along the fast eigen-direction; U̇(0) = ν_f.
    """
    xp, (tau, nu_f) = _ops(tau, nu_f)
    _check_nu_f(nu_f, "stick-slip")
    a, w = _alpha_omega(xp, nu_f)
    return xp.out(_fast_mode(xp, tau, nu_f, a, w))


def tau1(nu_f):
    r"""Eq. (16): the end of the frictionless swing, :math:`\tau_1 = 2\arctan(\alpha + \omega)`.

    At τ1, sin τ1 = 1/α and cos τ1 = −ω/α.
    """
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "stick-slip")
    a, w = _alpha_omega(xp, nu_f)
    return xp.out(_tau1(xp, a, w))


def tau2(nu_f):
    r"""Eq. (17): the stop, :math:`\tau_2 = \tau_1 + \frac{1}{2\omega}\ln(1 + \omega/\alpha)`.

    The last piece stops where tanh ω(τ − τ1) = ω/(2α + ω); at ν_f = 1/2 the limit τ1 + 1/2.
    """
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "stick-slip")
    a, w = _alpha_omega(xp, nu_f)
    return xp.out(_tau2(xp, a, w))


def displacement_limit_piecewise_linear(tau, nu_f):
    r"""Eqs. (14)–(15), corrected: the ν → 0 slip of the piecewise-linear law (12), ν_f ≤ 1/2.

    .. math::
        U(\tau) = \begin{cases}
        \nu_f(\alpha - \omega)e^{(\alpha+\omega)\tau} & \tau \le 0,\\
        \nu_f[\sin\tau - (\alpha + \omega)\cos\tau + 2\alpha] & 0 \le \tau \le \tau_1,\\
        \nu_f e^{\alpha(\tau-\tau_1)}[(3\alpha + \omega)\cosh\omega(\tau-\tau_1)
          - (\alpha + 3\omega + 2/\omega)\sinh\omega(\tau-\tau_1)] & \tau_1 \le \tau \le \tau_2,\\
        \Delta_0 & \tau \ge \tau_2 \ \text{(stuck)}.
        \end{cases}

    The paper prints "+1" for "+2α" in the middle piece (``ERRATA``): ν_f·2α = 1, so the printed form
    is right only with the 1 outside the bracket. At ν_f = 1/2 the third piece is e^{s}(3 − 2s)/2.
    """
    xp, (tau, nu_f) = _ops(tau, nu_f)
    _check_nu_f(nu_f, "stick-slip")
    a, w = _alpha_omega(xp, nu_f)
    t1, t2 = _tau1(xp, a, w), _tau2(xp, a, w)
    s = xp.where(tau < t2, tau, t2) - t1
    c, sn = _cos_sin(xp, nu_f, s, w)
    before = _fast_mode(xp, xp.where(tau < 0, tau, 0 * tau), nu_f, a, w)
    swing = nu_f * (xp.sin(tau) - (a + w) * xp.cos(tau) + 2 * a)
    last = nu_f * xp.exp(a * s) * ((3 * a + w) * c - (a * w + 3 * w * w + 2) * sn)
    return xp.out(xp.where(tau <= 0, before, xp.where(tau <= t1, swing, last)))


def delta0_piecewise_linear(nu_f):
    r"""Eq. (18): the ν → 0 slip of the piecewise-linear law (12),

    .. math:: \Delta_0 = \left(1 + \frac{\omega}{\alpha}\right)^{\frac12\left(1 + \frac{\alpha}{\omega}\right)}
              \ (\nu_f \le 1/2), \qquad \Delta_0 = 0 \ (\nu_f > 1/2).

    At ν_f = 1/2 the limit √e ≈ 1.6487 (evaluated as exp[(ln(1+x) + ln(1+x)/x)/2], x = ω/α); Δ0 → 2
    as ν_f → 0. The jump from √e to 0 at ν_f = 1/2 is the paper's first-order transition.
    """
    xp, (nu_f,) = _ops(nu_f)
    _check_nu_f(nu_f, "any")
    a, w = _alpha_omega(xp, nu_f)
    x = w / a
    value = xp.exp((xp.log1p(x) + _log1p_ratio(xp, x)) / 2)
    return xp.out(xp.where(nu_f <= 0.5, value, 0 * value))
