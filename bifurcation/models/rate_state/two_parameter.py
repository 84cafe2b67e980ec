"""Two-parameter continuation of the Hopf point: Hopf curves k_c(p) and Bautin points (l1 = 0).

A Hopf curve is continued in a second parameter p — ``"eta"`` (the normalised mass M V²/(a Dc)),
``"b_over_a"`` or ``"damping"`` (radiation damping η) — from point to point: at each p the root of
Re λ_max(A(k; p)) = 0 (``hopf._max_real``: ``mpmath.eig`` of the Jacobian of the engine's own
right-hand side) by the secant method started from the previous point's k_c and the secant
prediction through the last two (a natural-parameter predictor–corrector; no closed form used).
``closed_form_k_c`` gives the independent check (docs/rate-state.md):
k_c = (b − a − ηV)/Dc · [1 + M V²/((a + ηV) Dc)].

A Bautin point is where the first Lyapunov coefficient l1 (Kuznetsov's formula, ``hopf._lyapunov``)
changes sign along the curve: ``bautin_point`` solves l1(p) = 0 by the secant method (Newton with a
difference derivative) from a bracket found on a scan, and reports both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath as mp

from .hopf import _max_real, hopf_point
from .spec import SliderSpec

__all__ = ["FoldPoint", "HopfCurve", "PeriodDoubling", "bautin_point", "closed_form_k_c", "fold_curve", "hopf_curve",
           "period_doubling"]

PARAMETERS = ("eta", "b_over_a", "damping")


@dataclass(frozen=True)
class HopfCurve:
    parameter: str
    values: tuple
    k_c: tuple
    k_c_closed_form: tuple
    max_rel_dev: float


def _slider(parameter, p, *, state_law, a, b, dc, v_lp, eta, damping):
    """(SliderSpec at k = 1, V_lp) for the parameter value p (the others fixed)."""
    if parameter == "eta":
        eta = p
    elif parameter == "b_over_a":
        b = p * a
    elif parameter == "damping":
        damping = p
    else:
        raise ValueError(parameter)
    mass = None if eta == 0 else eta * a * dc / v_lp ** 2
    return SliderSpec(a=a, b=b, dc=dc, state_law=state_law, k=1.0, mass=mass, damping=damping)


def closed_form_k_c(spec: SliderSpec, v_lp) -> mp.mpf:
    """k_c = (b − a')/Dc · [1 + M V²/(a' Dc)], a' = a + ηV (one state variable; docs/rate-state.md)."""
    v = mp.mpf(v_lp)
    ap = mp.mpf(spec.a) + mp.mpf(spec.damping) * v
    dc = mp.mpf(spec.dc[0])
    return (mp.mpf(spec.b[0]) - ap) / dc * (1 + mp.mpf(spec.mass or 0) * v * v / (ap * dc))


def _growth(spec, v_lp):
    def g(k):
        return mp.re(_max_real(spec, k, v_lp))
    return g


def hopf_curve(parameter: str, values, *, state_law="aging", a=0.01, b=0.015, dc=0.01, v_lp=1.0, eta=0.0,
               damping=0.0, dps: int = 40) -> HopfCurve:
    """k_c along ``values`` of ``parameter`` (module docstring), each with its closed-form check."""
    if parameter not in PARAMETERS:
        raise ValueError(f"parameter {parameter!r}: use one of {PARAMETERS}")
    kw = dict(state_law=state_law, a=a, b=b, dc=dc, v_lp=v_lp, eta=eta, damping=damping)
    ks, cf = [], []
    with mp.workdps(dps):
        first = _slider(parameter, values[0], **kw)
        ks.append(mp.mpf(hopf_point(a=first.a, b=first.b, dc=first.dc, state_law=first.state_law, v_lp=v_lp,
                                    mass=first.mass, damping=first.damping, dps=dps, lyapunov=False).k_c))
        cf.append(closed_form_k_c(first, v_lp))
        for i, p in enumerate(values[1:], start=1):
            spec = _slider(parameter, p, **kw)
            guess = ks[-1] if i < 2 else ks[-1] + (ks[-1] - ks[-2]) * (mp.mpf(p) - values[i - 1]) / \
                (mp.mpf(values[i - 1]) - values[i - 2])
            ks.append(mp.findroot(_growth(spec, v_lp), (guess, guess * (1 + mp.mpf(1e-6))), solver="secant",
                                  tol=mp.mpf(10) ** (-dps + 6)))
            cf.append(closed_form_k_c(spec, v_lp))
        dev = max(abs(k / c - 1) for k, c in zip(ks, cf))
    return HopfCurve(parameter, tuple(float(v) for v in values), tuple(float(k) for k in ks),
                     tuple(float(c) for c in cf), float(dev))


