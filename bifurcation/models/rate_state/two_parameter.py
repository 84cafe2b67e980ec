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

__all__ = ["HopfCurve", "bautin_point", "closed_form_k_c", "hopf_curve"]

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
