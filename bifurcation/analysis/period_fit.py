r"""The recurrence time T(ν) against its asymptotic expansion, for ν_f < 1/2.

Why these terms (docs/physics.md, "Asymptotics at small ν"). Write V = U − νt: V̈ = −V + g((V̇ + ν)/ν_f) with
g = 1 − Φ, an O(ν) regular perturbation of the autonomous ν = 0 flow, and the stop U̇ = 0 is V̇ = −ν, so
Δ = V_stop + ν t_stop and T = Δ/ν. Near the fixed point the start is O(ν) off it in both eigen-directions
λ± = α ± ω (λ+λ− = 1). The fast mode carries the block out in t_stop = (1/λ+) ln(1/ν) + O(1); by then the
slow mode has grown to ~ ν^{1−r}, r = λ−/λ+ = (α − ω)², and it sets the transverse offset from the limit
orbit, which changes V_stop analytically. Hence

.. math::
    T - \frac{\Delta_0}{\nu} = \frac{\Delta - \Delta_0}{\nu}
    = (\alpha - \omega)\ln\frac1\nu + C_0 + K\nu^{-r} + \sum_{j,k} c_{jk}\,\nu^{j(1-r)+k-1}
      [\ln(1/\nu)]^{0,1},

with j, k ≥ 0, j + k ≥ 2 (the leading ones: K2 ν^{1−2r}, ν^{1−r}, C2 ν, ν^{2−3r}, …). The logarithms
beyond the leading one come from the ν-dependence of the eigenvalues at the shifted fixed point (a law
that is not linear near x = 0, such as Carlson–Langer: ν^{−r(ν)} = ν^{−r}(1 + O(ν ln ν))) and from
resonances λ+ = mλ− (ν_f = 0.3: m = 9, ν_f = 0.4: m = 4), which add ν^{m−1} ln(1/ν) and
ν^{m−1−r} ln(1/ν) — exponents of the same set, negligible below ν ~ 1e-5 (see ``resonance_note``).
For the piecewise-linear law the flow near the fixed point is exactly linear, so neither occurs.

K ν^{−r} dominates the logarithm at small ν (r = 0.25 at ν_f = 0.4): the paper's T = Δ/ν + t1 misses it.

The fit is linear least squares with r fixed by linear theory, weights 1/(ε_rel T) (the data are exact
to ~2e-16 relative, so the absolute error of T − Δ0/ν grows as 1/ν), and the higher terms chosen by the
data: in each window ν ≤ ν_max the smallest model of the ladder whose residuals are at the data precision.
A free 1/ν column absorbs any rounding of Δ0 (its coefficient, ``delta0_shift``, checks the direct limit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..engine import Status
from ..errors import InputError
from ._data import _number, cycles_along_nu, match_nu_f
from ._lsq import linear_fit

__all__ = ["R_MAX", "PeriodFit", "Term", "check_applies", "expansion_terms", "fit_period"]

#: Relative precision of the engine's T (and Δ) in double precision: a few 1e-16 (engine tests).
DEFAULT_RELATIVE_ERROR = 2.2e-16
#: Windows ν ≤ ν_max over which the ladder is fitted; the widest with enough points gives the answer,
#: the others the spread.
DEFAULT_WINDOWS = (1e-3, 1e-5, 1e-7)
#: Highest exponent of ν offered to the ladder (ν^3 at ν = 1e-3 is 1e-9 of the leading term).
_MAX_EXPONENT = 3.0
#: A smaller model is accepted when its √(reduced χ²) is within this factor of the best of the ladder
#: in the same window (reduced, so that a model with more terms does not win by fitting noise).
_ACCEPT = 1.2


@dataclass(frozen=True)
class Term:
    """One column ν^exponent · ln(1/ν)^log of the expansion of T − Δ0/ν, with a readable label."""

    label: str
    exponent: float
    log: bool = False

    def __call__(self, nu) -> np.ndarray:
        nu = np.asarray(nu, dtype=float)
        out = nu ** self.exponent
        return out * np.log(1 / nu) if self.log else out


#: The ladder offers the exponents j(1 − r) + k − 1 > 0 only; for r = (α − ω)² ≥ 1/2 (ν_f ≥ √2/3 ≈
#: 0.4714) the term K2 ν^{1−2r} grows as ν → 0 too, and more of them as r → 1 (exponents crowding into
#: (−1, 0)): the model lacks terms the data hold and its numbers mean nothing (fitted ln coefficients of
#: 1e3–1e7 against α − ω ≈ 0.8, measured on results/critical-point.zarr). The method does not apply there.
R_MAX = 0.5


def check_applies(nu_f: float, r: float, what: str) -> None:
    """``InputError`` where the expansion's ladder is incomplete (``R_MAX``): say so, never a number."""
    if r >= R_MAX:
        raise InputError("nu_f", nu_f, f"is where the {what} does not apply: r = (α − ω)² = {r:.4f} ≥ 1/2, so "
                         "the term ν^(1−2r) grows as ν → 0 and the expansion's ladder (exponents > 0) cannot "
                         "hold it", "use ν_f < √2/3 ≈ 0.4714, or `bifurcation extrapolate` at ν_f = 0.5")