def bautin_point(parameter: str, bracket, *, state_law="aging", a=0.01, b=0.015, dc=0.01, v_lp=1.0, eta=0.0,
                 damping=0.0, dps: int = 30, scan: int = 6) -> list:
    """The parameter values where l1 = 0 on the Hopf curve, by the secant method from scanned brackets.

    l1 is evaluated on a log-spaced scan of ``scan`` values over ``bracket``; every sign change between
    neighbours is refined by the secant method (Newton with a difference derivative) in ln p. Returns
    one dict per sign change: ``value``, ``bracket`` (the scan's neighbours), ``l1_at_value``,
    ``inside`` (whether the root stayed in its bracket). Empty when l1 keeps its sign on the scan.
    """
    kw = dict(state_law=state_law, a=a, b=b, dc=dc, v_lp=v_lp, eta=eta, damping=damping)

    def l1(p):
        s = _slider(parameter, float(p), **kw)
        return hopf_point(a=s.a, b=s.b, dc=s.dc, state_law=s.state_law, v_lp=v_lp, mass=s.mass, damping=s.damping,
                          dps=dps).lyapunov_coefficient

    lo, hi = bracket
    grid = [lo * (hi / lo) ** (i / (scan - 1)) for i in range(scan)]
    vals = [l1(g) for g in grid]
    out = []
    for g0, g1, v0, v1 in zip(grid, grid[1:], vals, vals[1:]):
        if v0 * v1 < 0:
            with mp.workdps(20):
                root = mp.findroot(lambda x: l1(mp.exp(x)), (math.log(g0), math.log(g1)), solver="secant", tol=1e-26)
            value = math.exp(float(root))
            out.append({"value": value, "bracket": (g0, g1), "l1_at_value": l1(value), "inside": g0 < value < g1})
    return out


@dataclass(frozen=True)
class FoldPoint:
    """A fold of cycles (limit point of cycles): a cycle with a Floquet multiplier exactly 1."""

    eta: float                   # normalised mass M V²/(a Dc)
    kappa: float                 # k / k_c(η)
    k: float
    period: float
    w: tuple                     # section coordinates (ln θ[, z]) at V = V_lp, ẋ > 0
    ln_v_max: float
    ln_v_min: float
    multipliers: tuple           # nontrivial Floquet multipliers (one of them 1 at the fold)
    residual: float              # max |P(w) − w| at the converged point
    fold_residual: float         # |μ₁ − 1| (μ₁ from central differences: ~1e-10 of noise)
    status: str                  # "ok" or "no-convergence"


