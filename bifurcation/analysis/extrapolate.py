r"""Δ(ν → 0) from finite-ν data, with an honest uncertainty, compared with the direct limit and the paper.

Three regimes, each with the correction model its asymptotics give (docs/physics.md):

ν_f = 1/2 (α = 1, a Jordan block).
    The finite-ν orbit leaves the fixed point with a relative weight ε of the generalised eigenvector:
    the linear solution U = ν[(t − 2)e^t + t + 2] has U − U̇ ≈ −U̇/(t − 1) at velocity U̇. The ν = 0 flow
    has no resonances at eigenvalues (1, 1), so it is analytically linearisable, and
    Δ(ν) = Δ0 + a1 ε + a2 ε² + … + O(ν ln ν), with ε = 1/(τ − 1) and (τ − 1)e^τ = 1/(2ν), i.e.
    τ − 1 = W(1/(2eν)) (another reference velocity only reparametrises ε at O(ε²)). At ν = 1e-15,
    ε = 1/W(1/(2e·1e-15)) = 0.0339 (``critical_epsilon``): convergence is logarithmic. The O(ν) terms
    come from Δ = V_stop + ν t_stop with t_stop ≈ τ, so the model carries ν/ε and ν columns too.
    Polynomials of order 2…5 in ε over windows of the smallest ν; the estimate is the median of the
    ensemble, the uncertainty the largest deviation from it combined with the largest covariance
    error — model and window variation, not the covariance alone.
ν_f < 1/2.
    Δ = Δ0 + ν[(α − ω) ln(1/ν) + C0 + Kν^{−r} + …] (``period_fit``): the same ladder with Δ0 free.
ν_f > 1/2.
    Creep: Δ = ν·Δ/ν|₀ + O(ν²), so Δ0 = 0; fitted as a polynomial in ν over creep points (a check).

The paper's numbers: Eq. (18) for the piecewise-linear law at ν_f ≤ 1/2 (the limit √e at 1/2), and
"Δ = 0.17 at ν_f = 1/2" for Carlson–Langer (an extrapolation from ν ≥ 1e-9, text under Fig. 3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..engine import Status
from ..errors import InputError
from ._data import cycles_along_nu, match_nu_f
from ._lsq import lambert_w, linear_fit
from .period_fit import DEFAULT_RELATIVE_ERROR, DEFAULT_WINDOWS, direct_delta0, fit_ladder

__all__ = ["ExtrapolationResult", "ModelRow", "critical_epsilon", "extrapolate_delta", "paper_value"]

#: Paper's extrapolated Carlson–Langer slip at ν_f = 1/2 (text under Fig. 3 of PRL 76, 4865).
PAPER_CL_HALF = 0.17
#: Polynomial orders in ε and windows ν ≤ ν_max of the ensemble at ν_f = 1/2.
CRITICAL_ORDERS = (2, 3, 4, 5)
CRITICAL_WINDOWS = (1e-5, 1e-7, 1e-9)
_HALF_TOL = 1e-12


def critical_epsilon(nu) -> np.ndarray:
    """ε = 1/(τ − 1) with (τ − 1)e^τ = 1/(2ν): τ − 1 = W(1/(2eν)) (module docstring)."""
    return 1.0 / lambert_w(1.0 / (2 * math.e * np.asarray(nu, dtype=float)))


def paper_value(law: str, nu_f: float) -> tuple[float | None, str]:
    """The paper's Δ0 at (law, ν_f) and where it says so; (None, "") where it gives none."""
    if law == "piecewise-linear" and nu_f <= 0.5:
        from ..theory import delta0_piecewise_linear

        return float(delta0_piecewise_linear(nu_f)), "Eq. (18)"
    if law == "piecewise-linear" or (law == "carlson-langer" and nu_f > 0.5):
        return 0.0, "Eq. (18) / text: Δ → 0 for ν_f > 1/2"
    if law == "carlson-langer" and abs(nu_f - 0.5) < _HALF_TOL:
        return PAPER_CL_HALF, "text under Fig. 3: 'an extrapolation for ν → 0 shows … Δ = 0.17 at ν_f = 1/2'"
    return None, ""


