"""Cycles of period n (fixed points of the n-th return map), the period-doubling cascade, and where a
torus (Neimark–Sacker) bifurcation could occur.

A period-n cycle is a fixed point of Pⁿ, P the return map on the section V = V_lp
(``continuation.ReturnMap``). ``continue_period_n`` continues one in κ = k/k_c with the same
pseudo-arclength predictor–corrector as the period-1 branches (``continuation._arclength``; residual
Pⁿ(w) − w, Floquet multipliers the eigenvalues of ∂Pⁿ/∂w by central differences), so a multiplier of
Pⁿ crossing −1 is flagged as on any branch; ``locate_doubling`` finds that crossing by the secant
method on μ_min(κ) + 1 (each cycle by Newton at fixed κ) and switches to the period-2n cycle through
w_PD + ε v (v the eigenvector of −1), κ free (Kuznetsov 2004, §10.3).

Torus: a Neimark–Sacker bifurcation needs a complex pair of multipliers crossing the unit circle. With
the state dimension n_s the section has n_s − 1 coordinates, so ∂P/∂w has n_s − 1 multipliers: a
planar flow (one state variable, quasi-static) has one multiplier and neither a period doubling nor a
torus; with three state dimensions (one state variable with inertia, or two state variables
quasi-static) the two multipliers can be a complex pair, whose modulus is then √|det ∂P/∂w| =
exp(½ ∮ div f dt) (Liouville). ``torus_scan`` reports, along a branch, where the pair is complex and
its modulus: a torus needs that modulus to reach 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .continuation import Branch, BranchPoint, ReturnMap, _arclength, _jac, _newton, _NoReturn

__all__ = ["Cascade", "Doubling", "TorusScan", "cascade", "crossings", "continue_period_n", "locate_doubling", "torus_scan"]


def _map_n(pmap, k_c, n):
    """(w, κ) → (Pⁿ(w), total time, max ln V, min ln V), or raise _NoReturn."""
    def f(w, kappa):
        tot, top, bot = 0.0, -math.inf, math.inf
        for _ in range(n):
            r = pmap(w, kappa * k_c)
            if r is None:
                raise _NoReturn
            w, tot, top, bot = r[0], tot + r[1], max(top, r[2]), min(bot, r[3])
        return w, tot, top, bot
    return f


def continue_period_n(parent: Branch, w, kappa: float, n: int, *, points: int = 30, step: float = 0.01,
                      max_step: float = 0.05, kappa_range=(0.05, 20.0), max_steps: int = 500_000,
                      fix: int | None = None) -> Branch:
    """The branch of period-``n`` cycles through (w, κ) (a fixed point of Pⁿ), continued in κ.

    Each point's ``period`` is the time of the n returns, its ``multipliers`` those of Pⁿ. The first
    step goes towards smaller κ (the doubling cascades of the slider run that way); ``folds`` and
    ``period_doublings`` index the branch as in ``continue_cycles``. The first cycle is solved with κ
    fixed, or with w[``fix``] fixed: next to a doubling the new branch is a parabola in κ (P²ⁿ has a
    multiplier near 1 there, and Newton at fixed κ is nearly singular), transverse in w.
    """
    spec, k_c, v_lp = parent.spec, parent.hopf.k_c, parent.v_lp
    pmap = ReturnMap(spec, v_lp, t_max=1e4 * 2 * math.pi / parent.hopf.omega_c, max_steps=max_steps)
    f = _map_n(pmap, k_c, n)
    m = len(w)
    weights = np.ones(m + 1)

    def G(X):
        return f(X[:m], X[m])[0] - X[:m]

    def newton(X, extra, extra_grad):
        return _newton(G, X, weights, m, extra, extra_grad)

    def point(X, J, ok):
        r = f(X[:m], X[m])
        mult = np.linalg.eigvals(J[:, :m] + np.eye(m))
        return BranchPoint(float(X[m]), float(X[m] * k_c), r[1], tuple(X[:m]), r[2], r[3], float(v_lp) * r[1],
                           tuple(complex(z) for z in mult), float(np.max(np.abs(r[0] - X[:m]))),
                           "ok" if ok else "no-convergence")

    X = np.append(np.asarray(w, dtype=float), float(kappa))
    j = m if fix is None else fix
    grad = np.zeros(m + 1)
    grad[j] = 1.0
    X, J, ok = newton(X, lambda Y, x0=float(X[j]): Y[j] - x0, grad)
    out = [point(X, J, ok)]
    _, _, vt = np.linalg.svd(J)
    tau = vt[-1] if vt[-1][m] < 0 else -vt[-1]     # towards smaller κ

    def leaves(X, p):
        if not kappa_range[0] < X[m] < kappa_range[1]:
            return f"left the range at κ = {X[m]:.6g} (κ in {tuple(kappa_range)})"
        return None

    folds, pds, stop = _arclength(X, tau, out, newton, point, weights, m, step=step, max_step=max_step,
                                  points=points, leaves=leaves, failure=lambda: pmap.last_failure,
                                  where=lambda X: f"κ = {X[m]:.6g}")
    return Branch(spec, float(v_lp), parent.hopf, tuple(out), tuple(folds), tuple(pds),
                  {"stop": stop, "period_multiple": n})


@dataclass(frozen=True)
class Doubling:
    """A multiplier −1 of Pⁿ located on a period-n branch, and the period-2n cycle beside it."""

    n: int                       # the period multiple of the branch it is on
    kappa: float                 # where a multiplier of Pⁿ is −1
    multiplier: float            # that multiplier at the located κ
    period: float                # the period-n cycle's period (n returns) there
    w: tuple
    kappa_2: float               # the period-2n cycle's κ (beyond the doubling by ε along v)
    w_2: tuple
    period_2: float              # its period (2n returns)
    multipliers_2: tuple         # its multipliers (of P²ⁿ)
    residual_2: float            # max |P²ⁿ(w) − w|
    status: str = "ok"           # "ok", or "not-switched": the Newton of the switch landed elsewhere

    @property
    def period_ratio(self) -> float:
        return self.period_2 / self.period


def locate_doubling(branch: Branch, index: int, *, beyond: float = 1e-3, max_steps: int = 500_000) -> Doubling:
    """The doubling flagged between ``branch.points[index]`` and ``[index + 1]`` of a period-n branch."""
    import mpmath as mp

    n = branch.meta.get("period_multiple", 1)
    spec, k_c = branch.spec, branch.hopf.k_c
    pmap = ReturnMap(spec, branch.v_lp, t_max=1e4 * 2 * math.pi / branch.hopf.omega_c, max_steps=max_steps)
    f = _map_n(pmap, k_c, n)
    m = len(branch.points[index].w)

    def jac(fun, w):
        return _jac(fun, w, 1e-7 * np.maximum(np.abs(w), 1.0))[1]

    def cycle(w, kappa):
        w = np.array(w, dtype=float)
        for _ in range(12):
            dw = np.linalg.solve(jac(lambda u: f(u, kappa)[0], w) - np.eye(m), f(w, kappa)[0] - w)
            w = w - dw
            if np.max(np.abs(dw)) < 1e-13 * max(1.0, np.max(np.abs(w))):
                break
        return w, np.linalg.eig(jac(lambda u: f(u, kappa)[0], w))

    a, b = branch.points[index], branch.points[index + 1]
    state = {}

    def mu_plus_one(kappa):
        t = (kappa - a.kappa) / (b.kappa - a.kappa)
        w, (mult, _) = cycle(np.array(a.w) + t * (np.array(b.w) - np.array(a.w)), kappa)
        state["w"] = w
        return min(z.real for z in mult if abs(z.imag) < 1e-9) + 1

    with mp.workdps(20):
        kappa_pd = float(mp.findroot(lambda x: mu_plus_one(float(x)), (a.kappa, b.kappa), solver="anderson",
                                     tol=1e-26, verify=False))
    w_pd, (mult, vecs) = cycle(state["w"], kappa_pd)
    j = int(np.argmin([z.real if abs(z.imag) < 1e-9 else np.inf for z in mult]))
    v = np.real(vecs[:, j])
    v /= np.linalg.norm(v)

    def G(X):
        w, kappa = X[:m], X[m]
        return np.append(f(f(w, kappa)[0], kappa)[0] - w, v @ (w - w_pd) - beyond)

    X = np.append(w_pd + beyond * v, kappa_pd)
    for _ in range(30):
        h = 1e-7 * np.maximum(np.abs(X), 1.0)
        J = np.array([(G(X + e) - G(X - e)) / (2 * hj) for hj, e in zip(h, np.diag(h))]).T
        dX = np.linalg.solve(J, G(X))
        X = X - dX
        if np.max(np.abs(dX)) < 1e-13 * max(1.0, np.max(np.abs(X))):
            break
    w2, kappa_2 = X[:m], float(X[m])
    r1 = f(w2, kappa_2)
    r2 = f(r1[0], kappa_2)
    mult2 = np.linalg.eigvals(jac(lambda u: f(f(u, kappa_2)[0], kappa_2)[0], w2))
    period = f(w_pd, kappa_pd)[1]
    # a period-2n cycle next to the doubling: twice the period (to the distance moved) and a κ that
    # moved by a fraction of the branch's step, not a cycle of another branch Newton fell onto
    step = abs(b.kappa - a.kappa)
    switched = abs((r1[1] + r2[1]) / period - 2) < 1e-2 and abs(kappa_2 - kappa_pd) < step
    return Doubling(n, kappa_pd, float(min(z.real for z in mult if abs(z.imag) < 1e-9)), period,
                    tuple(w_pd), kappa_2, tuple(w2), r1[1] + r2[1], tuple(complex(z) for z in mult2),
                    float(np.max(np.abs(r2[0] - w2))), "ok" if switched else "not-switched")


def crossings(multipliers, tol: float = 1e-9, noise: float = 1e-6) -> list:
    """Where a sequence of multiplier sets (one per branch point) crosses the unit circle, and how.

    Returns (i, kind) for each crossing between points i and i + 1: ``"fold"`` (a real multiplier through
    +1), ``"period-doubling"`` (a real one through −1), ``"torus"`` (a complex pair, |Im μ| > ``tol`` on
    both sides, whose modulus passes 1). Multipliers are matched between points by sorting: real ones by
    value, a complex pair by modulus — enough on a branch stepped finely compared with their motion.
    A crossing within ``noise`` of the circle on both sides is not counted: on a neutral family (the
    degenerate quasi-static Hopf points) the multiplier is 1 to ~1e-8 of finite-difference noise.
    """
    out = []
    for i, (m0, m1) in enumerate(zip(multipliers, multipliers[1:])):
        r0 = sorted(z.real for z in m0 if abs(z.imag) <= tol)
        r1 = sorted(z.real for z in m1 if abs(z.imag) <= tol)
        def through(u, v, at):
            return (u - at) * (v - at) < 0 and max(abs(u - at), abs(v - at)) > noise

        if any(through(x, y, 1.0) for x, y in zip(r0[::-1], r1[::-1])):
            out.append((i, "fold"))
        if r0 and r1 and through(min(r0), min(r1), -1.0):
            out.append((i, "period-doubling"))
        c0 = [abs(z) for z in m0 if abs(z.imag) > tol]
        c1 = [abs(z) for z in m1 if abs(z.imag) > tol]
        if c0 and c1 and through(max(c0), max(c1), 1.0):
            out.append((i, "torus"))
    return out


@dataclass(frozen=True)
class TorusScan:
    """Where along a branch the two multipliers form a complex pair, and how far from the unit circle."""

    dimension: int               # number of nontrivial multipliers (section dimension)
    complex_points: tuple        # indices with a complex pair
    max_complex_modulus: float   # largest |μ| over those (a torus needs 1); NaN if none
    modulus_range: tuple         # (min, max) of √|det ∂P/∂w| over the branch: the pair's modulus if complex
    crossing: tuple              # indices i where a complex pair's |μ| − 1 changes sign between i and i + 1
    kinds: tuple = ()            # every crossing of the circle on the branch, (i, kind) from ``crossings``


def torus_scan(branch: Branch) -> TorusScan:
    """Complex pairs of multipliers along ``branch`` and their distance to the unit circle."""
    pts = branch.points
    dim = len(pts[0].multipliers)
    cplx = [i for i, p in enumerate(pts) if any(abs(z.imag) > 1e-9 for z in p.multipliers)]
    mods = [max(abs(z) for z in pts[i].multipliers) for i in cplx]
    # with one multiplier there is no pair: the "modulus of a pair" is undefined (NaN)
    dets = [math.sqrt(abs(np.prod(p.multipliers))) if dim > 1 else math.nan for p in pts]
    kinds = tuple(crossings([p.multipliers for p in pts]))
    cross = tuple(i for i, kind in kinds if kind == "torus")
    return TorusScan(dim, tuple(cplx), max(mods) if mods else math.nan, (min(dets), max(dets)), cross, kinds)


#: noise of a multiplier from central differences of Pⁿ (see ``cascade``)
MU_NOISE = 1e-7


@dataclass(frozen=True)
class Cascade:
    """A period-doubling cascade: the branches of period 1, 2, 4, … and the located doublings."""

    branches: dict               # period multiple n → Branch
    doublings: tuple             # Doubling, in order (period 1 → 2, 2 → 4, …)
    kappa_errors: tuple          # max(|μ + 1|, MU_NOISE) / |dμ/dκ| at each doubling (dμ/dκ from its bracket)
    ratios: tuple                # (κ_i − κ_{i+1}) / (κ_{i+1} − κ_{i+2})
    ratio_errors: tuple          # propagated from kappa_errors
    seconds: float
    loop_maxima: dict = None     # n → per point, the max of ln V over each of its n loops (the figure's)


def _slope(branch, index) -> float:
    a, b = branch.points[index], branch.points[index + 1]

    def mu(p):
        return min(z.real for z in p.multipliers if abs(z.imag) < 1e-9)
    return (mu(b) - mu(a)) / (b.kappa - a.kappa)


def _loop_maxima(branch, n) -> tuple:
    """Per branch point, max ln V over each of the n returns (n values: the classic cascade picture)."""
    pmap = ReturnMap(branch.spec, branch.v_lp, t_max=1e4 * 2 * math.pi / branch.hopf.omega_c, max_steps=500_000)
    out = []
    for p in branch.points:
        w, tops = np.array(p.w), []
        for _ in range(n):
            r = pmap(w, p.k)
            if r is None:
                break
            w = r[0]
            tops.append(r[2])
        out.append(tuple(tops))
    return tuple(out)


def cascade(parent: Branch, levels: int = 4, *, points: int = 25, step: float = 0.002, max_step: float = 0.02,
            shrink: float = 4.7) -> Cascade:
    """Follow the doublings of ``parent`` (a period-1 branch with a flagged doubling) ``levels`` deep.

    Each period-2n branch starts at the cycle switched onto at the previous doubling and is continued
    towards smaller κ with steps ``shrink`` times smaller per level (the doublings crowd together);
    the first doubling flagged on it is located. Stops early where a branch flags none.
    """
    import time

    t0 = time.perf_counter()
    if not parent.period_doublings:
        raise ValueError("the branch flags no period doubling")
    branches = {1: parent}
    doublings, errors = [], []
    b, i = parent, parent.period_doublings[0]
    for level in range(levels):
        # the period-2n cycle's distance from the period-n one shrinks like Feigenbaum's α ≈ 2.5 per
        # doubling: at a fixed ε = 1e-3 the fifth switch fell onto another branch (period ratio 1.79)
        d = locate_doubling(b, i, beyond=1e-3 / 2.5 ** level)
        doublings.append(d)
        # μ comes from central differences of Pⁿ: its noise, not |μ + 1| at the root, bounds κ. Two runs
        # whose period-n branches started differently put κ_PD up to 5.4e-11 apart; a floor of 1e-7 on
        # |μ + 1| over the slope gives that spread (6.6e-11 at the third doubling)
        errors.append(max(abs(d.multiplier + 1), MU_NOISE) / abs(_slope(b, i)))
        if level == levels - 1 or d.status != "ok":
            break
        fix = int(np.argmax(np.abs(np.subtract(d.w_2, d.w))))
        b = continue_period_n(parent, d.w_2, d.kappa_2, 2 * d.n, points=points, step=step / shrink ** level,
                              max_step=max_step / shrink ** level, fix=fix)
        branches[2 * d.n] = b
        if not b.period_doublings:
            break
        i = b.period_doublings[0]
    ks = [d.kappa for d in doublings]
    ratios, rerr = [], []
    for j in range(len(ks) - 2):
        d1, d2 = ks[j] - ks[j + 1], ks[j + 1] - ks[j + 2]
        ratios.append(d1 / d2)
        e1, e2 = errors[j] + errors[j + 1], errors[j + 1] + errors[j + 2]
        rerr.append(abs(d1 / d2) * (e1 / abs(d1) + e2 / abs(d2)))
    maxima = {n: _loop_maxima(b, n) for n, b in branches.items()}
    return Cascade(branches, tuple(doublings), tuple(errors), tuple(ratios), tuple(rerr), time.perf_counter() - t0,
                   maxima)