def fold_curve(etas, start_w, start_kappa, *, state_law="aging", a=0.01, b=0.015, dc=0.01, v_lp=1.0,
               damping=0.0, max_steps=200_000) -> list:
    """Folds of cycles continued in η = M V²/(a Dc): the curve that ends at a Bautin point.

    Unknowns X = (w, κ) at each η, equations F(X) = [P(w; κ k_c) − w; μ₁(∂P/∂w) − 1] (μ₁ the real
    multiplier nearest 1; ``continuation.ReturnMap`` for P, ∂P/∂w by central differences), solved by a
    Newton whose Jacobian (central differences of F) is formed at each iterate; the predictor is
    the previous fold (or the secant through the last two). ``start_w``, ``start_kappa``: a cycle near
    the fold at ``etas[0]`` (e.g. the point where ``continue_cycles`` flags a fold). The multiplier comes
    from central differences of P, so a fold is located to ~1e-9 in κ while the cycle there satisfies
    P(w) = w to rounding (``residual`` is max |P(w) − w|, ``fold_residual`` |μ₁ − 1|).
    """
    import numpy as np

    from .continuation import ReturnMap

    out, prev = [], []
    X = np.append(np.array(start_w, dtype=float), float(start_kappa))
    m = X.size - 1
    scale = np.ones(m + 1)
    scale[m - 1] = max(b - a, a)          # the net force z, in units of the friction drop
    for i, eta in enumerate(etas):
        mass = eta * a * dc / v_lp ** 2
        spec = SliderSpec(a=a, b=b, dc=dc, state_law=state_law, k=1.0, mass=mass, damping=damping)
        k_c = float(closed_form_k_c(spec, v_lp))
        pmap = ReturnMap(spec, v_lp, t_max=1e4 * dc / v_lp, max_steps=max_steps)
        if len(prev) >= 2:
            X = prev[-1] + (prev[-1] - prev[-2]) * (eta - etas[i - 1]) / (etas[i - 1] - etas[i - 2])

        def P(w, kappa):
            r = pmap(w, kappa * k_c)
            if r is None:
                raise RuntimeError(pmap.last_failure)
            return r

        def DP(w, kappa):
            # h = 1e-5: truncation ~h² and rounding ~1e-15/h balance near 1e-10 in μ₁
            h = 1e-5 * np.maximum(np.abs(w), scale[:m])
            cols = []
            for j in range(m):
                e = np.zeros(m)
                e[j] = h[j]
                cols.append((P(w + e, kappa)[0] - P(w - e, kappa)[0]) / (2 * h[j]))
            return np.array(cols).T

        def F(Y):
            w, kappa = Y[:m], Y[m]
            mult = np.linalg.eigvals(DP(w, kappa))
            near = mult[np.argmin(np.abs(mult - 1))]
            return np.append(P(w, kappa)[0] - w, near.real - 1)

        try:
            ok = False
            for _ in range(12):
                hY = 1e-6 * np.maximum(np.abs(X), scale)
                J = np.array([(F(X + e) - F(X - e)) / (2 * hj) for hj, e in zip(hY, np.diag(hY))]).T
                FX = F(X)
                dX = np.linalg.solve(J, FX)
                X = X - dX
                # μ₁ comes from central differences of P: ~1e-10 of noise, so the fold is located to
                # ~1e-9 in κ; the cycle itself (P(w) = w) is converged to rounding
                if np.max(np.abs(dX) / scale) < 1e-9 and np.max(np.abs(F(X)[:m]) / scale[:m]) < 1e-12:
                    ok = True
                    break
            w, kappa = X[:m], X[m]
            r = P(w, kappa)
            mult = np.linalg.eigvals(DP(w, kappa))
            FX = F(X)
            resid, fold_resid = float(np.max(np.abs(FX[:m]))), float(abs(FX[m]))
            # near the Bautin point dμ₁/dκ → 0 and the multiplier's noise moves κ by more than 1e-9 per
            # step: judged by what matters, a cycle to rounding with a multiplier within 1e-9 of 1
            ok = ok or (resid < 1e-12 * max(1.0, float(np.max(np.abs(X[:m])))) and fold_resid < 1e-9)
        except (RuntimeError, np.linalg.LinAlgError):
            break
        out.append(FoldPoint(float(eta), float(kappa), float(kappa * k_c), r[1], tuple(float(v) for v in w), r[2], r[3],
                             tuple(complex(z) for z in mult), resid, fold_resid, "ok" if ok else "no-convergence"))
        prev.append(X.copy())
    return out


@dataclass(frozen=True)
class PeriodDoubling:
    """A period doubling on a branch of cycles, and the period-2 cycle switched onto beside it."""

    kappa: float                 # k / k_c where a Floquet multiplier is −1
    multiplier: float            # that multiplier (−1 to the located precision)
    period: float                # the cycle's period there
    w: tuple
    kappa_2: float               # where the period-2 cycle was computed (beyond the doubling)
    w_2: tuple                   # its two section points
    period_2: float              # its period (two returns)
    multipliers_2: tuple         # Floquet multipliers of the period-2 cycle (of P∘P)
    residual_2: float            # max |P(P(w)) − w|


def period_doubling(branch, index: int, *, beyond: float = 1e-3, max_steps: int = 500_000) -> PeriodDoubling:
    """Locate the period doubling flagged between ``branch.points[index]`` and ``[index + 1]`` and switch.

    The cycle at fixed κ is Newton's fixed point of the return map P (``continuation.ReturnMap``, ∂P/∂w by
    central differences; regular at a period doubling, where only a multiplier −1 appears); κ_PD is the
    secant root of μ_min(κ) + 1 (μ_min the most negative real multiplier) between the two points. The
    period-2 cycle (branch switching): Newton on P(P(w; κ); κ) = w with v·(w − w_PD) = ε = ``beyond``
    (v the unit eigenvector of −1), κ free: the side on which it lies says whether the doubling is
    supercritical (a stable period-2 cycle where the cycle has lost its stability) or subcritical.
    """
    import numpy as np

    from .continuation import ReturnMap, _NoReturn
    from .doubling import locate_doubling

    try:   # the period-n locator and switch at n = 1 (doubling.py): one implementation of both
        d = locate_doubling(branch, index, beyond=beyond, max_steps=max_steps)
        pmap = ReturnMap(branch.spec, branch.v_lp, t_max=1e4 * 2 * math.pi / branch.hopf.omega_c,
                         max_steps=max_steps)
        image = pmap(np.asarray(d.w_2, dtype=float), d.kappa_2 * branch.hopf.k_c)
        if image is None:
            raise _NoReturn
    except _NoReturn:
        raise RuntimeError(f"the return map failed near the doubling between points {index} and {index + 1}") from None
    return PeriodDoubling(d.kappa, d.multiplier, d.period, d.w, d.kappa_2, (d.w_2, tuple(image[0])), d.period_2,
                          d.multipliers_2, d.residual_2)