def _power_label(j: int, k: int) -> str:
    a, b = j + k - 1, j
    if b == 0:
        return {-1: "1/nu", 0: "1", 1: "nu"}.get(a, f"nu^{a}")
    rpart = "r" if b == 1 else f"{b}r"
    return f"nu^-{rpart}" if a == 0 else f"nu^({a}-{rpart})"


def expansion_terms(r: float, *, max_exponent: float = _MAX_EXPONENT) -> list[tuple[float, str]]:
    """The exponents j(1 − r) + k − 1 > 0 of the expansion (j, k ≥ 0), sorted, with labels."""
    seen: dict[float, str] = {}
    for j in range(0, 16):
        for k in range(0, 6):
            e = j * (1 - r) + k - 1
            if 1e-12 < e <= max_exponent + 1e-12 and not any(abs(e - s) < 1e-9 for s in seen):
                seen[e] = _power_label(j, k)
    return sorted(seen.items())


def _ladder(r: float, *, power_term: bool, free_delta0: bool):
    """Models in increasing size: base terms, then the first n higher exponents, without and with logs."""
    base = [Term("ln(1/nu)", 0.0, True), Term("1", 0.0)]
    if power_term:
        base.append(Term("nu^-r", -r))
    if free_delta0:
        base.append(Term("1/nu", -1.0))
    extras = expansion_terms(r)
    models = []
    for n in range(len(extras) + 1):
        plain = [Term(lab, e) for e, lab in extras[:n]]
        models.append(base + plain)
        if n:
            models.append(base + plain + [Term(f"{lab}*ln(1/nu)" if lab != "1" else "ln(1/nu)", e, True)
                                          for e, lab in extras[:n]])
    models.sort(key=len)
    return models


@dataclass(frozen=True)
class _Candidate:
    nu_max: float
    terms: tuple
    coef: np.ndarray
    stderr: np.ndarray
    sqrt_reduced_chi2: float
    max_chi: float
    n_points: int
    accepted: bool = False

    def value(self, label: str) -> float:
        for t, c in zip(self.terms, self.coef):
            if t.label == label:
                return float(c)
        return math.nan

    def error(self, label: str) -> float:
        for t, s in zip(self.terms, self.stderr):
            if t.label == label:
                return float(s)
        return math.nan


def fit_ladder(nu, y, err, r, *, windows=DEFAULT_WINDOWS, power_term=True, free_delta0=True):
    """Fit every model of the ladder in every window; mark the accepted model of each window.

    Returns (best, candidates): best is the accepted model of the widest usable window.
    """
    nu, y, err = (np.asarray(a, dtype=float) for a in (nu, y, err))
    candidates, accepted = [], []
    for nu_max in sorted(windows, reverse=True):
        m = nu <= nu_max * (1 + 1e-9)
        n = int(m.sum())
        fits = []
        for terms in _ladder(r, power_term=power_term, free_delta0=free_delta0):
            if len(terms) > n // 2:
                break
            f = linear_fit([t(nu[m]) for t in terms], y[m], err[m])
            fits.append(_Candidate(nu_max, tuple(terms), f.coef, f.stderr, math.sqrt(f.reduced_chi2),
                                   f.max_chi, n))
        if not fits:
            continue
        floor = min(c.sqrt_reduced_chi2 for c in fits)
        pick = next(i for i, c in enumerate(fits) if c.sqrt_reduced_chi2 <= _ACCEPT * floor)
        fits[pick] = _Candidate(**{**fits[pick].__dict__, "accepted": True})
        accepted.append(fits[pick])
        candidates.extend(fits)
    if not accepted:
        raise InputError("nu", f"{nu.size} points", "are too few for the expansion (needs ≥ 8 with ν ≤ "
                         f"{max(windows):g})", "run a workflow with more ν values (≥ 4 per decade)")
    return accepted[0], candidates