@dataclass(frozen=True)
class ModelRow:
    """One model of the ensemble: its name, window, size, Δ0 estimate and fit quality."""

    model: str
    nu_max: float
    n_points: int
    delta0: float
    stderr: float
    residual_max: float


@dataclass(frozen=True)
class ExtrapolationResult:
    """Δ0 extrapolated from finite ν at (law, ν_f), with the direct limit and the paper's value.

    ``deviation`` = extrapolated − direct; ``consistent`` is |deviation| ≤ uncertainty (+ the direct
    value's own error). ``models`` is the ensemble; ``naive`` holds extrapolations the way one might
    have done them from ν ≥ 1e-9 (to show where a value like the paper's 0.17 comes from);
    ``nu_reaching_paper`` the ν at which the fitted model of Δ(ν) comes down to the paper's value (at
    ν_f = 1/2; None where it does not, or elsewhere).
    """

    law: str
    nu_f: float
    regime: str
    variable: str
    delta0_extrapolated: float
    uncertainty: float
    delta0_direct: float
    delta0_direct_error: float
    paper_value: float | None
    paper_source: str
    models: tuple
    nu: np.ndarray = field(repr=False)
    delta: np.ndarray = field(repr=False)
    curve: tuple = field(repr=False, default=())   # (x, Δ) of the model closest to the estimate
    naive: dict = field(default_factory=dict)
    nu_reaching_paper: float | None = None

    @property
    def deviation(self) -> float:
        return self.delta0_extrapolated - self.delta0_direct

    @property
    def consistent(self) -> bool:
        return bool(abs(self.deviation) <= self.uncertainty + self.delta0_direct_error)

    def summary(self) -> dict:
        """JSON-ready numbers (what `bifurcation extrapolate --json` prints)."""
        return {
            "law": self.law, "nu_f": self.nu_f, "regime": self.regime, "variable": self.variable,
            "delta0_extrapolated": self.delta0_extrapolated, "uncertainty": self.uncertainty,
            "delta0_direct": self.delta0_direct, "delta0_direct_error": self.delta0_direct_error,
            "paper_value": self.paper_value, "paper_source": self.paper_source or None,
            "deviation": self.deviation, "consistent": self.consistent,
            "n_points": int(self.nu.size), "nu_min": float(self.nu.min()), "nu_max": float(self.nu.max()),
            "models": [m.__dict__ for m in self.models], "naive": dict(self.naive),
        }


def _ensemble(rows):
    """Median of the models' Δ0, and the largest deviation from it ⊕ the largest covariance error."""
    values = np.array([r.delta0 for r in rows])
    centre = float(np.median(values))
    spread = float(np.max(np.abs(values - centre)))
    cov = max(r.stderr for r in rows)
    return centre, math.hypot(spread, cov)


def _critical(nu, delta, orders, windows):
    eps = critical_epsilon(nu)
    rows, fits = [], []
    for nu_max in windows:
        m = nu <= nu_max * (1 + 1e-9)
        for order in orders:
            cols = [eps[m] ** k for k in range(order + 1)] + [nu[m] / eps[m], nu[m]]
            if len(cols) > m.sum() - 3:
                continue
            f = linear_fit(cols, delta[m])
            rows.append(ModelRow(f"Δ0 + Σ_(k≤{order}) a_k ε^k + b ν/ε + c ν", nu_max, int(m.sum()),
                                 float(f.coef[0]), float(f.stderr[0]), float(np.max(np.abs(f.residuals)))))
            fits.append((order, f.coef, float(eps[m].max())))
    if not rows:
        raise InputError("nu", f"{nu.size} points", f"are too few below ν = {max(windows):g} for the ε "
                         "extrapolation", "run a workflow with ≥ 4 ν per decade down to 1e-15")
    centre, unc = _ensemble(rows)
    pick = int(np.argmin([abs(r.delta0 - centre) for r in rows]))
    order, coef, eps_max = fits[pick]
    x = np.linspace(0.0, eps_max, 200)
    curve = (x, sum(coef[k] * x ** k for k in range(order + 1)))   # the ε-polynomial (ν terms are tiny)
    return centre, unc, tuple(rows), curve


