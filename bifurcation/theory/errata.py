"""Errata of Vasconcelos, PRL 76, 4865 (1996), as read in our OCR copy, found by checking each closed
form against the exact piecewise solution (``bifurcation.theory.reference``, dps 40).

``cause`` says whether the printed paper is wrong ("paper") or only the OCR text ("OCR"); where we cannot
tell from the OCR alone it says so. tests/test_theory.py reproduces these numbers of ``evidence``: the
misses of the printed Eq. (10) at ν_f = 0.7, 0.9, 0.99 (2.32%, 5.09%, 5.79% at ν = 1e-9) and the jump
of the printed Eq. (15) middle piece at τ = 0 (ν_f − 1, −0.6 at ν_f = 0.4). The others were measured
once against the reference; the tests bound them more loosely (the dps-40 agreements to 1e-30 or
1e-35, the Eq. (13) differences through their rate of decay in ν, in tests/test_reference.py) or not
at all (the 0.075% at ν_f = 0.55).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ERRATA", "Erratum"]


@dataclass(frozen=True)
class Erratum:
    """One wrong formula: where, what is printed, what is right, and what shows it."""

    equation: str
    printed: str
    corrected: str
    evidence: str
    cause: str = "paper"

    def __post_init__(self) -> None:
        for name in ("equation", "printed", "corrected", "evidence"):
            if not getattr(self, name).strip():
                raise ValueError(f"Erratum.{name} is empty; every record needs all four texts")
        if self.cause not in ("paper", "OCR", "paper or OCR"):
            raise ValueError(f"Erratum.cause={self.cause!r}: use 'paper', 'OCR' or 'paper or OCR'")


ERRATA: tuple[Erratum, ...] = (
    Erratum(
        equation="Eq. (10)",
        printed="Δ = ν(√(e^{2αt0} − ω²) + t0 − α)",
        corrected="Δ = ν(√(e^{2αt0} − ω²) + t0 + α)",
        evidence=(
            "Exact piecewise reference (dps 40), creep cycles: the corrected form matches Δ to 2e-40 "
            "relative (ν_f = 0.7, 0.9, 0.99; ν = 1e-3, 1e-9), the printed one misses by 2.32% "
            "(ν_f = 0.7), 5.09% (0.9), 5.79% (0.99), 0.075% (0.55, ν = 1e-9). Algebra: at t0 Eq. (7) "
            "gives Δ = ν(t0 − z), z = e^{αt0} sin(ωt0)/ω, and z² + 2αz + 1 − e^{2αt0} = 0 with z < 0."
        ),
    ),
    Erratum(
        equation="Eq. (15), middle piece (0 ≤ τ ≤ τ1)",
        printed="U = ν_f[sin τ − (α + ω) cos τ + 1]",
        corrected="U = ν_f[sin τ − (α + ω) cos τ + 2α]  (= ν_f[sin τ − (α + ω) cos τ] + 1)",
        evidence=(
            "The frictionless swing Ü = 1 − U from U(0) = ν_f(α − ω) (Eq. 14), U̇(0) = ν_f. The printed "
            "form is discontinuous at τ = 0 by ν_f − 1 (−0.6 at ν_f = 0.4) and does not solve Ü = 1 − U; "
            "the corrected one is continuous with Eq. (14) at τ = 0 and with the third piece at τ1 "
            "(U = ν_f(3α + ω), U̇ = ν_f), and gives U(τ2) = Eq. (18) to 6e-41 (ν_f = 0.05…0.5). Likely a "
            "misplaced bracket: the '+1' belongs outside, since ν_f·2α = 1."
        ),
        cause="paper or OCR",
    ),
    Erratum(
        equation="Eq. (13) and the text before it",
        printed="t1 defined by U(t1) = ν_f",
        corrected="t1 defined by U̇(t1) = ν_f (the velocity reaches the kink of Eq. 12)",
        evidence=(
            "Eq. (13) is the ν → 0 root of U̇ = ν_f for Eq. (11): exact t1 − Eq. (13) = 5.4e-5, 3.1e-7, "
            "1.7e-9, 9.8e-12 at ν = 1e-6, 1e-9, 1e-12, 1e-15 (ν_f = 0.4). The OCR drops overdots "
            "throughout (also 'U ≪ ν_f', 'U(0) = U(0) = Ü(0) = 0', 'U_max ≪ ν_f')."
        ),
        cause="OCR",
    ),
    Erratum(
        equation="Eq. (9)",
        printed="(α/w) sin ωt − cos ωt + e^{−αt} = 0",
        corrected="(α/ω) sin ωt − cos ωt + e^{−αt} = 0, root t0 in (π/ω, 2π/ω)",
        evidence=(
            "With ω the root equals the exact stop time to 2e-41 relative (ν_f = 0.55…0.99); "
            "it is U̇ = 0 for Eq. (7), U̇ = ν{1 + e^{αt}[(α/ω) sin ωt − cos ωt]}."
        ),
        cause="OCR",
    ),
    Erratum(
        equation="after Eq. (5)",
        printed="V0 = F0 p mk",
        corrected="V0 = F0/√(mk)",
        evidence="Dimensions: F0/√(mk) is a velocity; the OCR lost the fraction bar and the root sign.",
        cause="OCR",
    ),
    Erratum(
        equation="Eq. (15), third piece (τ1 ≤ τ ≤ τ2)",
        printed="split over two lines: ν_f e^{α(τ−τ1)}[(3α + ω) cosh ω(τ−τ1)] / −(α + 3ω + 2/ω) sinh ω(τ−τ1)]",
        corrected="U = ν_f e^{α(τ−τ1)}[(3α + ω) cosh ω(τ−τ1) − (α + 3ω + 2/ω) sinh ω(τ−τ1)]",
        evidence=(
            "One expression: it solves Ü − 2αU̇ + U = 0 from U(τ1) = ν_f(3α + ω), U̇(τ1) = ν_f "
            "(sin τ1 = 1/α, cos τ1 = −ω/α), and its U̇ vanishes at τ2 of Eq. (17) (to 5e-41)."
        ),
        cause="OCR",
    ),
    Erratum(
        equation="text after Eq. (5)",
        printed="stick-slip motion for ν ≤ 1/2",
        corrected="stick-slip motion for ν_f ≤ 1/2",
        evidence="The transition is in ν_f (α = 1/(2ν_f) = 1); the rest of the paper says ν_f ≤ 1/2.",
        cause="paper or OCR",
    ),
)