@dataclass(frozen=True)
class PeriodFit:
    """The fitted expansion of T − Δ0/ν at one (law, ν_f); see the module docstring.

    ``log_coefficient`` (fitted) vs ``log_coefficient_expected`` = α − ω = 1/λ+; ``exponent_r`` = r;
    ``C0``, ``K`` (of ν^{−r}), ``K2`` (ν^{1−2r}), ``C1`` (ν ln(1/ν)), ``C2`` (ν) — NaN when the data did
    not need the term; ``terms``/``term_errors`` hold every fitted coefficient by label;
    ``delta0_shift`` the fitted correction to Δ0 (coefficient of 1/ν). ``residual_max`` is the largest
    |data − model| of T in the chosen window (units √(m/k)), ``chi_max`` the same over the data error,
    ``sqrt_reduced_chi2`` = √(χ²/(points − terms)) there (≈ 1 when the residuals are at the data error).
    """

    law: str
    nu_f: float
    alpha: float
    omega: float
    exponent_r: float
    log_coefficient: float
    log_coefficient_expected: float
    log_coefficient_uncertainty: float
    C0: float
    K: float
    K2: float
    C1: float
    C2: float
    delta0_used: float
    delta0_shift: float
    residual_max: float
    chi_max: float
    sqrt_reduced_chi2: float
    nu_max: float
    n_points: int
    model: tuple
    terms: dict
    term_errors: dict
    nu: np.ndarray = field(repr=False)
    excess: np.ndarray = field(repr=False)      # T − Δ0/ν, the fitted data
    errors: np.ndarray = field(repr=False)      # their data errors
    residuals: np.ndarray = field(repr=False)   # data − model at every point (also outside the window)
    candidates: tuple = field(repr=False, default=())
    power_term: bool = True
    resonance_note: str = ""

    @property
    def relative_deviation(self) -> float:
        """(fitted − expected)/expected for the ln(1/ν) coefficient."""
        return self.log_coefficient / self.log_coefficient_expected - 1

    def predict(self, nu) -> np.ndarray:
        """The fitted model of T − Δ0/ν (without the 1/ν shift) at ν."""
        return _expansion(self.model, self.terms, nu, shift=False)

    def summary(self) -> dict:
        """JSON-ready numbers (what `bifurcation fit-period --json` prints)."""
        return {
            "law": self.law, "nu_f": self.nu_f, "log_coefficient": self.log_coefficient,
            "log_coefficient_expected": self.log_coefficient_expected,
            "log_coefficient_uncertainty": self.log_coefficient_uncertainty,
            "relative_deviation": self.relative_deviation, "exponent_r": self.exponent_r,
            "C0": self.C0, "K": self.K, "K2": self.K2, "C1": self.C1, "C2": self.C2,
            "delta0_used": self.delta0_used, "delta0_shift": self.delta0_shift,
            "residual_max": self.residual_max, "chi_max": self.chi_max,
            "sqrt_reduced_chi2": self.sqrt_reduced_chi2,
            "nu_max": self.nu_max, "n_points": self.n_points, "model": [t.label for t in self.model],
            "terms": dict(self.terms), "term_errors": dict(self.term_errors),
            "resonance_note": self.resonance_note,
        }


def _expansion(model, terms: dict, nu, *, shift: bool) -> np.ndarray:
    """Σ coefficient · term over ``model`` at ν; the 1/ν column (the Δ0 shift) only if ``shift``.

    Summed in the model's order either way, so the residuals are those of the fit to the last bit.
    """
    nu = np.asarray(nu, dtype=float)
    out = np.zeros_like(nu)
    for t in model:
        if shift or t.label != "1/nu":
            out = out + terms[t.label] * t(nu)
    return out


def _resonance_note(alpha: float, omega: float) -> str:
    ratio = (alpha + omega) ** 2     # λ+/λ−
    m = round(ratio)
    if m >= 2 and abs(ratio - m) < 1e-9:
        return (f"λ+/λ− = {m} (resonance): adds ν^{m - 1}·ln(1/ν) and ν^({m - 1}−r)·ln(1/ν) terms "
                f"(size ≤ {1e-5 ** (m - 1 - (alpha - omega) ** 2) * math.log(1e5):.1e} relative to data "
                "at ν = 1e-5); they are in the ladder's log variants when the data ask for them")
    return ""


