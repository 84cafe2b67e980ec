"""The outcome vocabulary every model, the engine and the store share (the ground floor of the package).

A grid never throws per point: each point carries a status code, stored as int8. Code 0 means "not
computed" in every store (it is the fill value of ``status``); a model's own codes start at 1. The
single block's codes (``Status``) are the shared names: other models reuse a code where its meaning is
the same (the chain's no-stop 3, back-slip 4, nonfinite 5) and name their other codes in their own
``IntEnum`` (``Model.statuses``). ``DEFAULT_T_MAX``/``DEFAULT_MAX_STEPS`` bound one run of a point.

This module imports nothing from the package, so every layer may import it (docs/models.md, "Layers").
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_T_MAX", "NOT_COMPUTED", "Status"]

#: The status of a point no run has written (the store's fill value), in every model.
NOT_COMPUTED = 0

#: Bound on the time of one cycle. The longest legitimate cycles are the creep oscillations just above
#: ν_f = 1/2 (t0 ~ 2π/ω of Eq. 9) and the creep time t1 ~ (α − ω) ln(1/ν) ≤ 40; both are far below this.
DEFAULT_T_MAX = 1.0e5
#: Bound on the Taylor steps of one cycle (a few hundred are typical).
DEFAULT_MAX_STEPS = 200_000


class Status(IntEnum):
    """Per-point outcome. ``str(Status.STICK_SLIP) == "stick-slip"``."""

    NOT_COMPUTED = NOT_COMPUTED   #: never computed (used by the store's fill value)
    #: Stopped, and the slip stays finite as ν → 0: ν_f ≤ 1/2 (the ν = 0 fixed point is an unstable
    #: node, so the block always leaves the linear regime), or ν_f > 1/2 but U̇ reached ν_f at this ν
    #: (the finite-ν rounding of the transition). Not "U̇ reached ν_f" alone: with Carlson–Langer at
    #: ν_f = 0.4 the slip is finite (Δ → 0.738) while U̇ never exceeds 0.34.
    STICK_SLIP = 1
    #: Stopped with ν_f > 1/2 and U̇ < ν_f throughout: the linear creep cycle of Eqs. (7)–(10), Δ ∝ ν.
    CREEP = 2
    NO_STOP = 3        #: did not stop before t_max or max_steps (bounded, never hangs)
    NO_STICK = 4       #: stopped, but the spring force then exceeds static friction (back-slip)
    NONFINITE = 5      #: the integrator produced a non-finite state
    #: Stopped, but U̇/ν_f went beyond the x up to which the engine checked that no Taylor step can
    #: step over the law's friction (docs/engine.md, "Friction that fades"): no value is given.
    UNRESOLVED = 7

    def __str__(self) -> str:  # "stick-slip", as users and the store see it
        return self.name.lower().replace("_", "-")