def _nu_reaching(curve, target, delta_smallest_nu):
    """ν at which the fitted ε-polynomial equals ``target`` (beyond the data), or None."""
    if target is None or not curve:
        return None
    x, y = curve
    below = y - target
    if not (below[0] < 0 < delta_smallest_nu - target):
        return None
    i = int(np.flatnonzero(below > 0)[0])
    eps = x[i - 1] + (x[i] - x[i - 1]) * (-below[i - 1]) / (below[i] - below[i - 1])
    if eps <= 1.0 / 600:   # beyond any representable ν: the target is (numerically) the limit itself
        return None
    w = 1.0 / eps
    return float(math.exp(-math.log(2 * math.e * w) - w))


def _naive(nu, delta):
    """How a value like 0.17 arises: fits that assume faster convergence, from 1e-9 ≤ ν ≤ 1e-6."""
    out = {}
    m = (nu >= 1e-9 * (1 - 1e-9)) & (nu <= 1e-6 * (1 + 1e-9))
    if m.sum() >= 4:
        L = np.log(1 / nu[m])
        f = linear_fit([np.ones(m.sum()), 1 / L], delta[m])
        out["linear in 1/ln(1/ν), 1e-9 ≤ ν ≤ 1e-6"] = float(f.coef[0])
        # Δ0 + bν^p (p free) by a scan over p with linear fits: the power law one would expect off 1/2
        best = None
        for p in np.linspace(0.02, 1.0, 491):
            g = linear_fit([np.ones(m.sum()), nu[m] ** p], delta[m])
            ss = float(np.sum(g.residuals ** 2))
            if best is None or ss < best[0]:
                best = (ss, float(g.coef[0]), p)
        out[f"Δ0 + bν^p (best p = {best[2]:.2f}), 1e-9 ≤ ν ≤ 1e-6"] = best[1]
    k = int(np.argmin(np.abs(np.log(nu / 1e-9))))
    if abs(math.log(nu[k] / 1e-9)) < 0.01:
        out["Δ at ν = 1e-9 (the paper's Fig. 3)"] = float(delta[k])
    out[f"Δ at the smallest ν = {nu.min():.0e}"] = float(delta[np.argmin(nu)])
    return out


def _stick_slip(nu, delta, period, nu_f, relative_error, windows):
    from ..theory import alpha, omega

    r = (float(alpha(nu_f)) - float(omega(nu_f))) ** 2
    ref = float(delta[np.argmin(nu)])
    excess = period - ref / nu
    _best, candidates = fit_ladder(nu, excess, relative_error * period, r, windows=windows)
    rows = []
    for c in candidates:
        if c.accepted:
            name = "(Δ − Δ0)/ν = " + " + ".join(t.label for t in c.terms if t.label != "1/nu")
            rows.append(ModelRow(name, c.nu_max, c.n_points, ref + c.value("1/nu"), c.error("1/nu"),
                                 c.max_chi * relative_error * float(np.max(delta))))
    centre = rows[0].delta0
    spread = max(abs(r_.delta0 - centre) for r_ in rows)
    # never below the precision of one data point: the fit cannot know Δ0 better than the engine does
    return centre, max(math.hypot(rows[0].stderr, spread), relative_error * abs(centre)), tuple(rows)