def direct_delta0(law: str, nu_f: float) -> tuple[float, float]:
    """Δ0 by the engine's direct ν → 0 limit in quad precision, and |quad − double| as its error."""
    from ..engine import limit

    quad = float(limit(law, nu_f=nu_f, precision="quad").delta0)
    double = float(limit(law, nu_f=nu_f, precision="double").delta0)
    return quad, abs(quad - double)


def fit_period(source, law: str, nu_f: float, *, delta0: float | None = None,
               relative_error: float = DEFAULT_RELATIVE_ERROR, windows=DEFAULT_WINDOWS,
               power_term: bool = True, free_delta0: bool = True, nearest: bool = False) -> PeriodFit:
    """Fit T(ν) − Δ0/ν at fixed ν_f < 1/2 to its asymptotic expansion (module docstring).

    Parameters
    ----------
    source : xarray.Dataset, or a list of them
        Store(s) with dims (law, nu_f, nu) and fields ``period``/``delta`` (or ``slip_dataset``).
    law, nu_f : str, float
        Which series (ν_f < 1/2; a label of the stores within a relative 1e-12, or with ``nearest``
        the nearest label, which ``result.nu_f`` then holds).
    delta0 : float, optional
        Δ0(ν_f); default the engine's direct limit (quad precision).
    relative_error : float
        Relative error of the data T, used as weights.
    windows : sequence of float
        ν_max of the fit windows.
    power_term : bool
        Include K ν^{−r}. False shows what the expansion is without it (it fails: see the tests).
    free_delta0 : bool
        Fit a 1/ν column too (absorbs rounding of Δ0).
    """
    nu_f = _number("nu_f", nu_f)
    if not nu_f > 0:
        raise InputError("nu_f", nu_f, "is not > 0", "give a friction velocity 0 < nu_f < 0.5")
    if not (0 < nu_f < 0.5):
        raise InputError("nu_f", nu_f, "is not below 1/2: the expansion of T is for the stick-slip side "
                         "(at 1/2 the exponents merge)", "use 0 < nu_f < 0.5, or `bifurcation extrapolate` "
                         "at nu_f = 0.5")
    from ..theory import alpha, omega

    nu_f = match_nu_f(source, law, nu_f, nearest=nearest).label
    if not nu_f < 0.5:
        raise InputError("nu_f", nu_f, "(the nearest label) is not below 1/2", "give a ν_f label below 0.5")
    check_applies(nu_f, (float(alpha(nu_f)) - float(omega(nu_f))) ** 2, "recurrence-time expansion")
    nu, _, period, status = cycles_along_nu(source, law, nu_f)
    stick = status == Status.STICK_SLIP
    nu, period = nu[stick], period[stick]
    if delta0 is None:
        delta0 = direct_delta0(law, nu_f)[0]
    a, w = float(alpha(nu_f)), float(omega(nu_f))
    r = (a - w) ** 2
    excess = period - delta0 / nu
    errors = relative_error * period
    best, candidates = fit_ladder(nu, excess, errors, r, windows=windows, power_term=power_term,
                                  free_delta0=free_delta0)
    accepted = [c for c in candidates if c.accepted]
    log_values = [c.value("ln(1/nu)") for c in accepted]
    spread = max(abs(v - best.value("ln(1/nu)")) for v in log_values)
    terms = {t.label: float(c) for t, c in zip(best.terms, best.coef)}
    model = best.terms
    residuals = excess - _expansion(model, terms, nu, shift=True)
    inside = nu <= best.nu_max * (1 + 1e-9)
    return PeriodFit(
        law=law, nu_f=nu_f, alpha=a, omega=w, exponent_r=r,
        log_coefficient=best.value("ln(1/nu)"), log_coefficient_expected=a - w,
        log_coefficient_uncertainty=math.hypot(best.error("ln(1/nu)"), spread),
        C0=best.value("1"), K=best.value("nu^-r"), K2=best.value("nu^(1-2r)"),
        C1=best.value("nu*ln(1/nu)"), C2=best.value("nu"),
        delta0_used=float(delta0), delta0_shift=best.value("1/nu") if free_delta0 else 0.0,
        residual_max=float(np.max(np.abs(residuals[inside]))), chi_max=best.max_chi,
        sqrt_reduced_chi2=best.sqrt_reduced_chi2,
        nu_max=best.nu_max, n_points=best.n_points, model=model, terms=terms,
        term_errors={t.label: float(e) for t, e in zip(best.terms, best.stderr)},
        nu=nu, excess=excess, errors=errors, residuals=residuals, candidates=tuple(candidates),
        power_term=power_term, resonance_note=_resonance_note(a, w),
    )
