"""State evolution laws of rate-and-state friction, one registry entry each.

Friction (normal stress 1, docs/rate-state.md):

    μ = μ0 + a ln(V/V*) + Σ_i b_i ln(V* θ_i / (c_i Dc_i)),

with c_i = 1 for the aging and slip laws and c_i = 2 for PRZ (rsfmodel's convention for the PRZ
velocity term, b ln(θ V*/(2 Dc))). The engine integrates y_i = ln θ_i and x = ln V, so each law is given
by its logarithmic rate ẏ = θ̇/θ as a function of (x, y):

- aging (Dieterich 1979):      θ̇ = 1 − Vθ/Dc                 → ẏ = e^{−y} − e^{x}/Dc
- slip (Ruina 1983):           θ̇ = −(Vθ/Dc) ln(Vθ/Dc)        → ẏ = −(e^{x}/Dc)(x + y − ln Dc)
- PRZ (Perrin, Rice, Zheng 1995): θ̇ = 1 − (Vθ/(2Dc))²        → ẏ = e^{−y} − e^{2x + y}/(4 Dc²)

At steady state θ = c Dc / V for all three, so μ_ss = μ0 + (a − Σ b_i) ln(V/V*).
Each law's ``rate`` works on heyoka expressions and on mpmath numbers alike (only exp, log and
arithmetic), so the compiled integrator, the mpmath reference and the Hopf analysis share one formula.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ...errors import InputError

__all__ = ["STATE_LAWS", "StateLaw", "resolve_state_law", "state_law_names"]


@dataclass(frozen=True)
class StateLaw:
    """One state evolution law: its name, equation, source and logarithmic rate ẏ(x, y; Dc)."""

    name: str
    equation: str
    source: str
    steady_factor: float       # c: steady state θ = c Dc / V, and the velocity term b ln(V* θ/(c Dc))
    rate: Callable             # rate(x, y, dc, exp, log) -> ẏ = θ̇/θ

    def theta_ss(self, v: float, dc: float) -> float:
        """Steady-state θ at slip velocity ``v``."""
        return self.steady_factor * dc / v


def _aging(x, y, dc, exp, log):
    return exp(-y) - exp(x) / dc


def _slip(x, y, dc, exp, log):
    return -(exp(x) / dc) * (x + y - log(dc))


def _prz(x, y, dc, exp, log):
    return exp(-y) - exp(2 * x + y) / (4 * dc * dc)


STATE_LAWS = {
    "aging": StateLaw("aging", "dθ/dt = 1 − Vθ/Dc",
                      "Dieterich, J. Geophys. Res. 84, 2161 (1979); Ruina, JGR 88, 10359 (1983)", 1.0, _aging),
    "slip": StateLaw("slip", "dθ/dt = −(Vθ/Dc) ln(Vθ/Dc)", "Ruina, J. Geophys. Res. 88, 10359 (1983)", 1.0, _slip),
    "prz": StateLaw("prz", "dθ/dt = 1 − (Vθ/(2Dc))²",
                    "Perrin, Rice, Zheng, J. Mech. Phys. Solids 43, 1461 (1995)", 2.0, _prz),
}
_ALIASES = {"dieterich": "aging", "ruina": "slip", "perrin": "prz"}


def state_law_names() -> list[str]:
    """Names of the state laws (aliases: dieterich = aging, ruina = slip, perrin = prz)."""
    return sorted(STATE_LAWS)


def resolve_state_law(name: str, argument: str = "state_law") -> StateLaw:
    """The law called ``name`` (aliases accepted), or a one-line ``InputError``. Spelled exactly, in lower case,
    as every other choice of the CLI is (--ends, --law, --precision, --suite, a workflow's model name): 'AGING'
    was accepted here while --ends FREE was refused (walk 6)."""
    key = str(name).strip()
    key = _ALIASES.get(key, key)
    if key not in STATE_LAWS:
        lower = _ALIASES.get(key.lower(), key.lower())
        problem = "is not a known state law" + (" (names are lower case)" if lower in STATE_LAWS else "")
        raise InputError(argument, name, problem,
                         f"use one of {', '.join(state_law_names())} (or dieterich, ruina, perrin)")
    return STATE_LAWS[key]