def _creep(nu, delta):
    rows = []
    for nu_max in (1e-3, 1e-6, 1e-9):
        m = nu <= nu_max * (1 + 1e-9)
        for order in (1, 2):
            if m.sum() < order + 4:
                continue
            f = linear_fit([nu[m] ** k for k in range(order + 1)], delta[m], errors=DEFAULT_RELATIVE_ERROR
                           * np.maximum(np.abs(delta[m]), 1e-300))
            rows.append(ModelRow(f"Δ0 + Σ_(1≤k≤{order}) c_k ν^k", nu_max, int(m.sum()), float(f.coef[0]),
                                 float(f.stderr[0]), float(np.max(np.abs(f.residuals)))))
    if not rows:
        raise InputError("nu_f", "creep", "has too few creep points to extrapolate",
                         "run more ν values (creep points are those where U̇ stays below ν_f)")
    centre, unc = _ensemble(rows)
    return centre, unc, tuple(rows)


def extrapolate_delta(source, law: str, nu_f: float, *, relative_error: float = DEFAULT_RELATIVE_ERROR,
                      orders=CRITICAL_ORDERS, windows=None, direct: bool = True,
                      nearest: bool = False) -> ExtrapolationResult:
    """Extrapolate Δ(ν → 0) at (law, ν_f) from the finite-ν points of ``source``.

    Parameters
    ----------
    source : xarray.Dataset, or a list of them
        Store(s) (dims law, nu_f, nu) holding ``delta`` (and ``period``) along ν at this ν_f.
    law, nu_f : str, float
        Which series. ν_f = 1/2 uses the ε-polynomial ensemble; ν_f < 1/2 the power/log expansion of
        ``period_fit`` with Δ0 free; ν_f > 1/2 a polynomial in ν over creep points.
    orders : sequence of int
        ε-polynomial orders at ν_f = 1/2.
    windows : sequence of float, optional
        ν_max of the fit windows (default: 1e-5, 1e-7, 1e-9 at 1/2; ``period_fit``'s below 1/2).
    direct : bool
        Also compute the direct limit (engine, quad) to compare with.
    nearest : bool
        Take the nearest ν_f label of the stores when ``nu_f`` is not one (``result.nu_f`` is the
        label taken); by default such a ν_f is refused, naming the nearest labels.
    """
    nu_f = match_nu_f(source, law, nu_f, nearest=nearest).label
    nu, delta, period, status = cycles_along_nu(source, law, nu_f)
    naive, reach = {}, None
    pv, psrc = paper_value(law, nu_f)
    if abs(nu_f - 0.5) < _HALF_TOL:
        regime, variable = "critical", "ε = 1/W(1/(2eν))"
        value, unc, rows, curve = _critical(nu, delta, orders, windows or CRITICAL_WINDOWS)
        naive = _naive(nu, delta)
        reach = _nu_reaching(curve, pv, float(delta[np.argmin(nu)]))
        if reach is not None:
            naive[f"ν at which Δ(ν) comes down to {pv:g} (fitted model)"] = reach
    elif nu_f < 0.5:
        from ..theory import alpha, omega
        from .period_fit import check_applies

        check_applies(nu_f, (float(alpha(nu_f)) - float(omega(nu_f))) ** 2, "stick-slip extrapolation")
        regime, variable = "stick-slip", "ν (powers ν^(j(1−r)+k), ln ν)"
        keep = status == Status.STICK_SLIP
        value, unc, rows = _stick_slip(nu[keep], delta[keep], period[keep], nu_f, relative_error,
                                       windows or DEFAULT_WINDOWS)
        curve = ()
    else:
        regime, variable = "creep", "ν"
        keep = status == Status.CREEP
        value, unc, rows = _creep(nu[keep], delta[keep])
        curve = ()
    d_direct, d_err = direct_delta0(law, nu_f) if direct else (math.nan, math.nan)
    return ExtrapolationResult(law=law, nu_f=nu_f, regime=regime, variable=variable,
                               delta0_extrapolated=float(value), uncertainty=float(unc),
                               delta0_direct=float(d_direct), delta0_direct_error=float(d_err),
                               paper_value=pv, paper_source=psrc, models=rows, nu=nu, delta=delta,
                               curve=curve, naive=naive, nu_reaching_paper=reach)
